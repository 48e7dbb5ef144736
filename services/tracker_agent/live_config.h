// The live-vehicle part of the tracker agent's configuration: which camera (an Aravis GenICam
// camera or a GStreamer pipeline) with which camera.json, how long silence may last, and the
// ROS 2 topics (odometry in; pose, map → odom, diagnostics out; initialpose in). JSON objects
// "camera_source", "aravis", "gstreamer" and "ros" of the agent's configuration
// (docs/vehicle_integration.md), unknown keys rejected.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "base/status.h"
#include "camera_io/aravis_camera.h"
#include "camera_io/gst_camera.h"
#include "io/json_fields.h"

namespace fleetloc::tracker_agent {

// ROS 2 names: a topic "x" is "rt/<namespace>/x" on the wire (ROS 2's "rt/" prefix for topics).
struct RosOptions {
  bool enabled = false;  // on for live sources unless "ros": {"enabled": false}
  std::string ns;        // namespace ("" or "robot7"; no leading or trailing '/')
  std::string odom_topic = "odom";
  std::string pose_topic = "fleetloc/pose";
  std::string tf_topic = "tf";
  std::string initialpose_topic = "initialpose";
  std::string diagnostics_topic = "diagnostics";
  std::string map_frame = "map", odom_frame = "odom", base_frame = "base_link";
  int odom_history = 200;  // the odometry reader keeps this many samples unread
  bool publish_tf = true;
};

// The DDS topic name of ROS 2 topic `topic` under `ns` (a topic starting with '/' is absolute).
std::string RosTopicName(const std::string& ns, const std::string& topic);

struct LiveOptions {
  std::string camera_path;  // camera.json (docs/formats.md) of the live camera
  camera_io::AravisOptions aravis;
  camera_io::GstOptions gstreamer;
  double camera_stall_s = 1.0;    // no frame for this long: camera_stalled
  double camera_reopen_s = 3.0;   // ... and for this long: closed and opened again
  double odometry_stale_s = 0.5;  // no odometry for this long: odometry_stale
  // A frame up to this far past the newest odometry sample is tracked at once on odometry
  // extrapolated under constant velocity (its prediction's covariance grown for it) instead of
  // waiting for odometry to cover it; 0: frames always wait. About two odometry periods.
  double odometry_extrapolation_s = 0.02;
  double issue_hold_s = 5.0;  // a bad sample is reported in health for this long
  int frame_queue = 4;        // frames waiting for the tracker; beyond, the oldest drop
};

Status ValidateLive(const std::string& source, const LiveOptions& live, const RosOptions& ros);

// Reads "camera", "live", "aravis", "gstreamer" and "ros" of the agent configuration `parent`
// (its fields view `fields`) into `live` and `ros`.
Status ReadLiveOptions(const io::JsonFields& fields, const nlohmann::json& parent,
                       LiveOptions* live, RosOptions* ros);

}  // namespace fleetloc::tracker_agent
