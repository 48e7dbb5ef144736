// The live-vehicle part of the agent configuration: an Aravis and a GStreamer vehicle read with
// their ROS 2 names; missing and unknown fields named; the shipped example configurations load.
#include "tracker_agent/live_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tracker_agent/agent_config.h"

namespace fleetloc::tracker_agent {
namespace {

std::string Write(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("live_config_" + name + ".json");
  std::ofstream(path) << text;
  return path.string();
}

TEST(LiveConfig, AnAravisVehicleWithItsRos2Names) {
  auto c =
      LoadAgentConfig(Write("aravis", R"({"source": "aravis", "camera": "/etc/fleetloc/camera.json",
      "aravis": {"device": "192.168.10.20", "pixel_format": "Mono12", "region": [16, 8, 640, 480],
                 "exposure_us": 800, "gain": 3, "frame_rate_hz": 20, "packet_size": 8192},
      "ros": {"namespace": "robot7", "odom_topic": "wheel/odom", "pose_topic": "/fleetloc/pose"}})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_TRUE(c->ros.enabled);  // on by default for a live source
  EXPECT_EQ(c->live.aravis.device, "192.168.10.20");
  EXPECT_EQ(c->live.aravis.pixel_format, "Mono12");
  EXPECT_EQ(c->live.aravis.region_x, 16);
  EXPECT_EQ(c->live.aravis.region_height, 480);
  EXPECT_EQ(c->live.aravis.exposure_us, 800);
  EXPECT_EQ(c->live.aravis.packet_size, 8192);
  EXPECT_EQ(c->live.odometry_extrapolation_s, 0.02);  // the default: two 100 Hz periods
  EXPECT_EQ(RosTopicName(c->ros.ns, c->ros.odom_topic), "rt/robot7/wheel/odom");
  EXPECT_EQ(RosTopicName(c->ros.ns, c->ros.pose_topic), "rt/fleetloc/pose");  // absolute
  EXPECT_EQ(RosTopicName(c->ros.ns, c->ros.tf_topic), "rt/robot7/tf");
}

TEST(LiveConfig, BadLiveFieldsAreNamed) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"source": "aravis"})", "field 'camera': is required"},
      {R"({"source": "gstreamer", "camera": "c.json"})", "field 'gstreamer.pipeline': is required"},
      {R"({"source": "gstreamer", "camera": "c.json", "gstreamer": {"pipeline": "v4l2src ! fakesink"}})",
       "field 'gstreamer.pipeline': must end in an appsink"},
      {R"({"source": "aravis", "camera": "c.json", "aravis": {"exposure": 5}})",
       "field 'aravis.exposure': unknown option"},
      {R"({"source": "aravis", "camera": "c.json", "aravis": {"pixel_format": "YUV422_8"}})",
       "field 'aravis.pixel_format': YUV422_8 is not supported"},
      {R"({"source": "aravis", "camera": "c.json", "aravis": {"trigger": "Line0", "frame_rate_hz": 10}})",
       "field 'aravis.trigger': excludes frame_rate_hz"},
      {R"({"source": "aravis", "camera": "c.json", "ros": {"enabled": false}})",
       "field 'ros.enabled'"},
      {R"({"source": "aravis", "camera": "c.json", "ros": {"namespace": "/robot7"}})",
       "field 'ros.namespace'"},
      {R"({"source": "aravis", "camera": "c.json", "ros": {"odom_topic": "wheel odom"}})",
       "field 'ros.odom_topic'"},
      {R"({"source": "aravis", "camera": "c.json", "live": {"camera_stall_s": 5, "camera_reopen_s": 1}})",
       "field 'live.camera_reopen_s': must be >= live.camera_stall_s"},
      {R"({"source": "aravis", "camera": "c.json", "live": {"odometry_extrapolation_s": -0.01}})",
       "field 'live.odometry_extrapolation_s'"},
      {R"({"source": "aravis", "camera": "c.json", "live": {"odometry_extrapolation_s": 0.5}})",
       "field 'live.odometry_extrapolation_s': must be 0..0.1 s"},
      {R"({"source": "aravis", "camera": "c.json",
           "live": {"odometry_extrapolation_s": 0.05, "odometry_stale_s": 0.05}})",
       "field 'live.odometry_extrapolation_s': must be < live.odometry_stale_s"},
  };
  int i = 0;
  for (const auto& [text, expected] : cases) {
    auto c = LoadAgentConfig(Write("bad" + std::to_string(i++), text));
    ASSERT_FALSE(c.ok()) << text;
    EXPECT_NE(c.status().message().find(expected), std::string::npos) << c.status().message();
  }
}

TEST(LiveConfig, TheShippedExampleConfigurationsLoad) {
  for (const char* name : {"tracker_agent_aravis.json", "tracker_agent_gstreamer.json"}) {
    auto c = LoadAgentConfig(std::string(FLEETLOC_SOURCE_DIR "/deploy/config/") + name);
    ASSERT_TRUE(c.ok()) << name << ": " << c.status().message();
    EXPECT_TRUE(IsLiveSource(c->source));
  }
}

}  // namespace
}  // namespace fleetloc::tracker_agent
