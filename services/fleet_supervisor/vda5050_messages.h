// VDA 5050 (version 2) messages the fleet supervisor publishes for a fleet manager: a vehicle's
// `visualization` (agvPosition and velocity) and the supervisor's own `connection` state, as JSON,
// with the topic names <interfaceName>/<majorVersion>/<manufacturer>/<serialNumber>/<subtopic>.
// Pure: values in, JSON text out; the MQTT side is vda5050_publisher.h.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "fleet/vehicle_samples.h"

namespace fleetloc::fleet_supervisor {

// The topic fields (VDA 5050 section 6.2) and the protocol version written in each header.
struct Vda5050Header {
  std::string interface_name = "uagv";
  std::string major_version = "v2";
  std::string version = "2.0.0";
  std::string manufacturer = "fleetloc";
};

// `<interface_name>/<major_version>/<manufacturer>/<serial_number>/<subtopic>`.
std::string Vda5050Topic(const Vda5050Header& header, const std::string& serial_number,
                         const std::string& subtopic);

// Unix seconds as ISO 8601 UTC with milliseconds: "2026-11-26T12:13:09.123Z".
std::string Iso8601(double unix_s);

// A vehicle's velocity in its own frame (vx forward, vy left, omega counter-clockwise) from two
// poses in the map frame (the displacement taken along the mean heading, so driving an arc reads
// as forward motion); nullopt when the poses are not at least 1 ms apart in order.
struct Velocity {
  double vx = 0, vy = 0, omega = 0;
};
std::optional<Velocity> VelocityBetween(const fleet::PoseSample& before,
                                        const fleet::PoseSample& after);

// The `visualization` message of one vehicle. `map_id` names the mosaic and its version
// ("<mosaic_id>@<version>"); `map_description` says so in words.
nlohmann::json VisualizationMessage(const Vda5050Header& header, const std::string& serial_number,
                                    std::uint32_t header_id, double now,
                                    const fleet::PoseSample& pose, const std::string& mosaic_id,
                                    const std::optional<Velocity>& velocity);

// The `connection` message: `state` is ONLINE, OFFLINE or CONNECTIONBROKEN.
nlohmann::json ConnectionMessage(const Vda5050Header& header, const std::string& serial_number,
                                 std::uint32_t header_id, double now, const std::string& state);

// "<mosaic_id>@<version>" (VDA 5050 mapId: the map and its version in one string).
std::string Vda5050MapId(const std::string& mosaic_id, long long version);

}  // namespace fleetloc::fleet_supervisor
