// Covariance check: only finite, symmetric, positive definite matrices pass, each failure named.
#include "geometry/covariance_check.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::geometry {
namespace {

TEST(CovarianceProblem, AcceptsOnlyFiniteSymmetricPositiveDefiniteMatrices) {
  const Eigen::Matrix3d good = Eigen::Vector3d(1e-8, 2e-8, 1e-6).asDiagonal();
  EXPECT_EQ(CovarianceProblem(good), "");
  Eigen::Matrix3d correlated = good;
  correlated(0, 1) = correlated(1, 0) = 0.9e-8;
  EXPECT_EQ(CovarianceProblem(correlated), "");
  Eigen::Matrix3d asymmetric = good;
  asymmetric(0, 1) = 5e-9;
  Eigen::Matrix3d indefinite = good;
  indefinite(0, 1) = indefinite(1, 0) = 3e-8;
  Eigen::Matrix3d nan = good;
  nan(2, 2) = std::nan("");
  EXPECT_NE(CovarianceProblem(Eigen::Matrix3d::Zero()).find("positive definite"),
            std::string::npos);
  EXPECT_NE(CovarianceProblem(-good).find("positive definite"), std::string::npos);
  EXPECT_NE(CovarianceProblem(indefinite).find("positive definite"), std::string::npos);
  EXPECT_NE(CovarianceProblem(asymmetric).find("symmetric"), std::string::npos);
  EXPECT_NE(CovarianceProblem(nan).find("finite"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::geometry
