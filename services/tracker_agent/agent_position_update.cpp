// Forward-camera landmarks → detection window → map fit → corrected pose (see
// agent_position_update.h).
#include "tracker_agent/agent_position_update.h"

#include <spdlog/spdlog.h>

#include <cmath>

namespace fleetloc::tracker_agent {
namespace {

Status CheckLandmarks(const std::vector<Eigen::Vector2d>& landmarks) {
  if (landmarks.empty()) return InvalidInput("position update: the landmark map is empty");
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    if (!landmarks[i].allFinite()) {
      return InvalidInput("position update: landmark " + std::to_string(i) + " is not finite");
    }
  }
  if (const auto same = mapmatch::FindDuplicateLandmarks(landmarks)) {
    return InvalidInput("position update: landmarks " + std::to_string(same->first) + " and " +
                        std::to_string(same->second) + " are at the same position");
  }
  return Status::Ok();
}

double Distance(const geometry::Pose2& a, const geometry::Pose2& b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

}  // namespace

nlohmann::json ToJson(const PositionUpdateStats& s) {
  return {{"images", s.images},
          {"images_rejected", s.images_rejected},
          {"points", s.points},
          {"attempted", s.attempted},
          {"applied", s.applied},
          {"rejected", s.rejected},
          {"not_needed", s.not_needed},
          {"last_correction_m", s.last_correction_m},
          {"max_correction_m", s.max_correction_m},
          {"last_disagreement_m", s.last_disagreement_m},
          {"max_disagreement_m", s.max_disagreement_m},
          {"last_reason", s.last_reason},
          {"last_rejected", s.last_rejected}};
}

Result<std::unique_ptr<AgentPositionUpdate>> AgentPositionUpdate::Create(
    const mapmatch::ForwardCameraParams& camera, std::vector<Eigen::Vector2d> landmarks,
    const PositionUpdateOptions& options) {
  if (!(std::isfinite(options.period_s) && options.period_s > 0)) {
    return InvalidInput("position update: period_s must be > 0");
  }
  if (!(std::isfinite(options.window_s) && options.window_s > 0)) {
    return InvalidInput("position update: window_s must be > 0");
  }
  if (!(std::isfinite(options.max_correction_m) && options.max_correction_m > 0)) {
    return InvalidInput("position update: max_correction_m must be > 0");
  }
  if (!(std::isfinite(options.max_correction_rad) && options.max_correction_rad > 0)) {
    return InvalidInput("position update: max_correction_rad must be > 0");
  }
  FLEETLOC_RETURN_IF_ERROR(mapmatch::Validate(options.fit));
  FLEETLOC_RETURN_IF_ERROR(CheckLandmarks(landmarks));
  Result<mapmatch::ForwardCamera> model = mapmatch::ForwardCamera::Create(camera);
  if (!model.ok()) return model.status();
  Result<mapmatch::LandmarkDetector> detector =
      mapmatch::LandmarkDetector::Create(*model, options.detector);
  if (!detector.ok()) return detector.status();
  return std::unique_ptr<AgentPositionUpdate>(
      new AgentPositionUpdate(std::move(detector).value(), std::move(landmarks), options));
}

AgentPositionUpdate::AgentPositionUpdate(mapmatch::LandmarkDetector detector,
                                         std::vector<Eigen::Vector2d> landmarks,
                                         const PositionUpdateOptions& options)
    : detector_(std::move(detector)),
      landmarks_(std::move(landmarks)),
      options_(options),
      window_(options.window_s) {}

Status AgentPositionUpdate::AddImage(double t, const cv::Mat& image,
                                     const geometry::Pose2& estimate) {
  ++stats_.images;
  if (!(t >= last_image_t_)) {
    ++stats_.images_rejected;
    return InvalidInput("forward image at t=" + std::to_string(t) + ": before the previous one");
  }
  Result<std::vector<mapmatch::FloorPointDetection>> detections = detector_.Detect(image);
  Status added = detections.status();
  if (added.ok()) {
    std::vector<Eigen::Vector2d> points;
    points.reserve(detections->size());
    for (const mapmatch::FloorPointDetection& d : *detections) points.push_back(d.point);
    added = window_.Add(t, estimate, points);
    if (added.ok()) stats_.points += static_cast<long long>(points.size());
  }
  if (!added.ok()) {
    ++stats_.images_rejected;
    return InvalidInput("forward image at t=" + std::to_string(t) + ": " + added.message());
  }
  last_image_t_ = t;
  if (!last_fit_t_) last_fit_t_ = t;
  return Status::Ok();
}

std::optional<geometry::PoseWithCovariance> AgentPositionUpdate::Update(
    double t, const geometry::PoseWithCovariance& current, bool use) {
  if (!last_fit_t_ || t - *last_fit_t_ < options_.period_s) return std::nullopt;
  last_fit_t_ = t;
  ++stats_.attempted;
  window_.DropOlderThanWindow(t);
  if (window_.empty()) {
    Reject(t, "no floor points detected in the last " + std::to_string(options_.window_s) + " s");
    return std::nullopt;
  }
  Result<mapmatch::PositionUpdate> update =
      mapmatch::UpdateGlobalPosition(window_, t, landmarks_, current, options_.fit);
  if (!update.ok()) {
    Reject(t, update.status().message());
    return std::nullopt;
  }
  if (!update->applied) {
    Reject(t, "the map fit did not converge: " + update->fit.reason);
    return std::nullopt;
  }
  const mapmatch::MapFitResult& fit = update->fit;
  spdlog::debug(
      "position fit at t={:.3f}: {} landmarks, {} pairs, rms {:.3f} m, support {:.1f} (runner-up "
      "{:.1f}), {} starts, {} iterations",
      t, fit.landmarks_matched, fit.inliers, fit.rms_residual_m, fit.support, fit.runner_up_support,
      fit.starts, fit.iterations);
  const double moved = Distance(update->pose.pose, current.pose);
  const double turned = std::abs(geometry::WrapAngle(update->pose.pose.theta - current.pose.theta));
  if (moved > options_.max_correction_m || turned > options_.max_correction_rad) {
    Reject(t, "the fit would move the pose " + std::to_string(moved) + " m and turn it " +
                  std::to_string(turned) + " rad, more than the agent allows");
    return std::nullopt;
  }
  stats_.last_rejected = false;
  if (!use) {
    ++stats_.not_needed;
    stats_.last_disagreement_m = moved;
    stats_.max_disagreement_m = std::max(stats_.max_disagreement_m, moved);
    return update->pose;
  }
  ++stats_.applied;
  stats_.last_correction_m = moved;
  stats_.max_correction_m = std::max(stats_.max_correction_m, moved);
  window_.ApplyCorrection(update->fit.correction);
  const geometry::Pose2& pose = update->pose.pose;
  spdlog::info("position update at t={:.3f}: corrected by {:.3f} m to ({:.4f}, {:.4f}, {:.2f} deg)",
               t, moved, pose.x, pose.y, pose.theta * 180.0 / M_PI);
  return update->pose;
}

void AgentPositionUpdate::Forget() {
  window_ = mapmatch::DetectionWindow(options_.window_s);
  last_fit_t_.reset();
  last_image_t_ = -INFINITY;
}

void AgentPositionUpdate::Reject(double t, const std::string& reason) {
  spdlog::info("position update at t={:.3f} rejected: {}", t, reason);
  ++stats_.rejected;
  stats_.last_rejected = true;
  stats_.last_reason = reason;
}

}  // namespace fleetloc::tracker_agent
