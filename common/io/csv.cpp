// Strict CSV reading and round-trip-exact writing.
#include "io/csv.h"

#include <charconv>
#include <cmath>
#include <system_error>

#include "io/file_util.h"
#include "io/messages.h"

namespace fleetloc::io {
namespace {

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma - start));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

std::string_view Trim(std::string_view s) {
  const std::size_t first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// 'text' with single quotes. (Built by appending: GCC 12 warns falsely, -Wrestrict, on
// "'" + std::string(...).)
std::string Quoted(std::string_view text) {
  std::string quoted(1, '\'');
  quoted.append(text);
  quoted += '\'';
  return quoted;
}

std::string Join(const std::vector<std::string>& fields) {
  std::string joined;
  for (const std::string& f : fields) joined += (joined.empty() ? "" : ",") + f;
  return joined;
}

// Compares the header line with the expected columns; names the first column that differs.
Status CheckHeader(const std::filesystem::path& path, std::string_view line,
                   const std::vector<std::string>& expected) {
  const std::vector<std::string_view> actual = SplitFields(line);
  const std::string want = "expected header '" + Join(expected) + "'";
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (i >= actual.size()) return BadField(path, 1, expected[i], "missing from header, " + want);
    if (actual[i] != expected[i]) {
      return BadField(path, 1, expected[i],
                      "header column " + std::to_string(i + 1) + " is '" + std::string(actual[i]) +
                          "', " + want);
    }
  }
  if (actual.size() > expected.size()) {
    return BadField(path, 1, actual[expected.size()], "unexpected header column, " + want);
  }
  return Status::Ok();
}

}  // namespace

Result<CsvTable> CsvTable::Read(const std::filesystem::path& path,
                                const std::vector<std::string>& header) {
  Result<std::string> text = ReadFileText(path);
  if (!text.ok()) return text.status();
  CsvTable table(path, header);
  FLEETLOC_RETURN_IF_ERROR(table.ParseLines(*text));
  return table;
}

Status CsvTable::ParseLines(std::string_view text) {
  constexpr std::string_view kBom = "\xEF\xBB\xBF";
  if (text.substr(0, kBom.size()) == kBom) text.remove_prefix(kBom.size());
  int line_number = 0;
  int first_empty_line = 0;  // first of the empty lines seen since the last data row
  std::size_t start = 0;
  while (start < text.size() || line_number == 0) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    start = end + 1;
    ++line_number;
    if (line_number == 1) {
      if (Trim(line).empty()) {
        return BadField(path_, 1, header_[0], "missing header, expected '" + Join(header_) + "'");
      }
      FLEETLOC_RETURN_IF_ERROR(CheckHeader(path_, line, header_));
    } else if (Trim(line).empty()) {
      if (first_empty_line == 0) first_empty_line = line_number;
    } else if (first_empty_line != 0) {
      return BadField(path_, first_empty_line, "",
                      "empty line before more data on line " + std::to_string(line_number));
    } else {
      FLEETLOC_RETURN_IF_ERROR(AddRow(line_number, line));
    }
  }
  return Status::Ok();
}

Status CsvTable::AddRow(int line, std::string_view text) {
  const std::vector<std::string_view> fields = SplitFields(text);
  const std::size_t n = header_.size();
  if (fields.size() < n) {
    return BadField(path_, line, header_[fields.size()],
                    "missing (row has " + std::to_string(fields.size()) + " of " +
                        std::to_string(n) + " fields)");
  }
  if (fields.size() > n) {
    return BadField(path_, line, "(column " + std::to_string(n + 1) + ")",
                    "extra field '" + std::string(fields[n]) + "', the header has " +
                        std::to_string(n) + " columns");
  }
  rows_.push_back({line, std::vector<std::string>(fields.begin(), fields.end())});
  return Status::Ok();
}

Status CsvTable::Error(const CsvRow& row, std::size_t column, std::string_view what) const {
  return BadField(path_, row.line, header_.at(column), what);
}

Status CsvTable::Double(const CsvRow& row, std::size_t column, double* out) const {
  std::string_view s = Trim(row.fields.at(column));
  if (s.empty()) return Error(row, column, "empty, expected a number");
  if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
  const std::string quoted = Quoted(s);
  if (ec == std::errc::result_out_of_range) return Error(row, column, quoted + " is out of range");
  if (ec != std::errc() || end != s.data() + s.size()) {
    return Error(row, column, quoted + " is not a number");
  }
  if (!std::isfinite(*out)) return Error(row, column, quoted + " is not a finite number");
  return Status::Ok();
}

Status CsvTable::CheckAscending(const CsvRow& row, std::size_t column, double previous,
                                double value) const {
  if (value > previous) return Status::Ok();
  return Error(row, column,
               FormatDouble(value) + " is not after " + FormatDouble(previous) + " on line " +
                   std::to_string(row.line - 1) + "; it must be strictly ascending");
}

Status CsvTable::Int(const CsvRow& row, std::size_t column, int* out) const {
  const std::string_view s = Trim(row.fields.at(column));
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
  const std::string quoted = Quoted(s);
  if (ec == std::errc::result_out_of_range) return Error(row, column, quoted + " is out of range");
  if (s.empty() || ec != std::errc() || end != s.data() + s.size()) {
    return Error(row, column, quoted + " is not an integer");
  }
  return Status::Ok();
}

CsvWriter::CsvWriter(std::filesystem::path path, std::vector<std::string> header)
    : path_(std::move(path)), header_(std::move(header)), text_(Join(header_) + "\n") {}

std::string_view CsvWriter::CurrentField() const {
  return column_ < header_.size() ? std::string_view(header_[column_]) : std::string_view("?");
}

void CsvWriter::Append(std::string_view field_text) {
  FLEETLOC_CHECK(column_ < header_.size());
  if (column_ > 0) text_ += ',';
  text_ += field_text;
  ++column_;
}

void CsvWriter::Number(double value) {
  if (!std::isfinite(value) && error_.ok()) {
    error_ = BadField(path_, line_, CurrentField(),
                      "refusing to write the non-finite value " + FormatDouble(value));
  }
  Append(FormatDouble(value));
}

void CsvWriter::Int(int value) { Append(std::to_string(value)); }

void CsvWriter::Text(std::string_view value) {
  if (value.find_first_of(",\r\n") != std::string_view::npos && error_.ok()) {
    error_ = BadField(path_, line_, CurrentField(),
                      "refusing to write text containing a comma or line break");
  }
  Append(value);
}

void CsvWriter::EndRow() {
  FLEETLOC_CHECK(column_ == header_.size());
  text_ += '\n';
  column_ = 0;
  ++line_;
}

Status CsvWriter::Commit() const {
  FLEETLOC_CHECK(column_ == 0);
  FLEETLOC_RETURN_IF_ERROR(error_);
  return WriteFileAtomically(path_, text_);
}

}  // namespace fleetloc::io
