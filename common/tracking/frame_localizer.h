// FrameLocalizer: anything that turns (frame, time, odometry) into base_link's pose in map — the
// mosaic tracker, and the OpenCV-based peers it is benchmarked against — so one replay loop,
// one agent and one benchmark drive them all the same way.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "geometry/pose2.h"
#include "localization/lock_state.h"

namespace fleetloc::tracking {

using localization::LockState;
using localization::LockStateName;

// What became of a frame's dense alignment (tracking/direct_aligner.h).
enum class DirectUse { kNotRun, kUsed, kRefused, kDisagreed };
const char* DirectUseName(DirectUse use);  // "not_run", "used", "refused", "disagreed"

struct FrameResult {
  double t = 0.0;
  geometry::PoseWithCovariance base_in_map;  // at the frame's time
  LockState state = LockState::kLost;
  int templates = 0;         // correspondences measured (before outlier rejection)
  int inliers = 0;           // correspondences kept by the pose update
  int template_size_px = 0;  // the template size that locked the frame (0: templates did not)
  double rms_residual_px = 0.0;
  int search_radius_px = 0;
  // Where the cycle's time went (ms): choosing sites (texture, overlap, selection), the coarse
  // search and the full-resolution search with the pose updates.
  double select_ms = 0, coarse_ms = 0, fine_ms = 0;
  double direct_ms = 0;  // the dense alignment
  // The full-resolution polish (TrackerOptions::polish): its time, and whether its fit was taken.
  double polish_ms = 0;
  bool polished = false;
  double view_blur_px = 0.0;  // the polish's view blur (the frame's blur against the mosaic)
  DirectUse direct = DirectUse::kNotRun;
  const char* direct_reason = "";  // why it was refused (static text)
  // The dense fit's quality when it ran: finest and coarsest correlation, the coarse search's
  // peak ratio, and its innovation against the prediction (χ², 3 dof).
  double direct_correlation = 0, direct_coarse_correlation = 0, direct_peak_ratio = 0;
  double direct_peak_z = 0;    // the search peak's height over the surface, in its std devs
  int direct_searches = 0;     // correlations of the whole frame (one per heading tried)
  int direct_iterations = 0;   // Gauss–Newton iterations over all levels
  double direct_sigma_px = 0;  // the fit's image-only 1-sigma position, worst direction
  double direct_chi2 = 0;
  // The dense fit was valid only once the polish confirmed it (DirectAlignment::needs_polish).
  bool direct_needs_polish = false;
};

class FrameLocalizer {
 public:
  virtual ~FrameLocalizer() = default;
  virtual std::string name() const = 0;
  // Starts from base_link's pose in map at the time whose odometry pose is `odom`.
  virtual void Reset(const geometry::PoseWithCovariance& base_in_map,
                     const geometry::Pose2& odom) = 0;
  // One frame (CV_8UC1, camera size) at time t with base_link's odometry pose at t.
  virtual FrameResult Track(const cv::Mat& frame, double t, const geometry::Pose2& odom) = 0;
  // A frame that cannot be used: odometry only.
  virtual FrameResult Coast(double t, const geometry::Pose2& odom) = 0;
};

}  // namespace fleetloc::tracking
