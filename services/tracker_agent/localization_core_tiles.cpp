// LocalizationCore's tiles: the footprint asked for ahead along the predicted motion, arrived
// tiles decoded between events, and the tracker warmed up at a start or relocalized pose before
// the frame that needs it.
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

#include "tracker_agent/localization_core.h"

namespace fleetloc::tracker_agent {

void LocalizationCore::Prefetch(double t, const geometry::Pose2& base) {
  // Where the vehicle is and where it will be prefetch_ahead_s from now if it keeps moving as it
  // did over the last prefetch_ahead_s (odometry), with the footprint in between.
  std::vector<geometry::Pose2> along{base};
  const Result<geometry::Pose2> before = odometry_.At(t - options_.prefetch_ahead_s);
  const Result<geometry::Pose2> now = odometry_.At(t);
  if (before.ok() && now.ok()) {
    const geometry::Pose2 step = geometry::Between(*before, *now);
    along.push_back(base * tracking::Interpolate({}, step, 0.5));
    along.push_back(base * step);
  }
  std::set<mosaic::TileKey> keys;
  for (const geometry::Pose2& pose : along) AddFootprintTiles(pose, &keys);
  const std::vector<mosaic::TileKey> missing(keys.begin(), keys.end());
  if (Status asked = ports_.tiles->Prefetch(missing); !asked.ok())
    health_.RecordError(asked.message());
}

void LocalizationCore::DecodeArrivedTiles(size_t max_tiles) {
  const Result<size_t> encoded = ports_.tiles->DecodeArrived(max_tiles);
  if (!encoded.ok()) health_.RecordError(encoded.status().message());
}

void LocalizationCore::AddFootprintTiles(const geometry::Pose2& base,
                                         std::set<mosaic::TileKey>* keys) const {
  // The footprint's bounding box grown by the margin, at level 0 and at the coarse levels.
  const geometry::Pose2 camera = base * camera_.model.mount;
  const double reach_m = (std::hypot(camera_.model.width_px, camera_.model.height_px) / 2 +
                          options_.prefetch_margin_px) *
                         layout_.geo.resolution;
  const double u = (camera.x - layout_.geo.origin_x) / layout_.geo.resolution;
  const double v = (layout_.geo.origin_y - camera.y) / layout_.geo.resolution;
  const int r = static_cast<int>(reach_m / layout_.geo.resolution);
  for (int level = 0; level < std::min(layout_.levels, 3); ++level) {
    const cv::Rect box(static_cast<int>(u - r) >> level, static_cast<int>(v - r) >> level,
                       (2 * r) >> level, (2 * r) >> level);
    mosaic::TilesCovering(layout_, level, box).ForEach([&](const mosaic::TileKey& k) {
      if (!ports_.tiles->Cached(k)) keys->insert(k);
    });
  }
}

void LocalizationCore::DropTiles(const std::vector<mosaic::TileKey>& changed) {
  tracker_.DropTiles(changed);
}

void LocalizationCore::WarmUpAtStart() {
  if (initial_) WarmUp(0.0, *initial_);
}

void LocalizationCore::BetweenEvents() {
  if (options_.live) DecodeArrivedTiles(kTilesDecodedPerTurn);
  WarmUpTracker();
}

void LocalizationCore::WarmUp(double t, const geometry::PoseWithCovariance& base) {
  if (started_) return;
  spdlog::info("warm-up: asking for the tiles around the start pose ({:.3f}, {:.3f})", base.pose.x,
               base.pose.y);
  Prefetch(t, base.pose);
  ScheduleTrackerWarmUp(base, "start pose");
}

void LocalizationCore::ScheduleTrackerWarmUp(const geometry::PoseWithCovariance& base,
                                             const char* what) {
  // Live only: a replay has no time between events to do it in (its loop decodes no tiles there).
  if (!options_.live) return;
  tracker_warm_up_ = base;
  warm_up_what_ = what;
  warm_up_tiles_ = 0;
  warm_up_ms_ = 0.0;
}

void LocalizationCore::WarmUpTracker() {
  if (!tracker_warm_up_ || !ports_.tiles->Settled()) return;
  const auto start = std::chrono::steady_clock::now();
  const int normalized = tracker_.WarmUp(*tracker_warm_up_, kTilesNormalizedPerTurn);
  warm_up_tiles_ += normalized;
  warm_up_ms_ +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (normalized == kTilesNormalizedPerTurn) return;  // more next turn
  tracker_warm_up_.reset();
  spdlog::info("warm-up: {} normalized tiles around the {} ready ({:.1f} ms of work)",
               warm_up_tiles_, warm_up_what_, warm_up_ms_);
}

}  // namespace fleetloc::tracker_agent
