// Is a 3×3 pose covariance usable as one? Received covariances (a vehicle's patch, a file) are
// checked before anything trusts or inverts them.
#pragma once

#include <Eigen/Core>
#include <string>

namespace fleetloc::geometry {

// "" when `covariance` (x, y, theta) is finite, symmetric (to rounding) and positive definite;
// else what is wrong with it (not finite, not symmetric, zero, negative or singular).
std::string CovarianceProblem(const Eigen::Matrix3d& covariance);

}  // namespace fleetloc::geometry
