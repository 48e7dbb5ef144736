// Covariance sanity check: finiteness, symmetry, positive definiteness.
#include "geometry/covariance_check.h"

#include <Eigen/Eigenvalues>

namespace fleetloc::geometry {

std::string CovarianceProblem(const Eigen::Matrix3d& c) {
  if (!c.allFinite()) return "covariance is not finite";
  if ((c - c.transpose()).cwiseAbs().maxCoeff() > 1e-9 * c.cwiseAbs().maxCoeff()) {
    return "covariance is not symmetric";
  }
  const double smallest =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c).eigenvalues().minCoeff();
  if (!(smallest > 0)) return "covariance is not positive definite (zero, negative or singular)";
  return "";
}

}  // namespace fleetloc::geometry
