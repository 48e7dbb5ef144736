// fleetctl sim-forward: a simulated forward-camera drive down a corridor (docs/forward_camera.md) —
// a run without downward frames (docs/formats.md: run.json, camera.json, an empty frames.csv and
// the drive's drifting odometry.csv) with its `forward/` directory (forward_camera.json,
// forward.csv, images, the truth at each image) and the corridor's landmarks.csv (docs/formats.md),
// for end-to-end tests of the global position update.
#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "commands.h"
#include "io/file_util.h"
#include "io/messages.h"
#include "run_io/forward_camera_json.h"
#include "run_io/run_tables.h"
#include "sim/forward_renderer.h"
#include "sim/forward_run.h"
#include "sim/random.h"
#include "support/sim_run_writer.h"

namespace fleetloc::fleetctl {
namespace {

namespace fs = std::filesystem;

struct SimForwardArgs {
  std::string out;
  std::string vehicle_id = "agv-1";
  std::string
      camera;  // forward_camera.json to use; default: a 640×480 camera 1 m up, 0.25 rad down
  bool overwrite = false;
  sim::ForwardRunOptions run;
};

mapmatch::ForwardCameraParams DefaultForwardCamera() {
  mapmatch::ForwardCameraParams p;
  p.K = {520, 0, 320, 0, 520, 240, 0, 0, 1};
  p.dist = {-0.08, 0.01, 0, 0, 0};
  p.mount = {.x_m = 0.45, .y_m = 0.0, .height_m = 1.0, .yaw_rad = 0.0, .pitch_rad = 0.25};
  return p;
}

// Empty or new, or (overwrite) a run written before: its forward/ and landmarks.csv are removed,
// the run's own files are rewritten.
Status PrepareForwardDir(const fs::path& dir, bool overwrite) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec)) {
    if (!overwrite)
      return InvalidInput(dir.string() + ": exists and is not empty (use --overwrite)");
    fs::remove_all(dir / "forward", ec);
    fs::remove(dir / "landmarks.csv", ec);
  }
  fs::create_directories(dir / "forward" / "img", ec);
  if (ec) return Internal(dir.string() + ": cannot create forward/: " + ec.message());
  return Status::Ok();
}

// The run's own files: no downward frames, the drive's odometry, and the truth at the first image
// as the initial pose (camera.json describes the simulator's downward camera, which saw nothing).
Status WriteForwardOnlyRun(const fs::path& dir, const std::string& vehicle_id,
                           const sim::ForwardRunPlan& plan) {
  run_io::Run run;
  run.dir = dir;
  run.vehicle_id = vehicle_id;
  run.camera = DefaultSimCamera(640, 480, 0.0005);
  run.initial_pose = plan.frame_truth.front().pose;
  run.initial_sigma = {0.01, 0.01, 0.005};
  run.odometry = plan.odometry;
  return run_io::WriteRun(run);
}

Status WriteImage(const fs::path& path, const cv::Mat& image) {
  try {
    if (cv::imwrite(path.string(), image, {cv::IMWRITE_PNG_COMPRESSION, 1})) return Status::Ok();
  } catch (const cv::Exception& e) {
    return Internal(path.string() + ": cannot write image: " + e.err);
  }
  return Internal(path.string() + ": cannot write image");
}

// docs/formats.md: header `id,x,y`, one floor-level corner per row, in map.
Status WriteLandmarksCsv(const fs::path& path, const std::vector<Eigen::Vector2d>& landmarks) {
  std::ostringstream text;
  text << "id,x,y\n";
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    text << i << ',' << io::FormatDouble(landmarks[i].x()) << ','
         << io::FormatDouble(landmarks[i].y()) << '\n';
  }
  return io::WriteFileAtomically(path, text.str());
}

Result<mapmatch::ForwardCameraParams> CameraParams(const SimForwardArgs& a) {
  if (a.camera.empty()) return DefaultForwardCamera();
  return run_io::ReadForwardCameraJson(a.camera);
}

Status RunSimForward(const SimForwardArgs& a) {
  FLEETLOC_RETURN_IF_ERROR(sim::Validate(a.run));
  Result<mapmatch::ForwardCameraParams> params = CameraParams(a);
  if (!params.ok()) return params.status();
  Result<mapmatch::ForwardCamera> camera = mapmatch::ForwardCamera::Create(*params);
  if (!camera.ok()) return camera.status();
  // Absolute: forward.csv names its images relative to forward/, whatever the working directory.
  const fs::path dir = io::AbsoluteDir(a.out), forward = dir / "forward";
  FLEETLOC_RETURN_IF_ERROR(PrepareForwardDir(dir, a.overwrite));
  const sim::CorridorScene scene = sim::BuildCorridorScene(a.run.scene);
  const sim::ForwardRunPlan plan = sim::PlanForwardRun(a.run);
  const sim::ForwardRenderer renderer(*camera, {});
  std::vector<run_io::FrameRef> frames;
  for (std::size_t i = 0; i < plan.frame_truth.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "img/f%05zu.png", i);
    const geometry::StampedPose& truth = plan.frame_truth[i];
    FLEETLOC_RETURN_IF_ERROR(WriteImage(
        forward / name, renderer.Render(scene, truth.pose, sim::MixSeed(a.run.seed, i))));
    frames.push_back({truth.t, forward / name});
    if ((i + 1) % 10 == 0)
      spdlog::info("sim-forward: {} of {} frames", i + 1, plan.frame_truth.size());
  }
  FLEETLOC_RETURN_IF_ERROR(
      run_io::WriteForwardCameraJson(forward / "forward_camera.json", *params));
  FLEETLOC_RETURN_IF_ERROR(run_io::WriteFramesCsv(forward / "forward.csv", frames, forward));
  FLEETLOC_RETURN_IF_ERROR(run_io::WriteStampedPosesCsv(forward / "truth.csv", plan.frame_truth));
  FLEETLOC_RETURN_IF_ERROR(WriteLandmarksCsv(dir / "landmarks.csv", scene.landmarks));
  FLEETLOC_RETURN_IF_ERROR(WriteForwardOnlyRun(dir, a.vehicle_id, plan));
  std::cout << R"({"frames": )" << frames.size() << R"(, "landmarks": )" << scene.landmarks.size()
            << R"(, "forward": ")" << forward.string() << "\"}\n";
  return Status::Ok();
}

}  // namespace

void RegisterSimForwardCommand(CLI::App& app, Status* result) {
  auto a = std::make_shared<SimForwardArgs>();
  CLI::App* cmd = app.add_subcommand(
      "sim-forward",
      "Simulate a forward-camera drive down a corridor: a run with forward/ and landmarks.csv");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--out", a->out, "Run directory to write (new or empty, or see --overwrite)")
      ->required();
  cmd->add_option("--vehicle-id", a->vehicle_id, "run.json's vehicle_id");
  cmd->add_option("--camera", a->camera, "forward_camera.json to simulate (default: built in)");
  cmd->add_flag("--overwrite", a->overwrite,
                "Write over a non-empty directory (its run files, forward/, landmarks.csv)");
  cmd->add_option("--frames", a->run.frames, "Forward frames");
  cmd->add_option("--frame-rate-hz", a->run.frame_rate_hz, "Forward frames per second");
  cmd->add_option("--speed-m-s", a->run.speed_m_s, "Driving speed");
  cmd->add_option("--start-x-m", a->run.start_x_m, "Start along the corridor");
  cmd->add_option("--weave-m", a->run.weave_amplitude_m, "Sideways weave amplitude");
  cmd->add_option("--seed", a->run.seed, "Odometry and image noise");
  cmd->add_option("--scene-seed", a->run.scene.seed, "Corridor layout");
  cmd->callback([a, result] { *result = RunSimForward(*a); });
}

}  // namespace fleetloc::fleetctl
