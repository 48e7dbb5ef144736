// ReadRun: a whole run directory, each file validated, then the cross-file rules of
// docs/formats.md, runs (odometry covers the frames of both cameras, truth has one row per frame).
#include <cmath>

#include "io/file_util.h"
#include "io/messages.h"
#include "run_io/forward_camera_json.h"
#include "run_io/run.h"
#include "run_io/run_json.h"
#include "run_io/run_tables.h"

namespace fleetloc::run_io {
namespace {

namespace fs = std::filesystem;

constexpr double kTruthTimeTolerance_s = 1e-9;

// Line of data row i in any run table (header on line 1, no empty lines before data).
int DataLine(std::size_t row) { return static_cast<int>(row) + 2; }

std::string FrameLocation(const fs::path& frames_csv, std::size_t row, double t) {
  return "frame t=" + io::FormatDouble(t) + " (" + frames_csv.filename().string() + ":" +
         std::to_string(DataLine(row)) + ")";
}

// At least as many samples as frames, and first/last samples bracketing the frames' time span.
Status CheckOdometryCoversFrames(const std::vector<geometry::StampedPose>& odometry,
                                 const fs::path& odometry_csv, const std::vector<FrameRef>& frames,
                                 const fs::path& frames_csv) {
  if (frames.empty()) return Status::Ok();
  const std::size_t n = odometry.size();
  if (n < frames.size()) {
    return io::BadField(odometry_csv, 0, "t",
                        std::to_string(n) + " samples for " + std::to_string(frames.size()) +
                            " frames of " + frames_csv.filename().string() +
                            "; odometry must be sampled at least as often as frames");
  }
  if (odometry.front().t > frames.front().t) {
    return io::BadField(odometry_csv, DataLine(0), "t",
                        "first odometry sample t=" + io::FormatDouble(odometry.front().t) +
                            " is after the first " +
                            FrameLocation(frames_csv, 0, frames.front().t) +
                            "; odometry must cover the frames' time span");
  }
  if (odometry.back().t < frames.back().t) {
    const std::size_t last = frames.size() - 1;
    return io::BadField(odometry_csv, DataLine(n - 1), "t",
                        "last odometry sample t=" + io::FormatDouble(odometry.back().t) +
                            " is before the last " +
                            FrameLocation(frames_csv, last, frames.back().t) +
                            "; odometry must cover the frames' time span");
  }
  return Status::Ok();
}

// An optional truth table: absent (left empty), or one row per frame at the frame's time.
Status ReadTruthOfFrames(const fs::path& truth_csv, const std::vector<FrameRef>& frames,
                         const fs::path& frames_csv, std::vector<geometry::StampedPose>* truth) {
  std::error_code ec;
  if (!fs::exists(truth_csv, ec)) return Status::Ok();
  Result<std::vector<geometry::StampedPose>> read = ReadStampedPosesCsv(truth_csv);
  if (!read.ok()) return read.status();
  *truth = std::move(*read);
  if (truth->size() != frames.size()) {
    return io::BadField(truth_csv, 0, "t",
                        std::to_string(truth->size()) + " rows for " +
                            std::to_string(frames.size()) + " frames; it needs one row per frame");
  }
  for (std::size_t i = 0; i < truth->size(); ++i) {
    if (std::abs((*truth)[i].t - frames[i].t) > kTruthTimeTolerance_s) {
      return io::BadField(truth_csv, DataLine(i), "t",
                          io::FormatDouble((*truth)[i].t) + " differs from " +
                              FrameLocation(frames_csv, i, frames[i].t));
    }
  }
  return Status::Ok();
}

// forward/ (docs/formats.md): forward_camera.json, forward.csv and, in simulated runs, truth.csv.
Result<std::optional<ForwardStream>> ReadForwardStream(const fs::path& run_dir) {
  const fs::path dir = run_dir / "forward";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return std::optional<ForwardStream>();
  ForwardStream forward;
  Result<mapmatch::ForwardCameraParams> camera = ReadForwardCameraJson(dir / "forward_camera.json");
  if (!camera.ok()) return camera.status();
  forward.camera = *camera;
  const fs::path forward_csv = dir / "forward.csv";
  Result<std::vector<FrameRef>> frames = ReadFramesCsv(forward_csv, dir);
  if (!frames.ok()) return frames.status();
  forward.frames = std::move(*frames);
  FLEETLOC_RETURN_IF_ERROR(
      ReadTruthOfFrames(dir / "truth.csv", forward.frames, forward_csv, &forward.truth));
  return std::optional<ForwardStream>(std::move(forward));
}

Status ReadTables(Run* run) {
  Result<std::optional<ForwardStream>> forward = ReadForwardStream(run->dir);
  if (!forward.ok()) return forward.status();
  run->forward = std::move(*forward);
  const fs::path frames_csv = run->dir / "frames.csv";
  Result<std::vector<FrameRef>> frames = ReadFramesCsv(frames_csv, run->dir);
  if (!frames.ok()) return frames.status();
  if (frames->empty() && (!run->forward || run->forward->frames.empty())) {
    return io::BadField(frames_csv, 0, "",
                        "no frames; a run needs at least one (here or in forward/forward.csv)");
  }
  run->frames = std::move(*frames);

  const fs::path odometry_csv = run->dir / "odometry.csv";
  Result<std::vector<geometry::StampedPose>> odometry = ReadStampedPosesCsv(odometry_csv);
  if (!odometry.ok()) return odometry.status();
  run->odometry = std::move(*odometry);
  FLEETLOC_RETURN_IF_ERROR(
      CheckOdometryCoversFrames(run->odometry, odometry_csv, run->frames, frames_csv));
  if (run->forward) {
    FLEETLOC_RETURN_IF_ERROR(CheckOdometryCoversFrames(
        run->odometry, odometry_csv, run->forward->frames, run->dir / "forward" / "forward.csv"));
  }
  return ReadTruthOfFrames(run->dir / "truth.csv", run->frames, frames_csv, &run->truth);
}

}  // namespace

Result<Run> ReadRun(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return NotFound(dir.string() + ": not found (run directory)");
  Run run;
  run.dir = io::AbsoluteDir(dir);
  Result<RunJson> run_json = ReadRunJson(run.dir / "run.json");
  if (!run_json.ok()) return run_json.status();
  run.vehicle_id = run_json->vehicle_id;
  run.initial_pose = run_json->initial_pose;
  run.initial_sigma = run_json->initial_sigma;
  Result<CameraFile> camera = ReadCameraJson(run.dir / run_json->camera);
  if (!camera.ok()) return camera.status();
  run.camera = *camera;
  FLEETLOC_RETURN_IF_ERROR(ReadTables(&run));
  return run;
}

}  // namespace fleetloc::run_io
