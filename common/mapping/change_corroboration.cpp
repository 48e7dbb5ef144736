// Cross-vehicle agreement on changed floor blocks.
#include "mapping/change_corroboration.h"

#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <set>

#include "mapping/change_detection.h"

namespace fleetloc::mapping {
namespace {

// Camera_ground point of pixel index (j, i) of an image of `size` (docs/formats.md).
Eigen::Vector2d GroundOf(cv::Size size, double j, double i, double res) {
  return {-(i + 0.5 - size.height / 2.0) * res, -(j + 0.5 - size.width / 2.0) * res};
}

// Pixel index of camera_ground point `ab` in an image of `size`.
cv::Point2f PixelOf(cv::Size size, const Eigen::Vector2d& ab, double res) {
  return {static_cast<float>(size.width / 2.0 - ab.y() / res - 0.5),
          static_cast<float>(size.height / 2.0 - ab.x() / res - 0.5)};
}

bool Overlap(const ObservedChange& a, const ObservedChange& b, double res) {
  const double reach =
      (std::hypot(a.image->cols, a.image->rows) + std::hypot(b.image->cols, b.image->rows)) / 2;
  return std::hypot(a.pose.x - b.pose.x, a.pose.y - b.pose.y) / res < reach;
}

// Indices of `mine`'s changed blocks that `other` (rendered in its grid) shows alike.
std::set<int> AgreeingBlocks(const ObservedChange& mine, const ObservedChange& other, double res,
                             const CorroborationOptions& o) {
  const cv::Matx23d m =
      PatchToPatch(mine.image->size(), mine.pose, other.image->size(), other.pose, res);
  cv::Mat rendered;
  cv::warpAffine(*other.image, rendered, m, mine.image->size(),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, 0);
  std::set<int> agreeing;
  for (size_t k = 0; k < mine.changed_blocks.size(); ++k) {
    const cv::Rect& r = mine.changed_blocks[k];
    ChangeOptions block;
    block.block_px = r.width;
    const std::vector<BlockComparison> c = CompareBlocks((*mine.image)(r), rendered(r), block);
    if (!c.empty() && c[0].mapped && c[0].ncc >= o.agree_ncc) agreeing.insert(static_cast<int>(k));
  }
  return agreeing;
}

}  // namespace

cv::Matx23d PatchToPatch(cv::Size from_size, const geometry::Pose2& from, cv::Size to_size,
                         const geometry::Pose2& to, double res) {
  const geometry::Pose2 relative = geometry::Between(to, from);  // from's frame in to's
  auto map = [&](double j, double i) {
    return PixelOf(to_size, relative * GroundOf(from_size, j, i, res), res);
  };
  const cv::Point2f src[3] = {{0, 0}, {1000, 0}, {0, 1000}};
  const cv::Point2f dst[3] = {map(0, 0), map(1000, 0), map(0, 1000)};
  return cv::Matx23d(cv::getAffineTransform(src, dst));
}

std::vector<bool> CorroborateChanges(const std::vector<ObservedChange>& changes, double res,
                                     const CorroborationOptions& o) {
  std::vector<bool> corroborated(changes.size(), true);
  if (o.min_vehicles <= 1) return corroborated;
  for (size_t i = 0; i < changes.size(); ++i) {
    const ObservedChange& mine = changes[i];
    if (mine.changed_blocks.empty()) continue;
    std::map<int, std::set<std::string>> witnesses;  // changed block → other vehicles agreeing
    for (size_t j = 0; j < changes.size(); ++j) {
      const ObservedChange& other = changes[j];
      if (other.vehicle_id == mine.vehicle_id || !Overlap(mine, other, res)) continue;
      for (int block : AgreeingBlocks(mine, other, res, o))
        witnesses[block].insert(other.vehicle_id);
    }
    int confirmed = 0;
    for (const auto& [block, vehicles] : witnesses) {
      if (static_cast<int>(vehicles.size()) + 1 >= o.min_vehicles) ++confirmed;
    }
    corroborated[i] =
        confirmed >= o.min_confirmed_fraction * static_cast<double>(mine.changed_blocks.size());
  }
  return corroborated;
}

}  // namespace fleetloc::mapping
