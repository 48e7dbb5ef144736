// Multi-frame dense place search: shifted, summed heading sweeps (see trajectory_place_search.h).
#include "relocalization/trajectory_place_search.h"

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace fleetloc::relocalization {
TrajectoryPlaceSearch::TrajectoryPlaceSearch(const DensePlaceSearch* dense,
                                             const geometry::CameraModel& camera, SweepLevel level)
    : dense_(dense),
      level_(level),
      centre_ground_(camera.PixelToGround({0.5 * camera.width_px, 0.5 * camera.height_px})) {}

std::size_t TrajectoryPlaceSearch::MemoryBytes(const DensePlaceSearch& dense, SweepLevel level) {
  return static_cast<std::size_t>(dense.heading_steps(level)) * dense.sweep_size(level).area() *
         sizeof(float);
}

void TrajectoryPlaceSearch::Reset() {
  sum_.clear();
  frames_.clear();
  motion_.clear();
}

double TrajectoryPlaceSearch::TravelTo(const geometry::Pose2& camera_in_odom) const {
  if (frames_.empty()) return 0.0;
  return std::hypot(camera_in_odom.x - first_in_odom_.x, camera_in_odom.y - first_in_odom_.y);
}

void TrajectoryPlaceSearch::Add(const cv::Mat& frame, const geometry::Pose2& camera_in_odom) {
  Begin(frame, camera_in_odom);
  SweepNewest();
}

void TrajectoryPlaceSearch::SweepNewest() {
  dense_->Sweep(
      frames_.back(), [&](const DensePlaceSearch::SweepMap& map) { Accumulate(map); }, level_);
}

void TrajectoryPlaceSearch::Begin(const cv::Mat& frame, const geometry::Pose2& camera_in_odom) {
  if (frames_.empty()) {
    first_in_odom_ = camera_in_odom;
    sum_.resize(dense_->heading_steps(level_));
    for (cv::Mat& m : sum_) m = cv::Mat::zeros(dense_->sweep_size(level_), CV_32F);
  }
  const geometry::Pose2 motion = first_in_odom_.Inverse() * camera_in_odom;
  // This frame's heading step for the first frame's step k is k + turn.
  turn_ = static_cast<int>(std::lround(motion.theta * sum_.size() / (2 * M_PI)));
  offset_ = motion * centre_ground_ - centre_ground_;
  frames_.push_back(frame.clone());
  motion_.push_back(motion);
}

void TrajectoryPlaceSearch::Accumulate(const DensePlaceSearch::SweepMap& map) {
  const int steps = static_cast<int>(sum_.size());
  const int k = ((map.k - turn_) % steps + steps) % steps;
  // The first frame's maps need no shift (warpAffine by zero would copy them exactly).
  if (offset_.isZero()) {
    sum_[k] += map.scores;
    return;
  }
  const Eigen::Vector2d d = Eigen::Rotation2Dd(dense_->sweep_heading_rad(k, level_)) * offset_;
  sum_[k] += ShiftedScores(map.scores, d, dense_->sweep_resolution_m(level_));
}

DensePeak TrajectoryPlaceSearch::Alternative(const geometry::Pose2& first) const {
  return dense_->Alternative(frames_, motion_, first);
}

DensePeak TrajectoryPlaceSearch::MeanRefined(const DensePlaceSearch& search,
                                             const geometry::Pose2& first) const {
  DensePeak newest{first, 0.0};
  for (std::size_t j = 0; j < frames_.size(); ++j) {
    const DensePeak r = search.Refine(frames_[j], {first * motion_[j], 0.0});
    newest.correlation += std::max(0.0, r.correlation) / static_cast<double>(frames_.size());
    if (j + 1 == frames_.size()) newest.camera_in_map = r.camera_in_map;
  }
  return newest;
}

// The alternative's sums place every frame by the odometry alone; both places are then refined
// frame by frame, as the trajectory's own place is, so that the odometry's drift costs neither
// more than the other (measured: a twin summing to 0.25 refined to the place's own 0.40).
TrajectoryPlaceSearch::OwnAndTwin TrajectoryPlaceSearch::MeasureTwin(
    const DensePlaceSearch& search, const geometry::Pose2& newest) const {
  OwnAndTwin out;
  if (frames_.empty()) return out;
  const geometry::Pose2 to_first = motion_.back().Inverse();
  out.own = MeanRefined(search, newest * to_first).correlation;
  const DensePeak twin = search.Alternative(frames_, motion_, newest * to_first);
  out.twin =
      std::max(twin.correlation, MeanRefined(search, twin.camera_in_map * to_first).correlation);
  return out;
}

std::vector<DensePeak> TrajectoryPlaceSearch::Search() const {
  if (frames_.empty()) return {};
  std::vector<DensePeak> coarse;  // the first frame's camera poses
  for (int k = 0; k < static_cast<int>(sum_.size()); ++k) {
    cv::Mat scores = sum_[k] / static_cast<double>(frames_.size());
    const int suppress_px =
        std::max(2, static_cast<int>(std::lround(0.25 * dense_->separation_m() /
                                                 dense_->sweep_resolution_m(level_))));
    dense_->AppendCoarsePeaks(scores, dense_->sweep_heading_rad(k, level_), suppress_px, &coarse,
                              level_);
  }
  std::vector<DensePeak> refined;
  DensePeak best_first{{}, -1.0};  // the first frame's pose of the best refined candidate
  for (const DensePeak& first : dense_->DistinctBest(coarse, dense_->options().coarse_peaks)) {
    const DensePeak newest = MeanRefined(*dense_, first.camera_in_map);
    if (newest.correlation > best_first.correlation)
      best_first = {first.camera_in_map, newest.correlation};
    refined.push_back(newest);
  }
  // The coarse sums are near noise on weak floors: the best's twin may not be among them.
  if (best_first.correlation >= 0) refined.push_back(Alternative(best_first.camera_in_map));
  return dense_->DistinctBest(std::move(refined), dense_->options().max_peaks);
}

}  // namespace fleetloc::relocalization
