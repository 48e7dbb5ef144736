// VDA 5050 message building.
#include "fleet_supervisor/vda5050_messages.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "geometry/pose2.h"

namespace fleetloc::fleet_supervisor {

std::string Vda5050Topic(const Vda5050Header& h, const std::string& serial_number,
                         const std::string& subtopic) {
  return h.interface_name + "/" + h.major_version + "/" + h.manufacturer + "/" + serial_number +
         "/" + subtopic;
}

std::string Iso8601(double unix_s) {
  const double whole = std::floor(unix_s);
  const std::time_t seconds = static_cast<std::time_t>(whole);
  int millis = static_cast<int>(std::lround((unix_s - whole) * 1000.0));
  std::time_t shown = seconds;
  if (millis >= 1000) {
    millis -= 1000;
    ++shown;
  }
  std::tm utc{};
  gmtime_r(&shown, &utc);
  char text[64];  // room for any int the compiler cannot rule out
  std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900,
                utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, millis);
  return text;
}

std::optional<Velocity> VelocityBetween(const fleet::PoseSample& a, const fleet::PoseSample& b) {
  const double dt = b.t - a.t;
  if (!(dt >= 1e-3)) return std::nullopt;
  const double dx = (b.x - a.x) / dt, dy = (b.y - a.y) / dt;
  const double turn = geometry::WrapAngle(b.theta - a.theta);
  // The chord between the poses runs along the heading halfway through the turn.
  const double mid = a.theta + turn / 2, c = std::cos(mid), s = std::sin(mid);
  return Velocity{c * dx + s * dy, -s * dx + c * dy, turn / dt};
}

std::string Vda5050MapId(const std::string& mosaic_id, long long version) {
  return mosaic_id + "@" + std::to_string(version);
}

namespace {

nlohmann::json Header(const Vda5050Header& h, const std::string& serial_number,
                      std::uint32_t header_id, double now) {
  return {{"headerId", header_id},
          {"timestamp", Iso8601(now)},
          {"version", h.version},
          {"manufacturer", h.manufacturer},
          {"serialNumber", serial_number}};
}

}  // namespace

nlohmann::json VisualizationMessage(const Vda5050Header& h, const std::string& serial_number,
                                    std::uint32_t header_id, double now,
                                    const fleet::PoseSample& pose, const std::string& mosaic_id,
                                    const std::optional<Velocity>& velocity) {
  nlohmann::json m = Header(h, serial_number, header_id, now);
  m["agvPosition"] = {{"x", pose.x},
                      {"y", pose.y},
                      {"theta", geometry::WrapAngle(pose.theta)},
                      {"mapId", Vda5050MapId(mosaic_id, pose.mosaic_version)},
                      {"mapDescription", "fleetloc floor mosaic " + mosaic_id + " version " +
                                             std::to_string(pose.mosaic_version)},
                      {"positionInitialized", pose.lock != localization::LockState::kLost},
                      {"localizationScore", std::clamp(pose.localization_score, 0.0, 1.0)},
                      {"deviationRange", std::max(0.0, pose.deviation_range_m)}};
  if (velocity)
    m["velocity"] = {{"vx", velocity->vx}, {"vy", velocity->vy}, {"omega", velocity->omega}};
  return m;
}

nlohmann::json ConnectionMessage(const Vda5050Header& h, const std::string& serial_number,
                                 std::uint32_t header_id, double now, const std::string& state) {
  nlohmann::json m = Header(h, serial_number, header_id, now);
  m["connectionState"] = state;
  return m;
}

}  // namespace fleetloc::fleet_supervisor
