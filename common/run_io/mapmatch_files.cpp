// landmarks.csv and points.csv (docs/formats.md; see mapmatch_files.h).
#include "run_io/mapmatch_files.h"

#include <map>

#include "io/csv.h"
#include "mapmatch/map_fit.h"

namespace fleetloc::run_io {
namespace {

// Row i of a table is on line i + 2 (CsvRow::line).
int LineOf(std::size_t row) { return static_cast<int>(row) + 2; }

Status ReadXy(const io::CsvTable& table, const io::CsvRow& row, std::size_t x_column,
              Eigen::Vector2d* xy) {
  FLEETLOC_RETURN_IF_ERROR(table.Double(row, x_column, &xy->x()));
  return table.Double(row, x_column + 1, &xy->y());
}

// InvalidInput naming the later of two rows with the same id or position.
Status CheckUnique(const io::CsvTable& table, const LandmarkMap& map) {
  std::map<std::string, std::size_t> first_row;
  for (std::size_t i = 0; i < map.ids.size(); ++i) {
    const auto [at, inserted] = first_row.emplace(map.ids[i], i);
    if (!inserted) {
      return table.Error(
          table.rows()[i], 0,
          "id '" + map.ids[i] + "' already used on line " + std::to_string(LineOf(at->second)));
    }
  }
  if (const auto duplicate = mapmatch::FindDuplicateLandmarks(map.positions)) {
    return table.Error(
        table.rows()[duplicate->second], 1,
        "landmark at the same position as line " + std::to_string(LineOf(duplicate->first)));
  }
  return Status::Ok();
}

}  // namespace

Result<LandmarkMap> ReadLandmarksCsv(const std::filesystem::path& path) {
  Result<io::CsvTable> table = io::CsvTable::Read(path, {"id", "x", "y"});
  if (!table.ok()) return table.status();
  LandmarkMap map;
  map.ids.reserve(table->rows().size());
  map.positions.resize(table->rows().size());
  for (std::size_t i = 0; i < table->rows().size(); ++i) {
    const io::CsvRow& row = table->rows()[i];
    if (row.fields[0].empty()) return table->Error(row, 0, "empty id");
    map.ids.push_back(row.fields[0]);
    FLEETLOC_RETURN_IF_ERROR(ReadXy(*table, row, 1, &map.positions[i]));
  }
  FLEETLOC_RETURN_IF_ERROR(CheckUnique(*table, map));
  return map;
}

Result<std::vector<Eigen::Vector2d>> ReadPointsCsv(const std::filesystem::path& path) {
  Result<io::CsvTable> table = io::CsvTable::Read(path, {"x", "y"});
  if (!table.ok()) return table.status();
  std::vector<Eigen::Vector2d> points(table->rows().size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    FLEETLOC_RETURN_IF_ERROR(ReadXy(*table, table->rows()[i], 0, &points[i]));
  }
  return points;
}

}  // namespace fleetloc::run_io
