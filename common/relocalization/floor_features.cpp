// ORB features bucketed on a grid (see floor_features.h).
#include "relocalization/floor_features.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

namespace fleetloc::relocalization {
namespace {

// The usable pixels: `valid` shrunk by the descriptor's reach, and the image border removed.
cv::Mat UsableMask(const cv::Mat& valid, cv::Size size, int reach_px) {
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  const cv::Rect inner(reach_px, reach_px, size.width - 2 * reach_px, size.height - 2 * reach_px);
  if (inner.width <= 0 || inner.height <= 0) return mask;
  mask(inner).setTo(255);
  if (valid.empty()) return mask;
  cv::Mat eroded;
  cv::erode(
      valid != 0, eroded,
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * reach_px + 1, 2 * reach_px + 1)));
  return mask & eroded;
}

// Keeps the strongest `per_cell` keypoints of each grid bucket among those inside `keep`.
std::vector<cv::KeyPoint> BucketStrongest(std::vector<cv::KeyPoint> keypoints, const cv::Rect& keep,
                                          int cell_px, int per_cell) {
  std::sort(keypoints.begin(), keypoints.end(),
            [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  std::map<std::pair<int, int>, int> taken;
  std::vector<cv::KeyPoint> kept;
  for (const cv::KeyPoint& kp : keypoints) {
    if (!keep.contains(cv::Point(static_cast<int>(kp.pt.x), static_cast<int>(kp.pt.y)))) continue;
    const auto cell = std::make_pair((static_cast<int>(kp.pt.x) - keep.x) / cell_px,
                                     (static_cast<int>(kp.pt.y) - keep.y) / cell_px);
    if (taken[cell]++ < per_cell) kept.push_back(kp);
  }
  return kept;
}

}  // namespace

Status Validate(const FloorFeatureOptions& options) {
  if (options.level < 0 || options.level > 4) return InvalidInput("features: level must be 0..4");
  if (options.cell_px < 8) return InvalidInput("features: cell_px must be >= 8");
  if (options.features_per_cell < 1)
    return InvalidInput("features: features_per_cell must be >= 1");
  if (options.fast_threshold < 1 || options.fast_threshold > 100)
    return InvalidInput("features: fast_threshold must be 1..100");
  if (options.patch_size_px < 15 || options.patch_size_px % 2 == 0)
    return InvalidInput("features: patch_size_px must be odd and >= 15");
  if (!(options.blur_sigma_px >= 0.0 && options.blur_sigma_px <= 5.0))
    return InvalidInput("features: blur_sigma_px must be in [0, 5]");
  return Status::Ok();
}

int FeatureMarginPx(const FloorFeatureOptions& options) {
  // ORB reads a patch of patch_size around each keypoint, rotated: half its diagonal.
  const int reach = static_cast<int>(std::ceil(options.patch_size_px * 0.7072)) + 1;
  return reach + static_cast<int>(std::ceil(3.0 * options.blur_sigma_px));
}

FloorFeatures DetectFloorFeatures(const cv::Mat& image, const cv::Mat& valid, const cv::Rect& keep,
                                  const FloorFeatureOptions& options) {
  FLEETLOC_CHECK(image.type() == CV_8UC1);
  FLEETLOC_CHECK(valid.empty() || (valid.size() == image.size() && valid.type() == CV_8UC1));
  cv::Mat smoothed = image;
  if (options.blur_sigma_px > 0.0)
    cv::GaussianBlur(image, smoothed, cv::Size(), options.blur_sigma_px);
  const int reach =
      FeatureMarginPx(options) - static_cast<int>(std::ceil(3.0 * options.blur_sigma_px));
  const cv::Mat mask = UsableMask(valid, image.size(), reach);
  const int cells = (keep.width / options.cell_px + 1) * (keep.height / options.cell_px + 1);
  cv::Ptr<cv::ORB> orb =
      cv::ORB::create(cells * options.features_per_cell * 8, 1.2f, 1, reach, 0, 2,
                      cv::ORB::HARRIS_SCORE, options.patch_size_px, options.fast_threshold);
  std::vector<cv::KeyPoint> keypoints;
  orb->detect(smoothed, keypoints, mask);
  keypoints =
      BucketStrongest(std::move(keypoints), keep, options.cell_px, options.features_per_cell);
  FloorFeatures features;
  if (keypoints.empty()) return features;
  orb->compute(smoothed, keypoints, features.descriptors);
  for (const cv::KeyPoint& kp : keypoints) {
    features.points_px.emplace_back(kp.pt.x + 0.5, kp.pt.y + 0.5);
    features.angles_rad.push_back(kp.angle * M_PI / 180.0);
    features.responses.push_back(kp.response);
  }
  return features;
}

}  // namespace fleetloc::relocalization
