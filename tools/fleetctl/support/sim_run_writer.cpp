// Simulated run writer: frames rendered on this thread and encoded on a second one, then the
// run's tables.
#include "support/sim_run_writer.h"

#include <chrono>
#include <cstdio>
#include <future>
#include <opencv2/imgcodecs.hpp>
#include <vector>

namespace fleetloc::fleetctl {
namespace {

namespace fs = std::filesystem;

Status WriteFrame(const fs::path& path, const cv::Mat& image) {
  try {
    if (cv::imwrite(path.string(), image, {cv::IMWRITE_PNG_COMPRESSION, 1})) return Status::Ok();
  } catch (const cv::Exception& e) {
    return Internal(path.string() + ": cannot write frame: " + e.err);
  }
  return Internal(path.string() + ": cannot write frame");
}

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Renders and writes every frame; returns their references for frames.csv. PNG encoding takes
// about as long as rendering, so frame i is written on a second thread while frame i + 1 renders.
Result<std::vector<run_io::FrameRef>> WriteFrames(sim::RunSimulator& simulator, const fs::path& dir,
                                                  const FrameProgress& progress,
                                                  FrameTimes* times) {
  std::vector<run_io::FrameRef> frames;
  std::future<Status> writing;
  auto wait_for_write = [&]() -> Status {
    if (!writing.valid()) return Status::Ok();
    const auto start = std::chrono::steady_clock::now();
    Status written = writing.get();
    times->write_wait_ms += MillisecondsSince(start);
    return written;
  };
  for (int i = 0; i < simulator.frame_count(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "frames/%06d.png", i);
    const auto start = std::chrono::steady_clock::now();
    sim::RenderedFrame frame = simulator.RenderFrame(i);
    times->render_ms += MillisecondsSince(start);
    FLEETLOC_RETURN_IF_ERROR(wait_for_write());
    writing = std::async(std::launch::async, [path = dir / name, image = std::move(frame.image)] {
      return WriteFrame(path, image);
    });
    frames.push_back({simulator.truth()[i].t, dir / name});
    if (progress) progress(i + 1, simulator.frame_count());
  }
  FLEETLOC_RETURN_IF_ERROR(wait_for_write());
  return frames;
}

}  // namespace

run_io::CameraFile DefaultSimCamera(int width_px, int height_px, double resolution_m) {
  run_io::CameraFile camera;
  camera.model = sim::DefaultSimCameraModel(width_px, height_px, resolution_m);
  return camera;
}

Status PrepareRunDir(const fs::path& dir, bool overwrite) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec)) {
    if (!overwrite) {
      return InvalidInput(dir.string() + ": exists and is not empty (use --overwrite)");
    }
    for (const char* name :
         {"run.json", "camera.json", "frames.csv", "odometry.csv", "truth.csv"}) {
      fs::remove(dir / name, ec);
    }
    fs::remove_all(dir / "frames", ec);
  }
  fs::create_directories(dir / "frames", ec);
  if (ec) return Internal(dir.string() + ": cannot create the run directory: " + ec.message());
  return Status::Ok();
}

Result<run_io::Run> WriteSimulatedRun(sim::RunSimulator& simulator,
                                      const run_io::CameraFile& camera, const fs::path& dir,
                                      const std::string& vehicle_id, const FrameProgress& progress,
                                      FrameTimes* times) {
  FrameTimes ignored;
  Result<std::vector<run_io::FrameRef>> frames =
      WriteFrames(simulator, dir, progress, times ? times : &ignored);
  if (!frames.ok()) return frames.status();
  run_io::Run run;
  run.dir = dir;
  run.vehicle_id = vehicle_id;
  run.camera = camera;
  run.initial_pose = simulator.initial_pose();
  run.initial_sigma = simulator.initial_sigma();
  run.frames = std::move(*frames);
  run.odometry = simulator.odometry();
  run.truth = simulator.truth();
  FLEETLOC_RETURN_IF_ERROR(run_io::WriteRun(run));
  return run;
}

}  // namespace fleetloc::fleetctl
