// What the DDS-free localization core asks of the rest of the tracker agent, and hands to it:
// mosaic tiles on demand, global relocalization, where its poses go and which frames tracked.
// The agent's DDS link, relocalizer and patch collector implement them; tests fake them.
#pragma once

#include <cstddef>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"
#include "mosaic/tile_key.h"
#include "relocalization/relocalizer.h"
#include "tracker_agent/capture_latency.h"
#include "tracking/frame_localizer.h"

namespace fleetloc::tracker_agent {

// Where a published pose comes from. The ROS 2 pose topic carries the poses at frame times and
// given start poses, the map → odom transform all three; only a frame's pose has a capture time
// to time the capture → pose latency from.
enum class PoseOrigin { kFrame, kOdometry, kGiven };

// A live frame in its tracker cycle: its times and when the cycle began (host clock).
struct FrameCycle {
  FrameTimes times;
  double cycle_start = 0.0;
};

// A pose the core publishes: base_link in map at time t.
struct PoseToPublish {
  double t = 0.0;
  geometry::PoseWithCovariance base;
  tracking::LockState state = tracking::LockState::kLost;
  PoseOrigin origin = PoseOrigin::kFrame;
  std::optional<FrameCycle> cycle;  // a live frame's pose: to time capture → pose
};

// The mosaic's tiles as the core's tracker reads them through its view.
class TileSupply {
 public:
  virtual ~TileSupply() = default;
  // Asks ahead for `keys` (tiles not cached yet); an error is counted, nothing else.
  virtual Status Prefetch(const std::vector<mosaic::TileKey>& keys) = 0;
  // Decodes at most `max_tiles` of the tiles that arrived; how many are still encoded.
  virtual Result<size_t> DecodeArrived(size_t max_tiles) = 0;
  // Nothing asked for is in flight or waiting to be decoded.
  virtual bool Settled() const = 0;
  virtual bool Cached(const mosaic::TileKey& key) const = 0;
};

// Global relocalization of a frame against the whole mosaic (the place index).
class GlobalRelocalization {
 public:
  virtual ~GlobalRelocalization() = default;
  virtual bool ready() const = 0;
  // Relocalizes `frame` (rectified) taken at `base_in_odom`. Requires ready().
  virtual Result<relocalization::Relocalization> Relocalize(
      const cv::Mat& frame, const geometry::Pose2& base_in_odom) = 0;
  // Forgets the frames held for a multi-frame search (the vehicle tracks again).
  virtual void ResetTrajectory() = 0;
  virtual double last_ms() const = 0;  // how long the last attempt took
};

// Where the core's poses go (the DDS pose stream, the vehicle's ROS 2 stack).
class PosePublisher {
 public:
  virtual ~PosePublisher() = default;
  virtual void PublishPose(const PoseToPublish& pose) = 0;
  // base_link in map and base_link in odom at time t (odometry covers t): the map → odom transform.
  virtual void PublishMapToOdom(double t, const geometry::Pose2& base_in_map,
                                const geometry::Pose2& base_in_odom) = 0;
  // Whether PublishMapToOdom is wanted at all (the core defers and looks up odometry for it).
  virtual bool WantsMapToOdom() const = 0;
};

// Told of each downward frame's result once its pose is out (the patch collector), unless the
// frame relocalized.
class TrackedFrameObserver {
 public:
  virtual ~TrackedFrameObserver() = default;
  virtual void FrameTracked(double t, const cv::Mat& frame,
                            const tracking::FrameResult& result) = 0;
};

}  // namespace fleetloc::tracker_agent
