// landmarks.csv and points.csv: values read exactly, and one file:line:field error per broken rule.
#include "run_io/mapmatch_files.h"

#include <gtest/gtest.h>

#include "run_io/run_io_test_util.h"

namespace fleetloc::run_io {
namespace {

using testing::HasError;
using testing::TempDir;
using testing::WriteText;

class MapmatchFilesTest : public ::testing::Test {
 protected:
  Result<LandmarkMap> Landmarks(const std::string& text) {
    WriteText(path_, text);
    return ReadLandmarksCsv(path_);
  }
  Result<std::vector<Eigen::Vector2d>> Points(const std::string& text) {
    WriteText(path_, text);
    return ReadPointsCsv(path_);
  }
  TempDir dir_;
  std::filesystem::path path_ = dir_.path() / "file.csv";
};

TEST_F(MapmatchFilesTest, ReadsLandmarksAndPoints) {
  const Result<LandmarkMap> map = Landmarks("id,x,y\nc1,0,0\nc2,4.25,-1e-3\n");
  ASSERT_TRUE(map.ok()) << map.status().message();
  EXPECT_EQ(map->ids, (std::vector<std::string>{"c1", "c2"}));
  EXPECT_EQ(map->positions[1], Eigen::Vector2d(4.25, -1e-3));
  const Result<std::vector<Eigen::Vector2d>> points = Points("x,y\n1,2\n1,2\n-0.5,3\n");
  ASSERT_TRUE(points.ok()) << points.status().message();
  ASSERT_EQ(points->size(), 3u);  // repeats are measurements, not errors
  EXPECT_EQ((*points)[2], Eigen::Vector2d(-0.5, 3));
}

TEST_F(MapmatchFilesTest, EachBrokenRuleNamesFileLineAndField) {
  const StatusCode bad = StatusCode::kInvalidInput;
  EXPECT_TRUE(HasError(Landmarks("x,y\n0,0\n").status(), bad, path_, 1, ""));
  EXPECT_TRUE(HasError(Landmarks("id,x,y\na,0,0\nb,nan,1\n").status(), bad, path_, 3, "x"));
  EXPECT_TRUE(HasError(Landmarks("id,x,y\na,0,0\nb,1\n").status(), bad, path_, 3, ""));
  EXPECT_TRUE(HasError(Landmarks("id,x,y\n,0,0\n").status(), bad, path_, 2, "id"));
  EXPECT_TRUE(HasError(Landmarks("id,x,y\na,0,0\nb,1,1\na,2,2\n").status(), bad, path_, 4, "id"));
  EXPECT_TRUE(HasError(Landmarks("id,x,y\na,0,0\nb,1,1\nc,1,1\n").status(), bad, path_, 4, "x"));
  EXPECT_TRUE(HasError(Points("x,y\n0,0\n0,inf\n").status(), bad, path_, 3, "y"));
  EXPECT_TRUE(HasError(Points("x,y\n0,0\nabc,1\n").status(), bad, path_, 3, "x"));
  EXPECT_TRUE(HasError(Points("id,x,y\n").status(), bad, path_, 1, ""));
}

TEST_F(MapmatchFilesTest, DuplicateMessagesNameTheEarlierLine) {
  EXPECT_NE(Landmarks("id,x,y\na,0,0\nb,1,1\na,2,2\n").status().message().find("line 2"),
            std::string::npos);
  EXPECT_NE(Landmarks("id,x,y\na,5,5\nb,1,1\nc,5,5\n").status().message().find("line 2"),
            std::string::npos);
}

TEST_F(MapmatchFilesTest, AMissingFileIsNotFound) {
  EXPECT_EQ(ReadPointsCsv(dir_.path() / "none.csv").status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetloc::run_io
