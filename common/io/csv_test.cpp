// Tests for the strict CSV reader/writer: header and row-width checks, typed fields, exact numbers.
#include "io/csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "io/io_test_util.h"
#include "io/messages.h"

namespace fleetloc::io {
namespace {

using testing::HasError;
using testing::TempDir;
using testing::WriteText;

const std::vector<std::string> kHeader = {"t", "x", "n"};

class CsvTableTest : public ::testing::Test {
 protected:
  Result<CsvTable> ReadText(const std::string& text) {
    WriteText(path_, text);
    return CsvTable::Read(path_, kHeader);
  }
  // Reads a one-row table and parses field `column` of its row as a double.
  Status ParseDouble(const std::string& row_text, std::size_t column) {
    Result<CsvTable> table = ReadText("t,x,n\n" + row_text + "\n");
    if (!table.ok()) return table.status();
    double value = 0;
    return table->Double(table->rows().at(0), column, &value);
  }
  TempDir dir_;
  std::filesystem::path path_ = dir_.path() / "table.csv";
};

TEST_F(CsvTableTest, ReadsRowsWithCrLfBomAndTrailingEmptyLines) {
  Result<CsvTable> table = ReadText("\xEF\xBB\xBFt,x,n\r\n0.5,-1e-3,7\r\n1, 2.25 ,-3\r\n\r\n\n");
  ASSERT_TRUE(table.ok()) << table.status().message();
  ASSERT_EQ(table->rows().size(), 2u);
  EXPECT_EQ(table->rows()[1].line, 3);
  double x = 0;
  int n = 0;
  ASSERT_TRUE(table->Double(table->rows()[0], 1, &x).ok());
  EXPECT_EQ(x, -1e-3);
  ASSERT_TRUE(table->Double(table->rows()[1], 1, &x).ok());
  EXPECT_EQ(x, 2.25);
  ASSERT_TRUE(table->Int(table->rows()[1], 2, &n).ok());
  EXPECT_EQ(n, -3);
}

TEST_F(CsvTableTest, HeaderOnlyFileHasNoRows) {
  Result<CsvTable> table = ReadText("t,x,n");
  ASSERT_TRUE(table.ok()) << table.status().message();
  EXPECT_TRUE(table->rows().empty());
}

TEST_F(CsvTableTest, MissingFileIsNotFound) {
  EXPECT_TRUE(
      HasError(CsvTable::Read(path_, kHeader).status(), StatusCode::kNotFound, path_, 0, ""));
}

TEST_F(CsvTableTest, EmptyFileNamesTheMissingHeader) {
  EXPECT_TRUE(HasError(ReadText("").status(), StatusCode::kInvalidInput, path_, 1, "t"));
}

TEST_F(CsvTableTest, BadHeaderNamesTheFirstDifferingColumn) {
  EXPECT_TRUE(HasError(ReadText("t,y,n\n").status(), StatusCode::kInvalidInput, path_, 1, "x"));
  EXPECT_TRUE(HasError(ReadText("t,x\n").status(), StatusCode::kInvalidInput, path_, 1, "n"));
  EXPECT_TRUE(HasError(ReadText("t,x,n,z\n").status(), StatusCode::kInvalidInput, path_, 1, "z"));
  EXPECT_TRUE(HasError(ReadText("t, x,n\n").status(), StatusCode::kInvalidInput, path_, 1, "x"));
}

TEST_F(CsvTableTest, MissingFieldNamesLineAndField) {
  EXPECT_TRUE(
      HasError(ReadText("t,x,n\n1,2,3\n4,5\n").status(), StatusCode::kInvalidInput, path_, 3, "n"));
}

TEST_F(CsvTableTest, ExtraFieldNamesLineAndColumn) {
  EXPECT_TRUE(HasError(ReadText("t,x,n\n1,2,3,4\n").status(), StatusCode::kInvalidInput, path_, 2,
                       "(column 4)"));
}

TEST_F(CsvTableTest, EmptyLineBeforeMoreDataIsAnError) {
  EXPECT_TRUE(HasError(ReadText("t,x,n\n1,2,3\n\n4,5,6\n").status(), StatusCode::kInvalidInput,
                       path_, 3, ""));
}

TEST_F(CsvTableTest, NonNumericNanInfAndEmptyFieldsAreRejected) {
  for (const std::string bad :
       {"abc", "1.5x", "nan", "NaN", "-nan", "inf", "-inf", "infinity", "", " ", "1e999", "0x10"}) {
    EXPECT_TRUE(
        HasError(ParseDouble("0," + bad + ",1", 1), StatusCode::kInvalidInput, path_, 2, "x"))
        << "'" << bad << "'";
  }
}

TEST_F(CsvTableTest, IntFieldRejectsFractionsAndText) {
  for (const std::string bad : {"3.0", "3e2", "x", "", "99999999999"}) {
    Result<CsvTable> table = ReadText("t,x,n\n0,0," + bad + "\n");
    ASSERT_TRUE(table.ok());
    int n = 0;
    EXPECT_TRUE(
        HasError(table->Int(table->rows()[0], 2, &n), StatusCode::kInvalidInput, path_, 2, "n"))
        << "'" << bad << "'";
  }
}

TEST_F(CsvTableTest, CheckAscendingNamesTheBreakingLine) {
  Result<CsvTable> table = ReadText("t,x,n\n1,0,0\n1,0,0\n");
  ASSERT_TRUE(table.ok());
  EXPECT_TRUE(table->CheckAscending(table->rows()[0], 0, 0.5, 1.0).ok());
  EXPECT_TRUE(HasError(table->CheckAscending(table->rows()[1], 0, 1.0, 1.0),
                       StatusCode::kInvalidInput, path_, 3, "t"));
}

TEST_F(CsvTableTest, WriterRoundTripsDoublesExactly) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  std::vector<double> values = {
      0.1, -0.0, 1e-320, std::numeric_limits<double>::max(), std::numeric_limits<double>::min(),
      M_PI};
  for (int i = 0; i < 500; ++i) values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  CsvWriter writer(path_, kHeader);
  for (std::size_t i = 0; i < values.size(); ++i) {
    writer.Number(values[i]);
    writer.Text("v");
    writer.Int(static_cast<int>(i));
    writer.EndRow();
  }
  ASSERT_TRUE(writer.Commit().ok());
  Result<CsvTable> table = CsvTable::Read(path_, kHeader);
  ASSERT_TRUE(table.ok()) << table.status().message();
  ASSERT_EQ(table->rows().size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    double t = 0;
    ASSERT_TRUE(table->Double(table->rows()[i], 0, &t).ok());
    EXPECT_EQ(t, values[i]) << FormatDouble(values[i]);
    EXPECT_EQ(std::signbit(t), std::signbit(values[i]));
  }
}

TEST_F(CsvTableTest, WriterRefusesNonFiniteNumbersAndWritesNothing) {
  CsvWriter writer(path_, kHeader);
  writer.Number(0.0);
  writer.Number(std::nan(""));
  writer.Int(1);
  writer.EndRow();
  EXPECT_TRUE(HasError(writer.Commit(), StatusCode::kInvalidInput, path_, 2, "x"));
  EXPECT_FALSE(std::filesystem::exists(path_));
}

TEST_F(CsvTableTest, WriterRefusesTextWithComma) {
  CsvWriter writer(path_, {"t", "file"});
  writer.Number(0.0);
  writer.Text("a,b.png");
  writer.EndRow();
  EXPECT_TRUE(HasError(writer.Commit(), StatusCode::kInvalidInput, path_, 2, "file"));
}

}  // namespace
}  // namespace fleetloc::io
