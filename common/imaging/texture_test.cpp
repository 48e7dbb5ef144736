// Tests for the texture score against a direct computation and on 1-D versus 2-D texture.
#include "imaging/texture.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::imaging {
namespace {

cv::Mat Gravel() {
  cv::Mat g = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(g.empty());
  return g;
}

// Direct definition at one pixel: mean over the window of [gx², gxgy; gxgy, gy²], λmin.
double DirectScore(const cv::Mat& gray, int x, int y, int window) {
  cv::Mat f;
  gray.convertTo(f, CV_64F);
  auto at = [&](int xx, int yy) { return f.at<double>(yy, xx); };
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  const int h = window / 2;
  for (int yy = y - h; yy <= y + h; ++yy) {
    for (int xx = x - h; xx <= x + h; ++xx) {
      const double gx = (at(xx + 1, yy - 1) + 2 * at(xx + 1, yy) + at(xx + 1, yy + 1) -
                         at(xx - 1, yy - 1) - 2 * at(xx - 1, yy) - at(xx - 1, yy + 1)) /
                        8.0;
      const double gy = (at(xx - 1, yy + 1) + 2 * at(xx, yy + 1) + at(xx + 1, yy + 1) -
                         at(xx - 1, yy - 1) - 2 * at(xx, yy - 1) - at(xx + 1, yy - 1)) /
                        8.0;
      m += Eigen::Vector2d(gx, gy) * Eigen::Vector2d(gx, gy).transpose();
    }
  }
  m /= window * window;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(m).eigenvalues().minCoeff();
}

TEST(TextureScore, EqualsSmallestEigenvalueOfStructureMatrixOnRealPhoto) {
  const cv::Mat gravel = Gravel();
  const cv::Mat score = TextureScore(gravel, 7);
  for (const cv::Point p : {cv::Point(100, 100), cv::Point(257, 31), cv::Point(400, 333)}) {
    const double direct = DirectScore(gravel, p.x, p.y, 7);
    EXPECT_NEAR(score.at<float>(p), direct, 1e-3 * direct + 1e-3) << p;
  }
}

TEST(TextureScore, StripesScoreNearZeroWhileRealTextureScoresHigh) {
  cv::Mat stripes(128, 128, CV_8UC1);
  for (int y = 0; y < stripes.rows; ++y)
    for (int x = 0; x < stripes.cols; ++x)
      stripes.at<uchar>(y, x) = static_cast<uchar>(128 + 100 * std::sin(0.4 * (x + 0.5 * y)));
  const double stripe_score = cv::mean(TextureScore(stripes, 7)(cv::Rect(8, 8, 112, 112)))[0];
  const double gravel_score = cv::mean(TextureScore(Gravel(), 7))[0];
  EXPECT_LT(stripe_score, 0.5);  // one-dimensional texture: one eigenvalue vanishes
  EXPECT_GT(gravel_score, 20.0 * (stripe_score + 1.0));
}

}  // namespace
}  // namespace fleetloc::imaging
