// VDA 5050 messages: topic names, ISO 8601 stamps, the visualization and connection fields and
// types the standard's schemas require, velocity in the vehicle frame.
#include "fleet_supervisor/vda5050_messages.h"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>

namespace fleetloc::fleet_supervisor {
namespace {

TEST(Vda5050, TopicHasTheFiveLevels) {
  Vda5050Header h;
  h.interface_name = "site-a";
  h.manufacturer = "acme";
  EXPECT_EQ(Vda5050Topic(h, "SN-1", "visualization"), "site-a/v2/acme/SN-1/visualization");
}

TEST(Vda5050, TimestampsAreIso8601UtcWithMilliseconds) {
  EXPECT_EQ(Iso8601(0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(Iso8601(1764159189.1234), "2025-11-26T12:13:09.123Z");
  EXPECT_EQ(Iso8601(1764159189.9996), "2025-11-26T12:13:10.000Z");  // rounding carries into seconds
}

TEST(Vda5050, VelocityIsInTheVehicleFrame) {
  fleet::PoseSample a, b;
  a.t = 10;
  b.t = 10.5;
  a.theta = b.theta = M_PI / 2;  // facing +y
  b.y = 0.5;                     // moved 0.5 m along +y in 0.5 s: forward at 1 m/s
  std::optional<Velocity> v = VelocityBetween(a, b);
  ASSERT_TRUE(v);
  EXPECT_NEAR(v->vx, 1.0, 1e-12);
  EXPECT_NEAR(v->vy, 0.0, 1e-12);
  EXPECT_NEAR(v->omega, 0.0, 1e-12);
  b.theta = M_PI / 2 + 0.1;
  EXPECT_NEAR(VelocityBetween(a, b)->omega, 0.2, 1e-12);
  // A quarter circle of radius 1 m driven forward in 1 s: all forward, no sideways motion.
  fleet::PoseSample s0, s1;
  s0.t = 0;
  s1.t = 1;
  s0.x = 1;
  s0.y = 0;
  s0.theta = M_PI / 2;
  s1.x = 0;
  s1.y = 1;
  s1.theta = M_PI;
  std::optional<Velocity> arc = VelocityBetween(s0, s1);
  ASSERT_TRUE(arc);
  EXPECT_NEAR(arc->vx, std::sqrt(2.0), 1e-12);  // the chord's length per second
  EXPECT_NEAR(arc->vy, 0.0, 1e-12);
  EXPECT_NEAR(arc->omega, M_PI / 2, 1e-12);
  EXPECT_FALSE(VelocityBetween(b, a));  // out of order
  b.t = a.t;
  EXPECT_FALSE(VelocityBetween(a, b));
}

TEST(Vda5050, VisualizationCarriesThePositionFieldsTheSchemaRequires) {
  fleet::PoseSample p;
  p.x = 1.5;
  p.y = -2.25;
  p.theta = 4.0;  // wrapped into (-pi, pi]
  p.lock = localization::LockState::kTracking;
  p.localization_score = 1.3;  // clamped to [0, 1]
  p.deviation_range_m = 0.004;
  p.mosaic_version = 3;
  const nlohmann::json m =
      VisualizationMessage({}, "SN-7", 41, 1764159189.5, p, "floor-a", Velocity{0.5, 0, 0.1});
  EXPECT_EQ(m["headerId"], 41);
  EXPECT_EQ(m["timestamp"], "2025-11-26T12:13:09.500Z");
  EXPECT_EQ(m["version"], "2.0.0");
  EXPECT_EQ(m["manufacturer"], "fleetloc");
  EXPECT_EQ(m["serialNumber"], "SN-7");
  const nlohmann::json& a = m["agvPosition"];
  for (const char* key : {"x", "y", "theta", "mapId", "positionInitialized"})
    EXPECT_TRUE(a.contains(key)) << key;
  EXPECT_EQ(a["x"], 1.5);
  EXPECT_NEAR(a["theta"].get<double>(), 4.0 - 2 * M_PI, 1e-12);
  EXPECT_EQ(a["mapId"], "floor-a@3");
  EXPECT_TRUE(a["mapDescription"].is_string());
  EXPECT_EQ(a["positionInitialized"], true);
  EXPECT_EQ(a["localizationScore"], 1.0);
  EXPECT_EQ(a["deviationRange"], 0.004);
  EXPECT_EQ(m["velocity"]["vx"], 0.5);
  EXPECT_EQ(m["velocity"]["omega"], 0.1);
  p.lock = localization::LockState::kLost;
  const nlohmann::json lost = VisualizationMessage({}, "SN-7", 42, 0, p, "floor-a", std::nullopt);
  EXPECT_EQ(lost["agvPosition"]["positionInitialized"], false);
  EXPECT_FALSE(lost.contains("velocity"));
}

TEST(Vda5050, ConnectionMessageHasItsState) {
  const nlohmann::json m = ConnectionMessage({}, "sup-1", 0, 0, "ONLINE");
  EXPECT_EQ(m["connectionState"], "ONLINE");
  for (const char* key : {"headerId", "timestamp", "version", "manufacturer", "serialNumber"}) {
    EXPECT_TRUE(m.contains(key)) << key;
  }
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
