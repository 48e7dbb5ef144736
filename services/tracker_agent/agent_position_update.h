// The global position update in the tracker agent (docs/architecture.md, paper 001 §5): each
// forward-camera image → LandmarkDetector → floor points in base_link, added to a DetectionWindow
// placed with the agent's pose estimate at the image's time; every period_s of image time the
// robust map fit of the window against the landmark map corrects the estimate. The agent decides
// whether to use the correction (not while the downward camera tracks: the mosaic is
// millimetre-accurate, the map fit centimetre-accurate) and applies it. No DDS, no files; fits are
// logged.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"
#include "mapmatch/global_position_update.h"
#include "mapmatch/landmark_detector.h"

namespace fleetloc::tracker_agent {

struct PositionUpdateOptions {
  double period_s = 1.0;  // one fit per this much image time; > 0
  double window_s = 2.0;  // over the detections of this last stretch; > 0
  // A fit is used only when the robust fit (mapmatch/robust_map_fit.h) passes its validation: it
  // lands the window's points on at least fit.fit.min_landmarks landmarks (3 here: with two,
  // points paired with the wrong landmarks fitted as well as with the right ones, seen facing a
  // corridor's end wall: 2 landmarks, 6 pairs, the pose 14 cm and 2.7° off), each with
  // min_points_per_landmark points (2 here: the window holds 4–5 images, a corner seen in two of
  // them counts), tightly, and no other correction within the search radius (0.5 m) is supported
  // almost as well. h shrinks to 5 cm: on rendered corridors (agent_position_update_test, exact
  // poses) the fits were 3-7 cm off with 10 cm and mostly within 1.3 cm with 5 cm.
  mapmatch::GlobalPositionUpdateOptions fit{.weight_half_life_s = 1.0,
                                            .fit = {.search_radius_m = 0.5,
                                                    .final_radius_m = 0.05,
                                                    .min_landmarks = 3,
                                                    .min_points_per_landmark = 2}};
  // ... and when it would move the pose at most this far and turn it at most this much (> 0).
  double max_correction_m = 0.5;
  double max_correction_rad = 0.1;
  mapmatch::LandmarkDetectorOptions detector;
};

struct PositionUpdateStats {
  long long images = 0;            // forward images given
  long long images_rejected = 0;   // that the detector could not use (size, type) or not placed
  long long points = 0;            // floor points detected in them
  long long attempted = 0;         // fits due: each one applied, rejected or not needed
  long long applied = 0;           // corrections the agent used
  long long rejected = 0;          // fits that did not converge, failed or jumped: never used
  long long not_needed = 0;        // converged while the downward camera tracked: not used
  double last_correction_m = 0.0;  // position change of the last used correction
  double max_correction_m = 0.0;
  double last_disagreement_m = 0.0;  // while tracking: the fit's pose vs the tracked one
  double max_disagreement_m = 0.0;
  std::string last_reason;     // why the last rejected fit was rejected
  bool last_rejected = false;  // the last fit was rejected
};

// The counters and sizes as the agent's summary shows them ("position_update").
nlohmann::json ToJson(const PositionUpdateStats& stats);

class AgentPositionUpdate {
 public:
  // InvalidInput for an invalid camera or options, or an empty or broken landmark map (non-finite
  // or repeated positions), naming the problem.
  static Result<std::unique_ptr<AgentPositionUpdate>> Create(
      const mapmatch::ForwardCameraParams& camera, std::vector<Eigen::Vector2d> landmarks,
      const PositionUpdateOptions& options);

  // Detects the floor points of `image` (taken at t, 8-bit gray or BGR of the camera's size) and
  // adds them to the window, placed with `estimate` (base_link in map at t). InvalidInput naming
  // the time for an image the detector cannot use or a time before the previous image's; counted
  // in images_rejected, the window unchanged.
  Status AddImage(double t, const cv::Mat& image, const geometry::Pose2& estimate);

  // When a fit is due at t (period_s after the previous one, the first period_s after the first
  // image), fits the window against the map with `current` (the estimate at t) and returns the
  // corrected pose with the fit's covariance if the fit converged (validated, not ambiguous)
  // within the max correction; nullopt otherwise (counted as rejected with the reason, or not
  // due). `use`: the
  // agent replaces its estimate with the result (the window follows the correction); otherwise only
  // the disagreement is recorded.
  std::optional<geometry::PoseWithCovariance> Update(double t,
                                                     const geometry::PoseWithCovariance& current,
                                                     bool use);

  // Drops the window (after the estimate jumped for another reason, e.g. a relocalization).
  void Forget();

  const PositionUpdateStats& stats() const { return stats_; }
  std::size_t landmarks() const { return landmarks_.size(); }

 private:
  AgentPositionUpdate(mapmatch::LandmarkDetector detector, std::vector<Eigen::Vector2d> landmarks,
                      const PositionUpdateOptions& options);
  void Reject(double t, const std::string& reason);  // counts and logs

  mapmatch::LandmarkDetector detector_;
  std::vector<Eigen::Vector2d> landmarks_;
  PositionUpdateOptions options_;
  mapmatch::DetectionWindow window_;
  std::optional<double> last_fit_t_;  // or the first image's time, before the first fit
  double last_image_t_ = -INFINITY;
  PositionUpdateStats stats_;
};

}  // namespace fleetloc::tracker_agent
