// Tests for area-sensor sampling: it equals the mean of k × k exact bilinear samples per pixel and
// agrees with the warp-larger-then-average rendering it replaces.
#include "sim/area_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::sim {
namespace {

cv::Mat Gravel() {
  cv::Mat image = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(image.empty());
  return image;
}

// Rotation by `angle` and scale about source point (250.3, 240.7) for a 96×64 output.
Eigen::Matrix<double, 2, 3> RigidMap(double angle, double scale) {
  Eigen::Matrix<double, 2, 3> map;
  const double c = scale * std::cos(angle), s = scale * std::sin(angle);
  map << c, -s, 0.0, s, c, 0.0;
  map.col(2) = Eigen::Vector2d(250.3, 240.7) - map.leftCols<2>() * Eigen::Vector2d(48, 32);
  return map;
}

// Bilinear value at continuous coordinates (pixel centres at i + 0.5), in double precision.
double Bilinear(const cv::Mat& image, const Eigen::Vector2d& p) {
  const double x = p.x() - 0.5, y = p.y() - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto at = [&](int i, int j) { return static_cast<double>(image.at<std::uint8_t>(j, i)); };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

class AreaSamplerCases : public ::testing::TestWithParam<std::tuple<int, double, double>> {};

TEST_P(AreaSamplerCases, PixelIsTheMeanOfExactBilinearSubSamples) {
  const auto [k, angle, scale] = GetParam();
  const cv::Mat gravel = Gravel();
  const Eigen::Matrix<double, 2, 3> map = RigidMap(angle, scale);
  const AreaSampler sampler(map, k);
  const cv::Size size(96, 64);
  const cv::Rect rect = sampler.SourceRect(size);
  const cv::Mat out = sampler.Sample(gravel(rect).clone(), rect, size);
  double sum_abs = 0.0, max_abs = 0.0;
  for (int j = 0; j < size.height; ++j) {
    for (int i = 0; i < size.width; ++i) {
      double mean = 0.0;
      for (int b = 0; b < k; ++b) {
        for (int a = 0; a < k; ++a) {
          mean += Bilinear(gravel, map * Eigen::Vector3d(i + (a + 0.5) / k, j + (b + 0.5) / k, 1));
        }
      }
      const double error = std::abs(out.at<float>(j, i) - mean / (k * k));
      sum_abs += error;
      max_abs = std::max(max_abs, error);
    }
  }
  // Only the 1/64-pixel phase tables differ from exact: ≤ 1/128 px times the local gradient.
  EXPECT_LT(sum_abs / size.area(), 0.15);
  EXPECT_LT(max_abs, 1.5);
}

INSTANTIATE_TEST_SUITE_P(
    SupersampleAngleScale, AreaSamplerCases,
    ::testing::Values(std::make_tuple(1, 0.0, 1.0), std::make_tuple(1, 0.7, 1.0),
                      std::make_tuple(3, 0.0, 1.0), std::make_tuple(3, 2.3, 1.0),
                      std::make_tuple(3, -0.8, 1.7), std::make_tuple(4, 0.4, 0.6)));

TEST(AreaSampler, AgreesWithWarpingLargerAndAveragingBlocks) {
  const cv::Mat gravel = Gravel();
  const Eigen::Matrix<double, 2, 3> map = RigidMap(0.9, 1.0);
  const int k = 3;
  const cv::Size size(96, 64);
  const AreaSampler sampler(map, k);
  const cv::Rect rect = sampler.SourceRect(size);
  const cv::Mat ours = sampler.Sample(gravel(rect).clone(), rect, size);
  // Fine pixel index q ↦ continuous (q + 0.5) / k ↦ source continuous ↦ source index (- 0.5).
  cv::Mat warp(2, 3, CV_64FC1);
  for (int r = 0; r < 2; ++r) {
    warp.at<double>(r, 0) = map(r, 0) / k;
    warp.at<double>(r, 1) = map(r, 1) / k;
    warp.at<double>(r, 2) = map(r, 2) + (map(r, 0) + map(r, 1)) * 0.5 / k - 0.5;
  }
  cv::Mat source, fine, reference;
  gravel.convertTo(source, CV_32FC1);
  cv::warpAffine(source, fine, warp, size * k, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP);
  cv::resize(fine, reference, size, 0, 0, cv::INTER_AREA);
  // OpenCV rounds sample positions to 1/32 pixel: agreement to a fraction of a grey level.
  EXPECT_LT(cv::norm(ours, reference, cv::NORM_L1) / size.area(), 0.3);
}

}  // namespace
}  // namespace fleetloc::sim
