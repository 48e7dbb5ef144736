// Patch collection on the wire (PatchObservation, PatchAck) as plain values, and the one place
// they are converted: the vehicle's patch client (patch_client.h) and the map server's patch
// service and decoder call these. Checking a received patch (wire_version, ids, pose, covariance,
// image) stays with the map server (services/map_server/patch_decoder.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/pose2.h"
#include "mosaic/patch_store.h"
#include "transport/fleetloc_types.h"

namespace fleetloc::transport {

// What a vehicle reports of one floor patch (see PatchObservation in idl/fleetloc.idl).
struct PatchToSend {
  uint64_t sequence = 0;
  double stamp_s = 0;
  std::string mosaic_id;
  long long mosaic_version = 0;
  geometry::Pose2 pose;       // camera_ground of the image centre in map
  double covariance[9] = {};  // row-major (x, y, theta)
  float quality = 0;
  double resolution_m = 0;
  std::vector<std::uint8_t> png;  // 8-bit gray PNG
};

// One PatchAck as the map server sends it (to the vehicle whose partition it is written in).
struct PatchAckReply {
  uint64_t sequence = 0;
  fleetloc_PatchAckStatus status = fleetloc_PATCH_REJECTED;
  std::string reason;
};

// One PatchAck as the vehicle receives it.
struct ReceivedAck {
  uint64_t sequence = 0;
  std::string server_id;  // the acknowledging map server; empty when its writer does not say
  fleetloc_PatchAckStatus status = fleetloc_PATCH_REJECTED;
  std::string reason;
};

// The wire's observation from `vehicle_id`, stamped with wire_version, encoding "png"; its image
// borrows `patch.png`.
fleetloc_PatchObservation ToIdl(const PatchToSend& patch, const std::string& vehicle_id);
// The sample's row-major covariance as a matrix.
Eigen::Matrix3d CovarianceFromIdl(const fleetloc_PatchObservation& sample);
// The store's record of a received observation: id, sequence, stamp, pose, covariance, quality;
// neither image nor PNG bytes (CopyPng copies them). The sample must have been checked (a
// sequence number fits int64).
mosaic::PatchRecord RecordFromIdl(const fleetloc_PatchObservation& sample);
// Copies the sample's PNG bytes into the record.
void CopyPng(const fleetloc_PatchObservation& sample, mosaic::PatchRecord* record);

fleetloc_PatchAck ToIdl(const PatchAckReply& ack, const std::string& vehicle_id);
ReceivedAck FromIdl(const fleetloc_PatchAck& ack, std::string server_id);

}  // namespace fleetloc::transport
