// Live-vehicle configuration from JSON: one reader per nested object, unknown keys rejected.
#include "tracker_agent/live_config.h"

#include <set>

namespace fleetloc::tracker_agent {
namespace {

// The nested object `name` of `parent`, its keys checked against `known`.
Result<io::JsonFields> Nested(const io::JsonFields& fields, const nlohmann::json& parent,
                              const char* name, const std::set<std::string>& known) {
  Result<io::JsonFields> nested = fields.Object(name);
  if (!nested.ok()) return nested.status();
  for (const auto& [key, value] : parent.at(name).items()) {
    if (!known.contains(key)) return nested->Error(key, "unknown option");
  }
  return nested;
}

Status ReadInt(const io::JsonFields& f, const char* key, int* out) {
  if (!f.Has(key)) return Status::Ok();
  double value = 0;
  FLEETLOC_RETURN_IF_ERROR(f.NonNegativeNumber(key, &value));
  if (value != static_cast<int>(value)) return f.Error(key, "must be an integer");
  *out = static_cast<int>(value);
  return Status::Ok();
}

Status ReadAravis(const io::JsonFields& fields, const nlohmann::json& parent,
                  camera_io::AravisOptions* o) {
  auto f = Nested(fields, parent, "aravis",
                  {"device", "pixel_format", "region", "exposure_us", "gain", "frame_rate_hz",
                   "trigger", "timestamps", "packet_size", "buffers"});
  if (!f.ok()) return f.status();
  for (const auto& [key, out] : {std::pair{"device", &o->device},
                                 {"pixel_format", &o->pixel_format},
                                 {"trigger", &o->trigger},
                                 {"timestamps", &o->timestamps}}) {
    if (f->Has(key)) FLEETLOC_RETURN_IF_ERROR(f->NonEmptyString(key, out));
  }
  if (f->Has("region")) {
    std::vector<double> r;
    FLEETLOC_RETURN_IF_ERROR(f->Numbers("region", {4}, &r));
    for (double v : r) {
      if (v < 0 || v != static_cast<int>(v))
        return f->Error("region", "must be 4 non-negative integers x, y, width, height");
    }
    o->region_x = static_cast<int>(r[0]);
    o->region_y = static_cast<int>(r[1]);
    o->region_width = static_cast<int>(r[2]);
    o->region_height = static_cast<int>(r[3]);
  }
  for (const auto& [key, out] : {std::pair{"exposure_us", &o->exposure_us},
                                 {"gain", &o->gain},
                                 {"frame_rate_hz", &o->frame_rate_hz}}) {
    if (f->Has(key)) FLEETLOC_RETURN_IF_ERROR(f->NonNegativeNumber(key, out));
  }
  FLEETLOC_RETURN_IF_ERROR(ReadInt(*f, "packet_size", &o->packet_size));
  return ReadInt(*f, "buffers", &o->buffers);
}

Status ReadGstreamer(const io::JsonFields& fields, const nlohmann::json& parent,
                     camera_io::GstOptions* o) {
  auto f = Nested(fields, parent, "gstreamer", {"pipeline", "timestamps", "epoch_s"});
  if (!f.ok()) return f.status();
  if (f->Has("epoch_s")) FLEETLOC_RETURN_IF_ERROR(f->Number("epoch_s", &o->epoch_s));
  if (f->Has("pipeline")) FLEETLOC_RETURN_IF_ERROR(f->NonEmptyString("pipeline", &o->pipeline));
  if (f->Has("timestamps"))
    FLEETLOC_RETURN_IF_ERROR(f->NonEmptyString("timestamps", &o->timestamps));
  return Status::Ok();
}

Status ReadLive(const io::JsonFields& fields, const nlohmann::json& parent, LiveOptions* o) {
  auto f = Nested(fields, parent, "live",
                  {"camera_stall_s", "camera_reopen_s", "odometry_stale_s",
                   "odometry_extrapolation_s", "issue_hold_s", "frame_queue"});
  if (!f.ok()) return f.status();
  if (f->Has("odometry_extrapolation_s")) {
    FLEETLOC_RETURN_IF_ERROR(
        f->NonNegativeNumber("odometry_extrapolation_s", &o->odometry_extrapolation_s));
  }
  for (const auto& [key, out] : {std::pair{"camera_stall_s", &o->camera_stall_s},
                                 {"camera_reopen_s", &o->camera_reopen_s},
                                 {"odometry_stale_s", &o->odometry_stale_s},
                                 {"issue_hold_s", &o->issue_hold_s}}) {
    if (f->Has(key)) FLEETLOC_RETURN_IF_ERROR(f->PositiveNumber(key, out));
  }
  return ReadInt(*f, "frame_queue", &o->frame_queue);
}

Status ReadRos(const io::JsonFields& fields, const nlohmann::json& parent, RosOptions* o) {
  auto f = Nested(
      fields, parent, "ros",
      {"enabled", "namespace", "odom_topic", "pose_topic", "tf_topic", "initialpose_topic",
       "diagnostics_topic", "map_frame", "odom_frame", "base_frame", "odom_history", "publish_tf"});
  if (!f.ok()) return f.status();
  if (f->Has("enabled")) FLEETLOC_RETURN_IF_ERROR(f->Bool("enabled", &o->enabled));
  if (f->Has("publish_tf")) FLEETLOC_RETURN_IF_ERROR(f->Bool("publish_tf", &o->publish_tf));
  for (const auto& [key, out] : {std::pair{"namespace", &o->ns},
                                 {"odom_topic", &o->odom_topic},
                                 {"pose_topic", &o->pose_topic},
                                 {"tf_topic", &o->tf_topic},
                                 {"initialpose_topic", &o->initialpose_topic},
                                 {"diagnostics_topic", &o->diagnostics_topic},
                                 {"map_frame", &o->map_frame},
                                 {"odom_frame", &o->odom_frame},
                                 {"base_frame", &o->base_frame}}) {
    if (f->Has(key)) FLEETLOC_RETURN_IF_ERROR(f->NonEmptyString(key, out));
  }
  return ReadInt(*f, "odom_history", &o->odom_history);
}

bool ValidRosName(const std::string& name, bool allow_leading_slash) {
  if (name.empty()) return false;
  for (size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    const bool slash_ok = c == '/' && (i > 0 || allow_leading_slash) && i + 1 < name.size() &&
                          (i == 0 || name[i - 1] != '/');
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || slash_ok)) return false;
  }
  return true;
}

}  // namespace

std::string RosTopicName(const std::string& ns, const std::string& topic) {
  if (!topic.empty() && topic[0] == '/') return "rt" + topic;
  return ns.empty() ? "rt/" + topic : "rt/" + ns + "/" + topic;
}

Status ValidateLive(const std::string& source, const LiveOptions& live, const RosOptions& ros) {
  auto bad = [](const std::string& field, const std::string& what) {
    return InvalidInput("tracker agent config: field '" + field + "': " + what);
  };
  const bool is_live = source == "aravis" || source == "gstreamer";
  if (is_live && live.camera_path.empty())
    return bad("camera", "is required (camera.json of the live camera)");
  if (source == "aravis") {
    if (Status s = camera_io::Validate(live.aravis); !s.ok())
      return InvalidInput("tracker agent config: " + s.message());
  }
  if (source == "gstreamer") {
    if (live.gstreamer.pipeline.empty())
      return bad("gstreamer.pipeline", "is required (the gstreamer source)");
    if (Status s = camera_io::Validate(live.gstreamer); !s.ok())
      return InvalidInput("tracker agent config: " + s.message());
  }
  if (is_live && !ros.enabled) return bad("ros.enabled", "a live source needs ROS 2 odometry");
  if (live.camera_reopen_s < live.camera_stall_s)
    return bad("live.camera_reopen_s", "must be >= live.camera_stall_s");
  if (live.odometry_extrapolation_s > 0.1)
    return bad("live.odometry_extrapolation_s", "must be 0..0.1 s (about two odometry periods)");
  if (live.odometry_extrapolation_s >= live.odometry_stale_s)
    return bad("live.odometry_extrapolation_s", "must be < live.odometry_stale_s");
  if (live.frame_queue < 1 || live.frame_queue > 64)
    return bad("live.frame_queue", "must be 1..64");
  if (!ros.ns.empty() && !ValidRosName(ros.ns, false))
    return bad("ros.namespace", "must be a ROS name without leading or trailing '/'");
  for (const auto& [field, name] : {std::pair{"ros.odom_topic", &ros.odom_topic},
                                    {"ros.pose_topic", &ros.pose_topic},
                                    {"ros.tf_topic", &ros.tf_topic},
                                    {"ros.initialpose_topic", &ros.initialpose_topic},
                                    {"ros.diagnostics_topic", &ros.diagnostics_topic}}) {
    if (!ValidRosName(*name, true)) return bad(field, "'" + *name + "' is not a ROS topic name");
  }
  if (ros.odom_history < 1 || ros.odom_history > 100000)
    return bad("ros.odom_history", "must be 1..100000");
  return Status::Ok();
}

Status ReadLiveOptions(const io::JsonFields& fields, const nlohmann::json& parent,
                       LiveOptions* live, RosOptions* ros) {
  if (fields.Has("camera"))
    FLEETLOC_RETURN_IF_ERROR(fields.NonEmptyString("camera", &live->camera_path));
  if (fields.Has("live")) FLEETLOC_RETURN_IF_ERROR(ReadLive(fields, parent, live));
  if (fields.Has("aravis")) FLEETLOC_RETURN_IF_ERROR(ReadAravis(fields, parent, &live->aravis));
  if (fields.Has("gstreamer"))
    FLEETLOC_RETURN_IF_ERROR(ReadGstreamer(fields, parent, &live->gstreamer));
  if (fields.Has("ros")) FLEETLOC_RETURN_IF_ERROR(ReadRos(fields, parent, ros));
  return Status::Ok();
}

}  // namespace fleetloc::tracker_agent
