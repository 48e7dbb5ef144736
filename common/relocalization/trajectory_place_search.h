// Multi-frame dense place search (issue 17): where one frame is not distinctive enough (dust over
// a weak floor leaves the true peak at noise level), a short trajectory is. Each frame's coarse
// heading sweep (DensePlaceSearch::Sweep) is shifted by the odometry between it and the first
// frame — for every heading of the first frame, the frame's own heading is that plus the odometry's
// turn, its centre the first frame's centre plus the rotated odometry offset — and summed, so the
// true place adds up while noise averages out. The best summed peaks are refined frame by frame
// one level finer at the poses the odometry predicts; their mean correlation ranks them. The
// answer is the newest frame's camera pose, for the caller to gate and verify. Pure.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "relocalization/dense_place_search.h"

namespace fleetloc::relocalization {

class TrajectoryPlaceSearch {
 public:
  using SweepLevel = DensePlaceSearch::SweepLevel;
  // `dense` must outlive this; `camera` is the frames' camera (its mount is not used: the poses
  // given are camera_ground's); `level`: where the sweeps are summed (the refine level: about 8×
  // the time, for floors whose coarse level shows nothing under dust).
  TrajectoryPlaceSearch(const DensePlaceSearch* dense, const geometry::CameraModel& camera,
                        SweepLevel level = SweepLevel::kCoarse);

  // Bytes of the summed sweep (one mosaic map per heading step) while frames are held.
  static std::size_t MemoryBytes(const DensePlaceSearch& dense, SweepLevel level);

  void Reset();
  // Adds a frame (CV_8UC1, the camera's size) with camera_ground's pose in odom at its time.
  void Add(const cv::Mat& frame, const geometry::Pose2& camera_in_odom);
  // Add in two steps, for a caller that sweeps the frame anyway (the single-frame dense search at
  // the coarse level): Begin, then Accumulate every map of the frame's sweep at level() — or
  // SweepNewest, which sweeps the frame given to Begin.
  void Begin(const cv::Mat& frame, const geometry::Pose2& camera_in_odom);
  void Accumulate(const DensePlaceSearch::SweepMap& map);
  void SweepNewest();
  SweepLevel level() const { return level_; }
  int frames() const { return static_cast<int>(frames_.size()); }
  // Distance from the first frame's camera to `camera_in_odom` (0 without frames).
  double TravelTo(const geometry::Pose2& camera_in_odom) const;

  // Up to the dense options' max_peaks distinct poses of the newest frame's camera, best first;
  // correlation: the mean over the frames of their refined correlations. Empty without frames.
  // The best's alternatives include Alternative(best): its twin need not be among the coarse sums.
  std::vector<DensePeak> Search() const;
  // The best place distinct from `first` (the first frame's camera) for the newest frame, with
  // the frames' mean correlation, summed at the refine level over ±2 of its heading steps around
  // first's heading: the best distinct alternative, measured at the level the best was.
  DensePeak Alternative(const geometry::Pose2& first) const;
  // The trajectory placed with its newest frame's camera at `newest` and its best distinct
  // alternative, both measured in `search` (another level's search of the same mosaic: where a
  // frame's twin shows): each the frames' mean correlation.
  struct OwnAndTwin {
    double own = 0.0, twin = 0.0;
  };
  OwnAndTwin MeasureTwin(const DensePlaceSearch& search, const geometry::Pose2& newest) const;

 private:
  // The frames' mean correlation in `search`, each refined about the pose the odometry gives it
  // from the first frame's camera at `first`, with the newest frame's refined camera pose.
  DensePeak MeanRefined(const DensePlaceSearch& search, const geometry::Pose2& first) const;

  const DensePlaceSearch* dense_;
  SweepLevel level_;
  Eigen::Vector2d centre_ground_;  // the frame centre in camera_ground
  std::vector<cv::Mat> sum_;       // per first-frame heading step: summed centre score maps
  std::vector<cv::Mat> frames_;
  std::vector<geometry::Pose2> motion_;  // each frame's camera in the first frame's camera
  geometry::Pose2 first_in_odom_;
  int turn_ = 0;                  // the newest frame's heading steps from the first frame's
  Eigen::Vector2d offset_{0, 0};  // its centre from the first's, in the first camera's axes
};

}  // namespace fleetloc::relocalization
