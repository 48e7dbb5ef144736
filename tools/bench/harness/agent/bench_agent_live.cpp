// The live-camera agent benchmark: drive, serve, track, compare.
#include "harness/agent/bench_agent_live.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "camera_io/camera_source.h"
#include "harness/common/bench_paths.h"
#include "io/file_util.h"
#include "live_sim/live_vehicle_sim.h"
#include "runtime/child_process.h"
#include "support/floor_images.h"
#include "support/tracker_summary.h"
#include "tracker_agent/ros_bridge.h"
#include "transport/pose_messages.h"
#include "transport/ros_messages.h"
#include "transport/topic_names.h"
#include "transport/vehicle_streams.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;
using PoseMsg = geometry_msgs_msg_dds__PoseWithCovarianceStamped_;

// The drive as a run directory (frames at their planned times) for the offline tracker.
Result<run_io::Run> WriteDriveRun(live_sim::PlannedDrive& drive, const std::string& dir) {
  run_io::Run run;
  run.dir = dir;
  run.vehicle_id = "bench";
  run.camera = drive.camera();
  run.initial_pose = drive.sim().truth().front().pose;
  run.initial_sigma = drive.sim().initial_sigma();
  run.odometry = drive.odometry();
  run.truth = drive.sim().truth();
  fs::create_directories(fs::path(dir) / "frames");
  for (int i = 0; i < drive.frame_count(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frames/frame_%05d.png", i);
    if (!cv::imwrite((fs::path(dir) / name).string(), drive.image(i)))
      return Internal("cannot write " + std::string(name));
    run.frames.push_back({drive.frame_t(i), fs::path(dir) / name});
  }
  FLEETLOC_RETURN_IF_ERROR(run_io::WriteRun(run));
  return run;
}

// The agent's configuration: the fake camera through the Aravis source or through aravissrc.
nlohmann::json AgentConfig(const LiveAgentBenchSettings& s, const std::string& work) {
  nlohmann::json config = {{"vehicle_id", "bench"},
                           {"domain", s.domain},
                           {"source", s.source},
                           {"camera", work + "/live_run/camera.json"},
                           {"outbox", work + "/live_outbox.db"},
                           {"drain_s", 0.0},
                           {"live", {{"odometry_extrapolation_s", s.odometry_extrapolation_s}}}};
  if (s.source == "aravis") {
    config["aravis"] = {
        {"device", "127.0.0.1"}, {"region", {0, 0, 640, 480}}, {"frame_rate_hz", s.rate_hz}};
  } else {  // aravissrc's PTS: the camera's clock, or the buffer's creation (do-timestamp)
    const bool device = s.gstreamer_timestamps == "device";
    config["gstreamer"] = {
        {"pipeline", std::string("aravissrc camera-name=127.0.0.1") +
                         (device ? "" : " do-timestamp=true") +
                         " ! video/x-raw,format=GRAY8,width=640,height=480,framerate=" +
                         std::to_string(static_cast<int>(s.rate_hz)) +
                         "/1 ! appsink max-buffers=2 drop=true sync=false"},
        {"timestamps", device ? "device" : "buffer"}};
  }
  return config;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double Rms(const std::vector<double>& errors) {
  double sum = 0;
  for (double e : errors) sum += e * e;
  return errors.empty() ? 0.0 : std::sqrt(sum / errors.size());
}

// The mosaic served, the drive rendered ahead of its start and written as a run for the offline
// tracker.
struct PreparedDrive {
  std::string mosaic;
  std::unique_ptr<live_sim::PlannedDrive> drive;
  run_io::Run run;
  double start = 0;  // host time of the drive's first frame
};

Result<PreparedDrive> PrepareDrive(const LiveAgentBenchSettings& s, const std::string& work) {
  Result<std::string> mosaic =
      EnsureDemoMosaic(work, "rock_dirt_2048.png", "agent_bench_mosaic.db");
  if (!mosaic.ok()) return mosaic.status();
  // The floor the mosaic was imported from: the demo image itself.
  Result<cv::Mat> floor =
      run_io::ReadGrayImage(fleetctl::DefaultFloorsDir() / "rock_dirt_2048.png");
  if (!floor.ok()) return floor.status();
  const double warmup_s = 3.0 + s.frames * 0.02;  // rendering ahead
  const double start = std::ceil(camera_io::HostNow() + warmup_s);
  spdlog::info("bench agent ({}): rendering {} frames at {} Hz", s.source, s.frames, s.rate_hz);
  auto drive =
      live_sim::PlannedDrive::Create(*floor, 0.0005, s.frames, s.rate_hz, start, 2.0, 1000.0, 20);
  if (!drive.ok()) return drive.status();
  live_sim::PlannedDrive& d = **drive;
  if (camera_io::HostNow() > start)
    return Internal("rendering took longer than planned; use fewer --frames");
  Result<run_io::Run> run = WriteDriveRun(d, work + "/live_run");
  if (!run.ok()) return run.status();
  return PreparedDrive{*mosaic, std::move(drive).value(), std::move(run).value(), start};
}

// What the vehicle heard while it drove: the ROS 2 poses by stamp, and the agent's own pose
// stream (which carries the lock state).
struct HeardPoses {
  std::map<double, geometry::Pose2> poses;
  std::vector<transport::PoseReport> reports;
};

// Drives the vehicle past the running agent: the start pose (as RViz's "2D Pose Estimate") while
// it stands, then odometry and the fake camera; the poses heard meanwhile. The agent and the map
// server are stopped at the end.
Result<HeardPoses> DriveAndListen(const LiveAgentBenchSettings& s, live_sim::PlannedDrive& d,
                                  double start, runtime::ChildProcess& agent,
                                  runtime::ChildProcess& server) {
  auto participant = transport::Participant::Create(s.domain);
  if (!participant.ok()) return participant.status();
  const transport::Participant& p = *participant;
  auto pose_topic = transport::Topic<PoseMsg>::Create(p, "rt/fleetloc/pose");
  if (!pose_topic.ok()) return pose_topic.status();
  auto pose_reader =
      transport::Reader<PoseMsg>::Create(p.get(), *pose_topic, tracker_agent::RosDefaultQos(5000));
  auto init_topic = transport::Topic<PoseMsg>::Create(p, "rt/initialpose");
  if (!pose_reader.ok() || !init_topic.ok()) return Internal("bench agent: DDS readers");
  auto init_writer =
      transport::Writer<PoseMsg>::Create(p.get(), *init_topic, tracker_agent::RosDefaultQos());
  if (!init_writer.ok()) return init_writer.status();
  // The agent's own pose stream carries the lock state (the ROS 2 pose does not): every pose it
  // publishes, frame-time and odometry-rate, is checked against the truth by state.
  auto fleet_topic =
      transport::Topic<fleetloc_VehiclePose>::Create(p, transport::topics::kVehiclePose);
  if (!fleet_topic.ok()) return fleet_topic.status();
  auto fleet_reader = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      p, *fleet_topic, transport::Qos().Reliable().Volatile().KeepLast(5000));
  if (!fleet_reader.ok()) return fleet_reader.status();
  HeardPoses heard;
  auto take = [&] {
    (void)pose_reader->TakeAll([&](const PoseMsg& m, const dds_sample_info_t&) {
      const transport::RosPoseStamped pose = transport::FromIdl(m);
      heard.poses[pose.t] = pose.pose.pose;
    });
    (void)fleet_reader->TakeAll([&](const fleetloc_VehiclePose& m, const dds_sample_info_t&) {
      heard.reports.push_back(transport::FromIdl(m));
    });
  };
  {
    auto odometry = live_sim::OdometryPublisher::Create(p, d.odometry());
    if (!odometry.ok()) return odometry.status();
    // The start pose while the vehicle stands (as RViz's "2D Pose Estimate"), then the camera.
    const double t0 = start + 0.1;
    live_sim::SleepUntilHost(t0);
    for (int i = 0; i < 100 && init_writer->MatchedReaders() == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const Eigen::Vector3d sigma = d.sim().initial_sigma();
    const transport::RosPoseMessage initial(
        t0, "map", {d.TruthAt(t0), sigma.cwiseProduct(sigma).asDiagonal()});
    FLEETLOC_RETURN_IF_ERROR(init_writer->Write(initial.get()));
    live_sim::SleepUntilHost(start + 0.2);
    live_sim::FakeGigECamera camera(&d, start - 100.0);
    while (!(*odometry)->done()) {
      take();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    take();
  }
  agent.Stop(SIGTERM);
  server.Stop(SIGTERM);
  return heard;
}

// The live run against the truth and the offline tracker.
struct LiveOutcome {
  nlohmann::json summary;                              // the agent's --summary
  std::vector<double> live_errors;                     // of the frames' ROS 2 poses, m
  double stamp_offset_ms = 0;                          // median pose stamp − true capture time
  nlohmann::json by_state = nlohmann::json::object();  // the agent's pose stream by lock state
  long long false_locks = 0;
  replay::Accuracy accuracy;       // the offline tracker's
  double live_rms = 0, ratio = 0;  // live, and live / offline
};

// The frames' ROS 2 poses against the truth: errors, and the stamps' median offset.
void CompareFramePoses(const std::map<double, geometry::Pose2>& poses, live_sim::PlannedDrive& d,
                       LiveOutcome* o) {
  std::vector<double> stamp_offsets;
  for (const auto& [t, pose] : poses) {
    const int i = d.FrameAt(t);
    if (std::abs(t - d.frame_t(i)) > 0.02) continue;  // the initial pose
    const geometry::Pose2& truth = d.sim().truth()[i].pose;
    o->live_errors.push_back(std::hypot(pose.x - truth.x, pose.y - truth.y));
    stamp_offsets.push_back(t - d.frame_t(i));  // the pose's stamp minus the true capture time
  }
  o->stamp_offset_ms = Median(stamp_offsets) * 1000.0;
}

// Lock states vs truth: a frame's pose against the truth of the planned frame nearest its
// stamp, an odometry-rate pose against the truth at its time. A tracked or relocalized frame pose
// more than kFalseLockM from the truth is a false lock.
constexpr double kFalseLockM = 0.002;

// The agent's pose stream against the truth, by lock state (and written to
// live_poses_vs_truth.csv).
void CompareLockStates(const HeardPoses& heard, live_sim::PlannedDrive& d, const std::string& work,
                       LiveOutcome* o) {
  const std::map<double, geometry::Pose2>& poses = heard.poses;
  nlohmann::json& by_state = o->by_state;
  std::string pose_log = "t,state,frame,stamp_minus_frame_s,at_frame,error_m,error_shifted_m\n";
  // An odometry-rate pose is propagated from the last frame's pose, which is the truth at the
  // frame's true capture but stamped (stamp − capture) later: it is also compared with the truth
  // that much earlier (error_shifted_m), which it matches when its error is the stamp's.
  double frame_stamp_offset_s = 0.0;
  for (const transport::PoseReport& r : heard.reports) {
    // A frame's pose (not an odometry-rate one): the ROS 2 pose topic has it too (every state
    // but lost), or it is lost (published at frame times only).
    const int i = d.FrameAt(r.t);
    const auto ros = poses.lower_bound(r.t - 2e-6);
    const bool at_frame = r.state == tracking::LockState::kLost ||
                          (ros != poses.end() && std::abs(ros->first - r.t) < 2e-6);
    const geometry::Pose2 truth = at_frame ? d.sim().truth()[i].pose : d.TruthAt(r.t);
    const double error = std::hypot(r.base_in_map.pose.x - truth.x, r.base_in_map.pose.y - truth.y);
    if (at_frame) {  // frames shown while the vehicle stands before the drive have no planned time
      frame_stamp_offset_s = std::abs(r.t - d.frame_t(i)) < 0.02 ? r.t - d.frame_t(i) : 0.0;
    }
    const geometry::Pose2 shifted = at_frame ? truth : d.TruthAt(r.t - frame_stamp_offset_s);
    const double error_shifted =
        std::hypot(r.base_in_map.pose.x - shifted.x, r.base_in_map.pose.y - shifted.y);
    const std::string key =
        std::string(tracking::LockStateName(r.state)) + (at_frame ? "" : "_propagated");
    nlohmann::json& e = by_state[key];
    if (e.is_null()) e = {{"poses", 0}, {"max_error_m", 0.0}, {"over_1px", 0}};
    e["poses"] = e.value("poses", 0) + 1;
    e["max_error_m"] = std::max(e.value("max_error_m", 0.0), error);
    e["mean_error_m"] = e.value("mean_error_m", 0.0) +
                        (error - e.value("mean_error_m", 0.0)) / e["poses"].get<double>();
    e["max_error_shifted_m"] = std::max(e.value("max_error_shifted_m", 0.0), error_shifted);
    if (error > 0.0005) e["over_1px"] = e.value("over_1px", 0) + 1;
    if (at_frame && error > kFalseLockM &&
        (r.state == tracking::LockState::kTracking ||
         r.state == tracking::LockState::kRelocalized)) {
      ++o->false_locks;
      spdlog::warn("false lock: {} pose at t={:.3f} is {:.1f} mm from the truth",
                   tracking::LockStateName(r.state), r.t, error * 1000);
    }
    pose_log +=
        fmt::format("{:.6f},{},{},{:.6f},{},{:.6f},{:.6f}\n", r.t, tracking::LockStateName(r.state),
                    i, r.t - d.frame_t(i), at_frame ? 1 : 0, error, error_shifted);
  }
  (void)io::WriteFileAtomically(work + "/live_poses_vs_truth.csv", pose_log);
}

// The capture-to-pose latency: overall, after the first poses, the first ones and by stage.
void PrintLatency(const nlohmann::json& latency, double p50, double p99, double stamp_offset_ms) {
  std::printf("capture -> pose on the wire: p50 %.2f ms, p99 %.2f ms (%lld poses)\n", p50, p99,
              latency["frames"].get<long long>());
  std::printf("  after the first %lld poses: p50 %.2f ms, p99 %.2f ms (%lld poses)\n",
              latency["steady"]["after_poses"].get<long long>(),
              latency["steady"]["p50"].get<double>(), latency["steady"]["p99"].get<double>(),
              latency["steady"]["frames"].get<long long>());
  std::printf("  the first poses:");
  for (const double ms : latency["first_ms"]) std::printf(" %.1f", ms);
  std::printf(" ms\n");
  std::printf("  by stage, p50 / p99:");
  for (const char* stage : {"camera", "input", "before_cycle", "cycle_and_publish"}) {
    const nlohmann::json& v = latency["stages"][stage];
    std::printf(" %s %.2f / %.2f ms;", stage, v["p50"].get<double>(), v["p99"].get<double>());
  }
  std::printf(
      "\npose stamp - true capture time: median %.2f ms (latency above is from the stamp; "
      "from the true capture: p50 %.2f ms, p99 %.2f ms after the first poses)\n",
      stamp_offset_ms, latency["steady"]["p50"].get<double>() + stamp_offset_ms,
      latency["steady"]["p99"].get<double>() + stamp_offset_ms);
}

void PrintOutcome(const LiveAgentBenchSettings& s, const LiveOutcome& o, size_t reports) {
  const nlohmann::json& summary = o.summary;
  const double p50 = summary["capture_to_pose_ms"]["p50"],
               p99 = summary["capture_to_pose_ms"]["p99"];
  const double cycle_p99 = summary["cycle_ms"]["p99"], cycle_median = summary["cycle_ms"]["median"];
  const nlohmann::json& latency = summary["capture_to_pose_ms"];
  std::printf(
      "\nlive vehicle: aravis fake GigE Vision camera 640x480 Mono8 at %.0f Hz read by %s, ROS 2 "
      "odometry, %d frames, odometry extrapolation up to %.0f ms\n",
      s.rate_hz,
      s.source == "aravis"                 ? "the aravis source"
      : s.gstreamer_timestamps == "device" ? "aravissrc (gstreamer, the camera's timestamps)"
                                           : "aravissrc (gstreamer, do-timestamp)",
      s.frames, s.odometry_extrapolation_s * 1000);
  PrintLatency(latency, p50, p99, o.stamp_offset_ms);
  std::printf("frames run on extrapolated odometry: %lld (up to %.2f ms past the newest sample)\n",
              summary["odometry_extrapolation"]["frames"].get<long long>(),
              summary["odometry_extrapolation"]["max_ms"].get<double>());
  const double steady_p99 = latency["steady"]["p99"];
  std::printf(
      "tracker cycle: median %.2f ms, p99 %.2f ms -> latency p99 %s cycle p99 + 3 ms (all frames), "
      "%s (after the first poses)\n",
      cycle_median, cycle_p99, p99 <= cycle_p99 + 3 ? "within" : "NOT within",
      steady_p99 <= cycle_p99 + 3 ? "within" : "NOT within");
  std::printf(
      "position rms vs truth: live %.4f mm over %zu frames, offline %.4f mm over %zu -> "
      "live/offline %.3f\n",
      o.live_rms * 1000, o.live_errors.size(), o.accuracy.position_rms_m * 1000, o.accuracy.frames,
      o.ratio);
  std::printf("frames dropped before tracking: %lld\n",
              summary["input_dropped_frames"].get<long long>());
  std::printf("lock states vs truth (agent pose stream, %zu poses): %s\n", reports,
              o.by_state.dump().c_str());
  std::printf("false locks (tracking/relocalized frame pose > %.0f mm from truth): %lld\n",
              kFalseLockM * 1000, o.false_locks);
}

Status WriteOutcomeJson(const LiveAgentBenchSettings& s, const LiveOutcome& o) {
  const nlohmann::json& summary = o.summary;
  const nlohmann::json out{{"source", s.source},
                           {"gstreamer_timestamps", s.gstreamer_timestamps},
                           {"odometry_extrapolation", summary["odometry_extrapolation"]},
                           {"stamp_offset_ms", o.stamp_offset_ms},
                           {"frames", s.frames},
                           {"rate_hz", s.rate_hz},
                           {"capture_to_pose_ms", summary["capture_to_pose_ms"]},
                           {"cycle_ms", summary["cycle_ms"]},
                           {"live_rms_m", o.live_rms},
                           {"live_frames", o.live_errors.size()},
                           {"offline_rms_m", o.accuracy.position_rms_m},
                           {"live_offline_ratio", o.ratio},
                           {"input_dropped_frames", summary["input_dropped_frames"]},
                           {"lock_states_vs_truth", o.by_state},
                           {"false_locks", o.false_locks}};
  return io::WriteFileAtomically(s.json, out.dump(2) + "\n");
}

}  // namespace

Status RunLiveAgentBench(const LiveAgentBenchSettings& s) {
  const std::string work = io::AbsoluteDir(s.work_dir).string();
  fs::create_directories(work);
  Result<PreparedDrive> prepared = PrepareDrive(s, work);
  if (!prepared.ok()) return prepared.status();
  live_sim::PlannedDrive& d = *prepared->drive;
  const std::string& mosaic = prepared->mosaic;
  const run_io::Run& run = prepared->run;
  auto server = runtime::ChildProcess::Start(
      runtime::ExecutableDir() + "/map_server",
      {"--mosaic", mosaic, "--domain", std::to_string(s.domain)}, work + "/map_server.log");
  if (!server.ok()) return server.status();
  const nlohmann::json config = AgentConfig(s, work);
  FLEETLOC_RETURN_IF_ERROR(io::WriteFileAtomically(work + "/live_agent.json", config.dump(2)));
  const std::string summary_path = work + "/live_agent_summary.json";
  fs::remove(summary_path);
  auto agent = runtime::ChildProcess::Start(
      runtime::ExecutableDir() + "/tracker_agent",
      {"--config", work + "/live_agent.json", "--summary", summary_path}, work + "/live_agent.log");
  if (!agent.ok()) return agent.status();
  Result<HeardPoses> heard = DriveAndListen(s, d, prepared->start, *agent, *server);
  if (!heard.ok()) return heard.status();
  Result<std::string> text = io::ReadFileText(summary_path);
  if (!text.ok()) return text.status();
  LiveOutcome o;
  o.summary = nlohmann::json::parse(*text);
  CompareFramePoses(heard->poses, d, &o);
  CompareLockStates(*heard, d, work, &o);
  spdlog::info("bench agent ({}): offline tracker over the same frames", s.source);
  Result<replay::ReplayResult> offline = fleetctl::TrackOffline(mosaic, run, {}, 256);
  if (!offline.ok()) return offline.status();
  o.accuracy = replay::Evaluate(offline->poses, run.truth, run.camera.model);
  o.live_rms = Rms(o.live_errors);
  o.ratio = o.live_rms / o.accuracy.position_rms_m;
  PrintOutcome(s, o, heard->reports.size());
  if (s.json.empty()) return Status::Ok();
  return WriteOutcomeJson(s, o);
}

}  // namespace fleetloc::bench
