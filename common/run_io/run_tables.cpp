// frames.csv, odometry.csv and truth.csv: reading with validation, writing round-trip exact.
#include "run_io/run_tables.h"

#include "io/csv.h"
#include "io/file_util.h"
#include "io/messages.h"

namespace fleetloc::run_io {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kFramesHeader = {"t", "file"};
const std::vector<std::string> kPosesHeader = {"t", "x", "y", "theta"};

// Parses field 0 of every row as the time stamp and checks it is strictly ascending.
Status ReadTimes(const io::CsvTable& table, std::vector<double>* times) {
  times->resize(table.rows().size());
  for (std::size_t i = 0; i < table.rows().size(); ++i) {
    const io::CsvRow& row = table.rows()[i];
    FLEETLOC_RETURN_IF_ERROR(table.Double(row, 0, &(*times)[i]));
    if (i > 0) FLEETLOC_RETURN_IF_ERROR(table.CheckAscending(row, 0, (*times)[i - 1], (*times)[i]));
  }
  return Status::Ok();
}

Status ResolveFrameFile(const io::CsvTable& table, const io::CsvRow& row, const fs::path& base_dir,
                        fs::path* file) {
  const std::string& name = row.fields[1];
  if (name.empty()) return table.Error(row, 1, "empty, expected an image file name");
  *file = (io::AbsoluteDir(base_dir) / name).lexically_normal();
  std::error_code ec;
  if (!fs::is_regular_file(*file, ec)) {
    return NotFound(io::Where(table.path(), row.line, "file") + "'" + name + "' not found (" +
                    file->string() + ")");
  }
  return Status::Ok();
}

}  // namespace

Result<std::vector<FrameRef>> ReadFramesCsv(const fs::path& path, const fs::path& base_dir) {
  Result<io::CsvTable> table = io::CsvTable::Read(path, kFramesHeader);
  if (!table.ok()) return table.status();
  std::vector<double> times;
  FLEETLOC_RETURN_IF_ERROR(ReadTimes(*table, &times));
  std::vector<FrameRef> frames(times.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    frames[i].t = times[i];
    FLEETLOC_RETURN_IF_ERROR(ResolveFrameFile(*table, table->rows()[i], base_dir, &frames[i].file));
  }
  return frames;
}

Status WriteFramesCsv(const fs::path& path, const std::vector<FrameRef>& frames,
                      const fs::path& base_dir) {
  const fs::path base = io::AbsoluteDir(base_dir);
  io::CsvWriter writer(path, kFramesHeader);
  for (const FrameRef& frame : frames) {
    const fs::path file = frame.file.is_absolute()
                              ? frame.file.lexically_normal().lexically_relative(base)
                              : frame.file;
    if (file.empty()) {
      return InvalidInput(path.string() + ": cannot write frame file " + frame.file.string() +
                          " relative to " + base.string());
    }
    writer.Number(frame.t);
    writer.Text(file.generic_string());
    writer.EndRow();
  }
  return writer.Commit();
}

Result<std::vector<geometry::StampedPose>> ReadStampedPosesCsv(const fs::path& path) {
  Result<io::CsvTable> table = io::CsvTable::Read(path, kPosesHeader);
  if (!table.ok()) return table.status();
  std::vector<double> times;
  FLEETLOC_RETURN_IF_ERROR(ReadTimes(*table, &times));
  std::vector<geometry::StampedPose> poses(times.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const io::CsvRow& row = table->rows()[i];
    geometry::StampedPose& p = poses[i];
    p.t = times[i];
    FLEETLOC_RETURN_IF_ERROR(table->Double(row, 1, &p.pose.x));
    FLEETLOC_RETURN_IF_ERROR(table->Double(row, 2, &p.pose.y));
    FLEETLOC_RETURN_IF_ERROR(table->Double(row, 3, &p.pose.theta));
    p.pose.theta = geometry::WrapAngle(p.pose.theta);
  }
  return poses;
}

Status WriteStampedPosesCsv(const fs::path& path, const std::vector<geometry::StampedPose>& poses) {
  io::CsvWriter writer(path, kPosesHeader);
  for (const geometry::StampedPose& p : poses) {
    writer.Number(p.t);
    writer.Number(p.pose.x);
    writer.Number(p.pose.y);
    writer.Number(geometry::WrapAngle(p.pose.theta));
    writer.EndRow();
  }
  return writer.Commit();
}

}  // namespace fleetloc::run_io
