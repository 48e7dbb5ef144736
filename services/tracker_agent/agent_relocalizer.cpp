// The agent's global relocalization: index intake, background loading, relocalizing a frame.
#include "tracker_agent/agent_relocalizer.h"

#include <spdlog/spdlog.h>

#include <chrono>

namespace fleetloc::tracker_agent {

AgentRelocalizer::AgentRelocalizer(std::unique_ptr<transport::PlaceIndexReceiver> receiver,
                                   std::string mosaic_id, mosaic::RasterSource* mosaic,
                                   const geometry::CameraModel& camera,
                                   const relocalization::RelocalizerOptions& options)
    : receiver_(std::move(receiver)),
      mosaic_id_(std::move(mosaic_id)),
      mosaic_(mosaic),
      camera_(camera),
      options_(options) {}

AgentRelocalizer::~AgentRelocalizer() {
  if (loading_.valid()) loading_.wait();
}

Result<std::unique_ptr<AgentRelocalizer>> AgentRelocalizer::Create(
    const transport::Participant& participant, std::string mosaic_id, mosaic::RasterSource* mosaic,
    const geometry::CameraModel& camera, const relocalization::RelocalizerOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(relocalization::Validate(options));
  auto receiver = transport::PlaceIndexReceiver::Create(participant);
  if (!receiver.ok()) return receiver.status();
  return std::unique_ptr<AgentRelocalizer>(new AgentRelocalizer(
      std::move(receiver).value(), std::move(mosaic_id), mosaic, camera, options));
}

void AgentRelocalizer::Poll() {
  for (transport::PlaceIndexBlob& blob : receiver_->Poll()) {
    if (blob.mosaic_id != mosaic_id_) {
      ++stats_.indexes_rejected;
      spdlog::warn("place index from '{}' is of mosaic '{}', not '{}': ignored", blob.server_id,
                   blob.mosaic_id, mosaic_id_);
      continue;
    }
    const long long newest = std::max(index_version_, loading_version_);
    if (blob.mosaic_version < newest) continue;
    if (queued_ && blob.mosaic_version < queued_->mosaic_version) continue;
    queued_ = std::make_unique<transport::PlaceIndexBlob>(std::move(blob));
  }
  if (loading_.valid() && loading_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    FinishLoading();
  }
  if (!loading_.valid() && queued_) {
    StartLoading(std::move(*queued_));
    queued_.reset();
  }
}

void AgentRelocalizer::StartLoading(transport::PlaceIndexBlob blob) {
  loading_version_ = blob.mosaic_version;
  spdlog::info("loading the place index of mosaic version {} from '{}' ({} bytes)",
               blob.mosaic_version, blob.server_id, blob.bytes.size());
  // Deserializing rebuilds the LSH tables (a second or so for a large mosaic): off the loop.
  loading_ = std::async(std::launch::async, [bytes = std::move(blob.bytes)] {
    return relocalization::PlaceIndex::Deserialize(bytes);
  });
}

void AgentRelocalizer::FinishLoading() {
  Result<relocalization::PlaceIndex> loaded = loading_.get();
  if (!loaded.ok()) {
    ++stats_.indexes_rejected;
    spdlog::warn("place index of version {} unusable: {}", loading_version_,
                 loaded.status().message());
    return;
  }
  auto index = std::make_unique<relocalization::PlaceIndex>(std::move(loaded).value());
  auto relocalizer = relocalization::Relocalizer::Create(index.get(), mosaic_, camera_, options_);
  if (!relocalizer.ok()) {
    ++stats_.indexes_rejected;
    spdlog::warn("place index of version {} unusable: {}", loading_version_,
                 relocalizer.status().message());
    return;
  }
  relocalizer_ = std::move(relocalizer).value();  // the old relocalizer goes before its index
  index_ = std::move(index);
  index_version_ = loading_version_;
  ++stats_.indexes_loaded;
  spdlog::info("place index of mosaic version {} ready: {} features", index_version_,
               index_->size());
}

void AgentRelocalizer::ResetTrajectory() {
  if (relocalizer_) relocalizer_->ResetTrajectory();
}

Result<relocalization::Relocalization> AgentRelocalizer::Relocalize(
    const cv::Mat& frame, const geometry::Pose2& base_in_odom) {
  FLEETLOC_CHECK(ready());
  const auto start = std::chrono::steady_clock::now();
  Result<relocalization::Relocalization> result = relocalizer_->Relocalize(frame, base_in_odom);
  stats_.last_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  stats_.total_ms += stats_.last_ms;
  ++stats_.attempts;
  if (!result.ok()) return result;
  if (result->found) ++stats_.found;
  if (result->found && result->from_trajectory) ++stats_.found_from_trajectory;
  if (!result->found && result->ambiguous) ++stats_.ambiguous;
  return result;
}

}  // namespace fleetloc::tracker_agent
