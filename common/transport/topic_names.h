// The DDS topic names and partition naming of fleetloc (docs/topics.md explains each).
#pragma once

#include <string>

namespace fleetloc::transport::topics {

inline constexpr const char* kMosaicInfo = "fleetloc/mosaic_info";
inline constexpr const char* kTileRequest = "fleetloc/tile_request";
inline constexpr const char* kTile = "fleetloc/tile";
inline constexpr const char* kTileUpdate = "fleetloc/tile_update";
inline constexpr const char* kPatchObservation = "fleetloc/patch_observation";
inline constexpr const char* kPatchAck = "fleetloc/patch_ack";
inline constexpr const char* kRemapCommand = "fleetloc/remap_command";
inline constexpr const char* kRemapStatus = "fleetloc/remap_status";
inline constexpr const char* kVehiclePose = "fleetloc/vehicle_pose";
inline constexpr const char* kVehicleHealth = "fleetloc/vehicle_health";
inline constexpr const char* kServiceHealth = "fleetloc/service_health";
inline constexpr const char* kPlaceIndex = "fleetloc/place_index";

// A vehicle's partition. Replies meant for one vehicle (Tile, PatchAck) are written in it only,
// so a vehicle's traffic does not grow with the fleet; the vehicle's own streams (VehiclePose,
// VehicleHealth, PatchObservation, TileRequest) are written in it too, so DDS Security can grant
// a vehicle its own partition only (transport/vehicle_streams.h). Requires a valid vehicle id
// (IsValidEntityId: never a wildcard).
inline std::string VehiclePartition(const std::string& vehicle_id) {
  return "fleetloc.vehicle." + vehicle_id;
}
// Every vehicle's partition: the receivers of the vehicles' streams subscribe with it.
inline constexpr const char* kAnyVehiclePartition = "fleetloc.vehicle.*";

// The USER_DATA of a map server's PatchAck writers names the server, so a vehicle knows which
// replica of a split mosaic stored its patch (a PatchAck sample does not say, and the type is
// @final: docs/topics.md, "Interoperability with a second vendor").
inline constexpr const char* kServerIdUserDataPrefix = "fleetloc.server_id=";
inline std::string ServerIdUserData(const std::string& server_id) {
  return kServerIdUserDataPrefix + server_id;
}
// The server id in `user_data`, or empty when it names none.
inline std::string ServerIdFromUserData(const std::string& user_data) {
  const std::string prefix = kServerIdUserDataPrefix;
  return user_data.rfind(prefix, 0) == 0 ? user_data.substr(prefix.size()) : std::string();
}

}  // namespace fleetloc::transport::topics
