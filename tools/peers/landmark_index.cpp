// Landmark grid and pair-distance table (see landmark_index.h).
#include "peers/landmark_index.h"

#include <algorithm>
#include <cmath>

namespace fleetloc::peers {

LandmarkGrid::LandmarkGrid(std::span<const Eigen::Vector2d> landmarks, double reach_m)
    : landmarks_(landmarks), reach2_(reach_m * reach_m) {
  Eigen::Vector2d low = landmarks.front(), high = low;
  for (const Eigen::Vector2d& m : landmarks) {
    low = low.cwiseMin(m);
    high = high.cwiseMax(m);
  }
  const Eigen::Vector2d extent = high - low;
  const double area = std::max(extent.x() * extent.y(), reach_m * reach_m);
  cell_m_ = std::max(reach_m, std::sqrt(area / (16.0 * static_cast<double>(landmarks.size()))));
  origin_ = low;
  columns_ = static_cast<int>(extent.x() / cell_m_) + 1;
  rows_ = static_cast<int>(extent.y() / cell_m_) + 1;
  // Counting sort of the landmarks by cell.
  std::vector<int> cell_of(landmarks.size());
  first_.assign(static_cast<std::size_t>(columns_ * rows_) + 1, 0);
  for (std::size_t m = 0; m < landmarks.size(); ++m) {
    const Eigen::Vector2d c = (landmarks[m] - origin_) / cell_m_;
    cell_of[m] = std::min(static_cast<int>(c.y()), rows_ - 1) * columns_ +
                 std::min(static_cast<int>(c.x()), columns_ - 1);
    ++first_[cell_of[m] + 1];
  }
  for (std::size_t c = 1; c < first_.size(); ++c) first_[c] += first_[c - 1];
  members_.resize(landmarks.size());
  std::vector<int> fill(first_.begin(), first_.end() - 1);
  for (std::size_t m = 0; m < landmarks.size(); ++m)
    members_[fill[cell_of[m]]++] = static_cast<int>(m);
}

int LandmarkGrid::NearestWithin(const Eigen::Vector2d& xy) const {
  const Eigen::Vector2d c = (xy - origin_) / cell_m_;
  if (!(c.x() > -1.0 && c.y() > -1.0 && c.x() < columns_ + 1.0 && c.y() < rows_ + 1.0)) return -1;
  const int cx = static_cast<int>(std::floor(c.x())), cy = static_cast<int>(std::floor(c.y()));
  int best = -1;
  double best_d2 = reach2_;
  // Cells are at least `reach` wide: the 3 × 3 block around xy's cell holds every candidate.
  for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, rows_ - 1); ++y) {
    for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, columns_ - 1); ++x) {
      const int cell = y * columns_ + x;
      for (int k = first_[cell]; k < first_[cell + 1]; ++k) {
        const double d2 = (landmarks_[members_[k]] - xy).squaredNorm();
        if (d2 <= best_d2) {
          best_d2 = d2;
          best = members_[k];
        }
      }
    }
  }
  return best;
}

LandmarkPairTable::LandmarkPairTable(std::span<const Eigen::Vector2d> landmarks) {
  for (std::size_t a = 0; a < landmarks.size(); ++a)
    for (std::size_t b = a + 1; b < landmarks.size(); ++b)
      pairs_.push_back(
          {(landmarks[a] - landmarks[b]).norm(), static_cast<int>(a), static_cast<int>(b)});
  std::sort(pairs_.begin(), pairs_.end(), [](const LandmarkPair& l, const LandmarkPair& r) {
    return l.distance_m < r.distance_m;
  });
}

std::span<const LandmarkPair> LandmarkPairTable::Matching(double distance_m,
                                                          double tolerance_m) const {
  const auto below = [](const LandmarkPair& p, double d) { return p.distance_m < d; };
  const auto above = [](double d, const LandmarkPair& p) { return d < p.distance_m; };
  const auto begin =
      std::lower_bound(pairs_.begin(), pairs_.end(), distance_m - tolerance_m, below);
  const auto end = std::upper_bound(begin, pairs_.end(), distance_m + tolerance_m, above);
  return {begin, end};
}

}  // namespace fleetloc::peers
