// WriteRun: a run directory in the layout of docs/formats.md
#include "io/file_util.h"
#include "run_io/run.h"
#include "run_io/run_json.h"
#include "run_io/run_tables.h"

namespace fleetloc::run_io {

namespace fs = std::filesystem;

Status WriteRun(const Run& run) {
  if (run.dir.empty()) return InvalidInput("WriteRun: the run has no directory");
  const fs::path dir = io::AbsoluteDir(run.dir);
  FLEETLOC_RETURN_IF_ERROR(WriteCameraJson(dir / "camera.json", run.camera));
  FLEETLOC_RETURN_IF_ERROR(WriteFramesCsv(dir / "frames.csv", run.frames, dir));
  FLEETLOC_RETURN_IF_ERROR(WriteStampedPosesCsv(dir / "odometry.csv", run.odometry));
  const fs::path truth_csv = dir / "truth.csv";
  if (!run.truth.empty()) {
    FLEETLOC_RETURN_IF_ERROR(WriteStampedPosesCsv(truth_csv, run.truth));
  } else {
    // A truth.csv left from an earlier run in this directory would no longer match it.
    std::error_code ec;
    fs::remove(truth_csv, ec);
    if (ec) return Internal(truth_csv.string() + ": cannot remove stale file: " + ec.message());
  }
  // run.json last: a directory with run.json in it is a complete run.
  RunJson run_json;
  run_json.vehicle_id = run.vehicle_id;
  run_json.initial_pose = run.initial_pose;
  run_json.initial_sigma = run.initial_sigma;
  return WriteRunJson(dir / "run.json", run_json);
}

}  // namespace fleetloc::run_io
