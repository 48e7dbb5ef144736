// A small strict reader and writer for the project's CSV files (docs/formats.md, 5 and 7).
// Written by hand on purpose: Debian 12, whose packages we build with, ships no C++ CSV library we
// use, and our format is plain comma-separated fields with a fixed header and no quoting, so a
// few dozen lines give exact file:line:field messages that a general parser would not.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.h"

namespace fleetloc::io {

// One data row; `fields` has exactly one entry per header column.
struct CsvRow {
  int line = 0;  // 1-based line in the file; data row i (0-based) is always on line i + 2
  std::vector<std::string> fields;
};

// A whole CSV file whose header and row widths have been checked.
class CsvTable {
 public:
  // Reads `path`; its first line must be exactly `header` joined by commas (a UTF-8 byte order
  // mark and CR line ends are tolerated). Every data row must have exactly one field per column.
  // Empty lines are allowed only at the end. NotFound when the file does not exist, InvalidInput
  // "<file>:<line>: field '<name>': ..." when it breaks these rules.
  static Result<CsvTable> Read(const std::filesystem::path& path,
                               const std::vector<std::string>& header);

  const std::filesystem::path& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }
  const std::vector<CsvRow>& rows() const { return rows_; }

  // InvalidInput "<file>:<line>: field '<header[column]>': <what>".
  Status Error(const CsvRow& row, std::size_t column, std::string_view what) const;
  // Parses a field as a finite double (surrounding blanks allowed); NaN, infinities, empty or
  // partly numeric text are InvalidInput naming file, line and field.
  Status Double(const CsvRow& row, std::size_t column, double* out) const;
  // Parses a field as a decimal int; anything else (including "3.0") is InvalidInput.
  Status Int(const CsvRow& row, std::size_t column, int* out) const;
  // For a column that must be strictly ascending: InvalidInput naming `row` unless
  // `value` > `previous` (the value on the row before).
  Status CheckAscending(const CsvRow& row, std::size_t column, double previous, double value) const;

 private:
  CsvTable(std::filesystem::path path, std::vector<std::string> header)
      : path_(std::move(path)), header_(std::move(header)) {}
  Status ParseLines(std::string_view text);
  Status AddRow(int line, std::string_view text);

  std::filesystem::path path_;
  std::vector<std::string> header_;
  std::vector<CsvRow> rows_;
};

// Builds a CSV file row by row and writes it atomically (WriteFileAtomically). It refuses values
// that its reader would reject — non-finite numbers, text containing commas or line breaks — and
// Commit() then returns InvalidInput naming the file, line and field instead of writing.
class CsvWriter {
 public:
  CsvWriter(std::filesystem::path path, std::vector<std::string> header);

  void Number(double value);
  void Int(int value);
  void Text(std::string_view value);
  // Ends the current row; it must hold exactly one value per header column (checked).
  void EndRow();
  // Writes the file unless a value was refused. Internal on I/O failure.
  Status Commit() const;

 private:
  void Append(std::string_view field_text);
  std::string_view CurrentField() const;

  std::filesystem::path path_;
  std::vector<std::string> header_;
  std::string text_;
  std::size_t column_ = 0;
  int line_ = 2;
  Status error_;
};

}  // namespace fleetloc::io
