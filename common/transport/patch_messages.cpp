// PatchObservation and PatchAck to and from plain values.
#include "transport/patch_messages.h"

#include <algorithm>

#include "transport/wire_util.h"

namespace fleetloc::transport {

fleetloc_PatchObservation ToIdl(const PatchToSend& p, const std::string& vehicle_id) {
  fleetloc_PatchObservation sample{};
  sample.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  SetBounded(sample.vehicle_id, vehicle_id);
  sample.sequence_number = p.sequence;
  sample.stamp = ToStamp(p.stamp_s);
  SetBounded(sample.mosaic_id, p.mosaic_id);
  sample.mosaic_version = p.mosaic_version;
  sample.x = p.pose.x;
  sample.y = p.pose.y;
  sample.theta = p.pose.theta;
  std::copy(p.covariance, p.covariance + 9, sample.covariance);
  sample.quality = p.quality;
  sample.resolution = p.resolution_m;
  SetBounded(sample.encoding, "png");
  sample.image = BorrowOctets(p.png);
  return sample;
}

Eigen::Matrix3d CovarianceFromIdl(const fleetloc_PatchObservation& sample) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(sample.covariance);
}

mosaic::PatchRecord RecordFromIdl(const fleetloc_PatchObservation& s) {
  mosaic::PatchRecord record;
  record.vehicle_id = GetBounded(s.vehicle_id);
  record.sequence = static_cast<int64_t>(s.sequence_number);
  record.stamp_s = ToSeconds(s.stamp);
  record.pose = {s.x, s.y, s.theta};
  record.covariance = CovarianceFromIdl(s);
  record.quality = s.quality;
  return record;
}

void CopyPng(const fleetloc_PatchObservation& sample, mosaic::PatchRecord* record) {
  const auto bytes = OctetSpan(sample.image);
  record->png.assign(bytes.begin(), bytes.end());
}

fleetloc_PatchAck ToIdl(const PatchAckReply& ack, const std::string& vehicle_id) {
  fleetloc_PatchAck message{};
  message.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  SetBounded(message.vehicle_id, vehicle_id);
  message.sequence_number = ack.sequence;
  message.status = ack.status;
  SetBounded(message.reason, ack.reason);
  return message;
}

ReceivedAck FromIdl(const fleetloc_PatchAck& ack, std::string server_id) {
  return {ack.sequence_number, std::move(server_id), ack.status, GetBounded(ack.reason)};
}

}  // namespace fleetloc::transport
