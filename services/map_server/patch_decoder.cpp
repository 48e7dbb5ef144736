// PatchObservation validation and PNG decoding.
#include "map_server/patch_decoder.h"

#include <cmath>
#include <optional>

#include "geometry/covariance_check.h"
#include "mosaic/tile_codec.h"
#include "transport/patch_messages.h"
#include "transport/wire_util.h"

namespace fleetloc::map_server {
namespace {

using transport::GetBounded;

DecodedPatch Reject(const std::string& counter, const std::string& message) {
  return {InvalidInput(message), counter};
}

bool AllFinite(const double* values, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(values[i])) return false;
  }
  return true;
}

// The image's encoding, byte size and PNG header (before anything decodes it); a rejection, or
// nothing when the image may be decoded.
std::optional<DecodedPatch> CheckImage(const fleetloc_PatchObservation& s, const std::string& what,
                                       const PatchLimits& limits) {
  if (GetBounded(s.encoding) != "png") {
    return Reject("rejected_patch_malformed",
                  what + ": encoding '" + GetBounded(s.encoding) + "' is not png");
  }
  const auto bytes = transport::OctetSpan(s.image);
  if (bytes.size() > static_cast<size_t>(limits.max_bytes)) {
    return Reject("rejected_patch_oversized", what + ": image of " + std::to_string(bytes.size()) +
                                                  " bytes, more than " +
                                                  std::to_string(limits.max_bytes));
  }
  const std::optional<cv::Size> size = mosaic::PngHeaderSize(bytes);
  if (!size) return Reject("rejected_patch_image", what + ": image is not a PNG");
  if (size->width < 16 || size->height < 16 || size->width > limits.max_side_px ||
      size->height > limits.max_side_px) {
    return Reject("rejected_patch_oversized", what + ": image " + std::to_string(size->width) +
                                                  "x" + std::to_string(size->height) +
                                                  " px out of [16, " +
                                                  std::to_string(limits.max_side_px) + "]");
  }
  if (Status header = mosaic::CheckGrayPngHeader(bytes, limits.max_side_px); !header.ok()) {
    return Reject("rejected_patch_image", what + ": " + header.message());
  }
  return std::nullopt;
}

}  // namespace

DecodedPatch CheckPatch(const fleetloc_PatchObservation& s, const mosaic::MosaicLayout& layout,
                        const PatchLimits& limits) {
  const std::string vehicle = GetBounded(s.vehicle_id);
  const std::string what = "PatchObservation " + vehicle + "#" + std::to_string(s.sequence_number);
  if (s.wire_version != fleetloc_CURRENT_WIRE_VERSION) {
    return Reject("rejected_patch_malformed",
                  what + ": unknown wire_version " + std::to_string(s.wire_version));
  }
  if (!transport::IsValidEntityId(vehicle)) {
    return Reject("rejected_patch_malformed", what + ": vehicle_id is not 1-11 of [A-Za-z0-9_-]");
  }
  if (s.sequence_number > static_cast<uint64_t>(INT64_MAX)) {
    return Reject("rejected_patch_malformed", what + ": sequence_number out of range");
  }
  const std::string mosaic_id = GetBounded(s.mosaic_id);
  if (!mosaic_id.empty() && mosaic_id != layout.mosaic_id) {
    return Reject("rejected_patch_mosaic", what + ": unknown mosaic '" + mosaic_id + "'");
  }
  if (!(std::abs(s.resolution / layout.geo.resolution - 1.0) < 1e-6)) {
    return Reject(
        "rejected_patch_malformed",
        what + ": resolution " + std::to_string(s.resolution) + " m/px is not the mosaic's");
  }
  const double pose[3] = {s.x, s.y, s.theta};
  if (!AllFinite(pose, 3)) return Reject("rejected_patch_malformed", what + ": pose not finite");
  if (const std::string problem = geometry::CovarianceProblem(transport::CovarianceFromIdl(s));
      !problem.empty()) {
    // A zero or negative covariance claims a certainty no vehicle has: malformed, counted apart.
    return Reject("rejected_patch_covariance", what + ": " + problem);
  }
  if (!(s.quality >= 0.0f && s.quality <= 1.0f)) {
    return Reject("rejected_patch_malformed", what + ": quality not in [0, 1]");
  }
  if (std::optional<DecodedPatch> rejected = CheckImage(s, what, limits)) return *rejected;
  return {transport::RecordFromIdl(s), ""};
}

Status DecodePatchImage(mosaic::PatchRecord* record, const PatchLimits& limits) {
  Result<cv::Mat> image = mosaic::DecodeGrayPng(record->png, limits.max_side_px);
  if (!image.ok()) {
    return InvalidInput("PatchObservation " + record->vehicle_id + "#" +
                        std::to_string(record->sequence) + ": " + image.status().message());
  }
  record->image = std::move(image).value();
  return Status::Ok();
}

DecodedPatch DecodePatch(const fleetloc_PatchObservation& sample,
                         const mosaic::MosaicLayout& layout, const PatchLimits& limits) {
  DecodedPatch checked = CheckPatch(sample, layout, limits);
  if (!checked.record.ok()) return checked;
  transport::CopyPng(sample, &*checked.record);
  if (Status decoded = DecodePatchImage(&*checked.record, limits); !decoded.ok()) {
    return Reject("rejected_patch_image", decoded.message());
  }
  return checked;
}

}  // namespace fleetloc::map_server
