// The CSV tables of a run (docs/formats.md): `t,file` (frames.csv, forward/forward.csv) and
// `t,x,y,theta` (odometry.csv, truth.csv). Data row i of any of them is on line i + 2.
#pragma once

#include <filesystem>
#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "run_io/run.h"

namespace fleetloc::run_io {

// Reads a `t,file` table: t finite and strictly ascending, each file resolved against `base_dir`
// (FrameRef::file is absolute and normalised) and required to exist. NotFound for a missing table
// or a missing image (naming the line and field 'file'); InvalidInput for any other breach.
Result<std::vector<FrameRef>> ReadFramesCsv(const std::filesystem::path& path,
                                            const std::filesystem::path& base_dir);
// Writes a `t,file` table with each file written relative to `base_dir` ('/' separators).
Status WriteFramesCsv(const std::filesystem::path& path, const std::vector<FrameRef>& frames,
                      const std::filesystem::path& base_dir);

// Reads a `t,x,y,theta` table: every number finite, t strictly ascending, theta wrapped to
// (-pi, pi]. NotFound when missing, InvalidInput naming file, line and field otherwise.
Result<std::vector<geometry::StampedPose>> ReadStampedPosesCsv(const std::filesystem::path& path);
// Writes a `t,x,y,theta` table, theta wrapped, numbers round-trip exact. InvalidInput (nothing
// written) if a number is not finite.
Status WriteStampedPosesCsv(const std::filesystem::path& path,
                            const std::vector<geometry::StampedPose>& poses);

}  // namespace fleetloc::run_io
