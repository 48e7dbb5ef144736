// Global relocalization in the tracker agent: collects the place index the map server publishes
// (the newest complete one for the mosaic being tracked), deserializes it off the tracking thread,
// and relocalizes a frame on request — at start without an initial pose, and when lock is lost
// (a "kidnapped" vehicle). Candidates are verified against the agent's own mosaic view, so tiles
// come through its cache and the map server like the tracker's.
#pragma once

#include <future>
#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "relocalization/relocalizer.h"
#include "tracker_agent/localization_ports.h"
#include "transport/place_index_channel.h"

namespace fleetloc::tracker_agent {

struct RelocalizationStats {
  long long attempts = 0;
  long long found = 0;
  long long found_from_trajectory = 0;  // of those, by frames combined with odometry
  long long ambiguous = 0;              // attempts refused as ambiguous (a self-similar floor)
  long long indexes_loaded = 0;
  long long indexes_rejected = 0;  // blobs that did not deserialize, or of another mosaic
  double last_ms = 0.0;
  double total_ms = 0.0;
};

class AgentRelocalizer : public GlobalRelocalization {
 public:
  // `mosaic` (the agent's view of `mosaic_id`) must outlive this object.
  static Result<std::unique_ptr<AgentRelocalizer>> Create(
      const transport::Participant& participant, std::string mosaic_id,
      mosaic::RasterSource* mosaic, const geometry::CameraModel& camera,
      const relocalization::RelocalizerOptions& options);
  ~AgentRelocalizer() override;

  // Takes arrived index chunks; starts loading a newly completed index in the background and
  // swaps in one whose loading finished. Cheap; call once per loop.
  void Poll();
  bool ready() const override { return relocalizer_ != nullptr; }
  long long index_version() const { return index_version_; }
  // Relocalizes `frame` (rectified, the camera's size) taken at `base_in_odom`; frames that find
  // nothing alone are combined with odometry (Relocalizer's multi-frame search). Requires ready().
  Result<relocalization::Relocalization> Relocalize(const cv::Mat& frame,
                                                    const geometry::Pose2& base_in_odom) override;
  // Forgets the frames held for the multi-frame search (the vehicle tracks again).
  void ResetTrajectory() override;
  double last_ms() const override { return stats_.last_ms; }
  const RelocalizationStats& stats() const { return stats_; }
  std::uint64_t chunks_rejected() const { return receiver_->rejected(); }

 private:
  AgentRelocalizer(std::unique_ptr<transport::PlaceIndexReceiver> receiver, std::string mosaic_id,
                   mosaic::RasterSource* mosaic, const geometry::CameraModel& camera,
                   const relocalization::RelocalizerOptions& options);
  void StartLoading(transport::PlaceIndexBlob blob);
  void FinishLoading();

  std::unique_ptr<transport::PlaceIndexReceiver> receiver_;
  std::string mosaic_id_;
  mosaic::RasterSource* mosaic_;
  geometry::CameraModel camera_;
  relocalization::RelocalizerOptions options_;
  std::future<Result<relocalization::PlaceIndex>> loading_;
  long long loading_version_ = -1;
  std::unique_ptr<transport::PlaceIndexBlob> queued_;  // arrived while another was loading
  std::unique_ptr<relocalization::PlaceIndex> index_;
  std::unique_ptr<relocalization::Relocalizer> relocalizer_;  // reads *index_
  long long index_version_ = -1;
  RelocalizationStats stats_;
};

}  // namespace fleetloc::tracker_agent
