// ReadRun: a whole run directory, each file validated, then the cross-file rules of CONTRACT
// section 4 (odometry covers the frames, truth has one row per frame).
#include <cmath>

#include "io/file_util.h"
#include "io/messages.h"
#include "io/run.h"
#include "io/run_json.h"
#include "io/run_tables.h"

namespace fleetloc::io {
namespace {

namespace fs = std::filesystem;

constexpr double kTruthTimeTolerance_s = 1e-9;

// Line of data row i in any run table (header on line 1, no empty lines before data).
int DataLine(std::size_t row) { return static_cast<int>(row) + 2; }

std::string FrameLocation(const fs::path& frames_csv, std::size_t row, double t) {
  return "frame t=" + FormatDouble(t) + " (" + frames_csv.filename().string() + ":" +
         std::to_string(DataLine(row)) + ")";
}

// At least as many samples as frames, and first/last samples bracketing the frames' time span.
Status CheckOdometryCoversFrames(const Run& run, const fs::path& odometry_csv,
                                 const fs::path& frames_csv) {
  const std::size_t n = run.odometry.size();
  if (n < run.frames.size()) {
    return BadField(odometry_csv, 0, "t",
                    std::to_string(n) + " samples for " + std::to_string(run.frames.size()) +
                        " frames; odometry must be sampled at least as often as frames");
  }
  if (run.odometry.front().t > run.frames.front().t) {
    return BadField(odometry_csv, DataLine(0), "t",
                    "first odometry sample t=" + FormatDouble(run.odometry.front().t) +
                        " is after the first " +
                        FrameLocation(frames_csv, 0, run.frames.front().t) +
                        "; odometry must cover the frames' time span");
  }
  if (run.odometry.back().t < run.frames.back().t) {
    const std::size_t last = run.frames.size() - 1;
    return BadField(odometry_csv, DataLine(n - 1), "t",
                    "last odometry sample t=" + FormatDouble(run.odometry.back().t) +
                        " is before the last " +
                        FrameLocation(frames_csv, last, run.frames.back().t) +
                        "; odometry must cover the frames' time span");
  }
  return Status::Ok();
}

Status CheckTruthMatchesFrames(const Run& run, const fs::path& truth_csv,
                               const fs::path& frames_csv) {
  if (run.truth.size() != run.frames.size()) {
    return BadField(truth_csv, 0, "t",
                    std::to_string(run.truth.size()) + " rows for " +
                        std::to_string(run.frames.size()) + " frames; it needs one row per frame");
  }
  for (std::size_t i = 0; i < run.truth.size(); ++i) {
    if (std::abs(run.truth[i].t - run.frames[i].t) > kTruthTimeTolerance_s) {
      return BadField(truth_csv, DataLine(i), "t",
                      FormatDouble(run.truth[i].t) + " differs from " +
                          FrameLocation(frames_csv, i, run.frames[i].t));
    }
  }
  return Status::Ok();
}

Status ReadTables(Run* run) {
  const fs::path frames_csv = run->dir / "frames.csv";
  Result<std::vector<FrameRef>> frames = ReadFramesCsv(frames_csv, run->dir);
  if (!frames.ok()) return frames.status();
  if (frames->empty()) return BadField(frames_csv, 0, "", "no frames; a run needs at least one");
  run->frames = std::move(*frames);

  const fs::path odometry_csv = run->dir / "odometry.csv";
  Result<std::vector<geometry::StampedPose>> odometry = ReadStampedPosesCsv(odometry_csv);
  if (!odometry.ok()) return odometry.status();
  run->odometry = std::move(*odometry);
  FLEETLOC_RETURN_IF_ERROR(CheckOdometryCoversFrames(*run, odometry_csv, frames_csv));

  const fs::path truth_csv = run->dir / "truth.csv";
  std::error_code ec;
  if (!fs::exists(truth_csv, ec)) return Status::Ok();
  Result<std::vector<geometry::StampedPose>> truth = ReadStampedPosesCsv(truth_csv);
  if (!truth.ok()) return truth.status();
  run->truth = std::move(*truth);
  return CheckTruthMatchesFrames(*run, truth_csv, frames_csv);
}

}  // namespace

Result<Run> ReadRun(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return NotFound(dir.string() + ": not found (run directory)");
  Run run;
  run.dir = AbsoluteDir(dir);
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

}  // namespace fleetloc::io
