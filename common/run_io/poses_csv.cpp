// poses.csv (docs/formats.md): the tracker's output, one row per frame.
#include <algorithm>
#include <array>
#include <string_view>

#include "geometry/pose2.h"
#include "io/csv.h"
#include "io/messages.h"
#include "run_io/run.h"

namespace fleetloc::run_io {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kHeader = {"t",   "x",   "y",   "theta", "sxx",    "sxy",
                                          "sxt", "syy", "syt", "stt",   "status", "inliers"};
constexpr std::size_t kCovarianceColumn = 4;  // sxx; the upper triangle follows row by row
constexpr std::size_t kStatusColumn = 10;
constexpr std::size_t kInliersColumn = 11;
constexpr std::array<std::string_view, 4> kStatuses = {"tracking", "coasting", "lost",
                                                       "relocalized"};
// (row, column) of each upper-triangle entry in column order sxx, sxy, sxt, syy, syt, stt.
constexpr std::array<std::array<int, 2>, 6> kUpperTriangle = {
    {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}};

bool IsStatus(std::string_view status) {
  return std::find(kStatuses.begin(), kStatuses.end(), status) != kStatuses.end();
}

Status ReadCovariance(const io::CsvTable& table, const io::CsvRow& row,
                      Eigen::Matrix3d* covariance) {
  for (std::size_t k = 0; k < kUpperTriangle.size(); ++k) {
    const auto [r, c] = kUpperTriangle[k];
    const std::size_t column = kCovarianceColumn + k;
    FLEETLOC_RETURN_IF_ERROR(table.Double(row, column, &(*covariance)(r, c)));
    (*covariance)(c, r) = (*covariance)(r, c);
    if (r == c && (*covariance)(r, c) < 0) {
      return table.Error(row, column, "a variance must not be negative, got " + row.fields[column]);
    }
  }
  return Status::Ok();
}

Status ReadRecord(const io::CsvTable& table, const io::CsvRow& row, PoseRecord* record) {
  FLEETLOC_RETURN_IF_ERROR(table.Double(row, 0, &record->t));
  FLEETLOC_RETURN_IF_ERROR(table.Double(row, 1, &record->pose.x));
  FLEETLOC_RETURN_IF_ERROR(table.Double(row, 2, &record->pose.y));
  FLEETLOC_RETURN_IF_ERROR(table.Double(row, 3, &record->pose.theta));
  record->pose.theta = geometry::WrapAngle(record->pose.theta);
  FLEETLOC_RETURN_IF_ERROR(ReadCovariance(table, row, &record->covariance));
  record->status = row.fields[kStatusColumn];
  if (!IsStatus(record->status)) {
    return table.Error(row, kStatusColumn,
                       "'" + record->status +
                           "' is not one of tracking, coasting, lost, "
                           "relocalized");
  }
  FLEETLOC_RETURN_IF_ERROR(table.Int(row, kInliersColumn, &record->inliers));
  if (record->inliers < 0) return table.Error(row, kInliersColumn, "must not be negative");
  return Status::Ok();
}

}  // namespace

Result<std::vector<PoseRecord>> ReadPosesCsv(const fs::path& path) {
  Result<io::CsvTable> table = io::CsvTable::Read(path, kHeader);
  if (!table.ok()) return table.status();
  std::vector<PoseRecord> records(table->rows().size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    const io::CsvRow& row = table->rows()[i];
    FLEETLOC_RETURN_IF_ERROR(ReadRecord(*table, row, &records[i]));
    if (i > 0) {
      FLEETLOC_RETURN_IF_ERROR(table->CheckAscending(row, 0, records[i - 1].t, records[i].t));
    }
  }
  return records;
}

Status WritePosesCsv(const fs::path& path, const std::vector<PoseRecord>& poses) {
  io::CsvWriter writer(path, kHeader);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const PoseRecord& p = poses[i];
    if (!IsStatus(p.status)) {
      return io::BadField(path, static_cast<int>(i) + 2, "status",
                          "refusing to write the unknown status '" + p.status + "'");
    }
    writer.Number(p.t);
    writer.Number(p.pose.x);
    writer.Number(p.pose.y);
    writer.Number(geometry::WrapAngle(p.pose.theta));
    for (const auto& [r, c] : kUpperTriangle) writer.Number(p.covariance(r, c));
    writer.Text(p.status);
    writer.Int(p.inliers);
    writer.EndRow();
  }
  return writer.Commit();
}

}  // namespace fleetloc::run_io
