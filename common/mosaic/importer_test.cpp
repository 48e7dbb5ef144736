// Tests for image import on real photos: the stored pyramid read back through a MosaicView equals
// the gray photo (level 0) and its area resize (higher levels), with the contract's default origin.
#include "mosaic/importer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "mosaic/mosaic_view.h"
#include "mosaic/test_util.h"
#include "mosaic/tile_store.h"

namespace fleetloc::mosaic {
namespace {

using testing::LoadGray;
using testing::MaxAbsDiff;
using testing::ScratchDir;
using testing::SourcePath;

std::unique_ptr<MosaicView> ViewOf(const std::string& db) {
  Result<std::unique_ptr<TileStore>> store = TileStore::Open(db, OpenMode::kReadOnly);
  EXPECT_TRUE(store.ok()) << store.status().message();
  std::shared_ptr<TileStore> shared = std::move(store).value();
  return std::make_unique<MosaicView>(shared->layout(), MakeTileLoader(shared),
                                      std::make_shared<TileCache>(16 << 20));
}

// Compares random blocks (inside, across tile borders, partly outside) of one level with
// `expected`.
void ExpectRandomBlocksMatch(MosaicView& view, int level, const cv::Mat& expected, int tolerance) {
  std::mt19937 rng(level + 1);
  std::uniform_int_distribution<int> x(-60, expected.cols + 20), y(-60, expected.rows + 20);
  std::uniform_int_distribution<int> size(1, 300);
  for (int i = 0; i < 150; ++i) {
    const cv::Rect rect(x(rng), y(rng), size(rng), size(rng));
    EXPECT_LE(MaxAbsDiff(view.ReadBlock(level, rect), CopyBlockWithZeroBorder(expected, rect)),
              tolerance)
        << "level " << level << " " << rect;
  }
}

TEST(Importer, RealColourPhotoReadsBackThroughTheView) {
  ScratchDir dir;
  const std::string photo = SourcePath("deploy/demo/floors/gravel_1024.png");  // RGBA 1024²
  ImportOptions options;
  options.resolution_m = 0.0005;
  int last_rows = 0, calls = 0;
  Result<MosaicLayout> layout =
      ImportImage(photo, options, dir.File("m.db"), [&](int done, int total) {
        EXPECT_GT(done, last_rows);
        EXPECT_EQ(total, 1024);
        last_rows = done;
        ++calls;
      });
  ASSERT_TRUE(layout.ok()) << layout.status().message();
  EXPECT_EQ(last_rows, 1024);
  EXPECT_GE(calls, 10);
  EXPECT_EQ(layout->levels, 3);
  EXPECT_EQ(layout->version, 1);
  EXPECT_DOUBLE_EQ(layout->geo.origin_x, 0.0);
  EXPECT_DOUBLE_EQ(layout->geo.origin_y, 1024 * 0.0005);  // mosaic covers x >= 0, y >= 0
  EXPECT_FALSE(std::filesystem::exists(dir.File("m.db.partial")));
  EXPECT_FALSE(std::filesystem::exists(dir.File("m.db-wal")));

  std::unique_ptr<MosaicView> view = ViewOf(dir.File("m.db"));
  cv::Mat expected = LoadGray(photo);
  ExpectRandomBlocksMatch(*view, 0, expected, 0);
  for (int level = 1; level < 3; ++level) {
    cv::resize(expected, expected, {}, 0.5, 0.5, cv::INTER_AREA);
    ExpectRandomBlocksMatch(*view, level, expected, 1);
  }
  EXPECT_EQ(view->missing_tiles() + view->unreadable_tiles(), 0);
}

TEST(Importer, OddSizedJpegHasTrueSizeExplicitOriginAndPaddedEdgeTiles) {
  ScratchDir dir;
  const cv::Mat photo = cv::imread(SourcePath("deploy/demo/floors/asphalt_1024.jpg"));
  ASSERT_TRUE(cv::imwrite(dir.File("crop.jpg"), photo(cv::Rect(5, 9, 700, 455))));
  ImportOptions options;
  options.resolution_m = 0.002;
  options.origin_x_m = -3.5;
  options.origin_y_m = 7.25;
  Result<MosaicLayout> layout = ImportImage(dir.File("crop.jpg"), options, dir.File("m.db"));
  ASSERT_TRUE(layout.ok()) << layout.status().message();
  Result<std::unique_ptr<TileStore>> store = TileStore::Open(dir.File("m.db"), OpenMode::kReadOnly);
  ASSERT_TRUE(store.ok());
  const MosaicLayout stored = (*store)->layout();
  EXPECT_EQ(stored.width_px, 700);
  EXPECT_EQ(stored.height_px, 455);
  EXPECT_EQ(stored.levels, 3);  // 700x455, 350x228, 175x114
  EXPECT_DOUBLE_EQ(stored.geo.origin_x, -3.5);
  EXPECT_DOUBLE_EQ(stored.geo.origin_y, 7.25);
  EXPECT_EQ(*(*store)->TileCountsPerLevel(), (std::vector<long long>{6, 2, 1}));
  const cv::Mat edge = *(*store)->ReadTile({0, 2, 1});  // holds columns 512..699, rows 256..454
  EXPECT_EQ(cv::countNonZero(edge(cv::Rect(188, 0, 68, 256))), 0);
  EXPECT_EQ(cv::countNonZero(edge(cv::Rect(0, 199, 256, 57))), 0);
  std::unique_ptr<MosaicView> view = ViewOf(dir.File("m.db"));
  ExpectRandomBlocksMatch(*view, 0, LoadGray(dir.File("crop.jpg")), 0);
}

TEST(Importer, BadInputIsRejectedAndLeavesNoFiles) {
  ScratchDir dir;
  ImportOptions options;
  options.resolution_m = 0.001;
  const std::string photo = SourcePath("tests/data/brick.png");
  EXPECT_EQ(ImportImage(dir.File("absent.png"), options, dir.File("a.db")).status().code(),
            StatusCode::kNotFound);
  std::ofstream(dir.File("text.png")) << "not a png";
  const Result<MosaicLayout> text = ImportImage(dir.File("text.png"), options, dir.File("b.db"));
  EXPECT_EQ(text.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(text.status().message().find("text.png"), std::string::npos);
  ImportOptions bad = options;
  bad.resolution_m = -1;
  EXPECT_EQ(ImportImage(photo, bad, dir.File("c.db")).status().code(), StatusCode::kInvalidInput);
  EXPECT_EQ(ImportImage(photo, options, dir.File("no/such/dir/m.db")).status().code(),
            StatusCode::kInvalidInput);
  ASSERT_TRUE(ImportImage(photo, options, dir.File("d.db")).ok());
  const Result<MosaicLayout> again = ImportImage(photo, options, dir.File("d.db"));
  EXPECT_EQ(again.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(again.status().message().find("already exists"), std::string::npos);
  // A PNG cut in half fails mid-way: neither the output nor its partial file is left behind.
  const std::string bytes = testing::ReadFileBytes(photo);
  testing::WriteFileBytes(dir.File("cut.png"), bytes, bytes.size() / 2);
  EXPECT_EQ(ImportImage(dir.File("cut.png"), options, dir.File("e.db")).status().code(),
            StatusCode::kInvalidInput);
  for (const char* name : {"a.db", "b.db", "c.db", "e.db", "e.db.partial", "e.db.partial-wal"}) {
    EXPECT_FALSE(std::filesystem::exists(dir.File(name))) << name;
  }
}

// Rows of an in-memory image, as a caller-made mosaic (e.g. a blended mapping run) delivers them.
class MatRowReader : public GrayRowReader {
 public:
  explicit MatRowReader(cv::Mat image) : image_(std::move(image)) {
    width_px_ = image_.cols;
    height_px_ = image_.rows;
  }
  bool streaming() const override { return true; }
  Status ReadRow(std::span<std::uint8_t> row) override {
    std::copy_n(image_.ptr<std::uint8_t>(next_++), width_px_, row.begin());
    return Status::Ok();
  }

 private:
  cv::Mat image_;
  int next_ = 0;
};

TEST(Importer, CallersRowsBecomeAMosaicAtTheGivenOrigin) {
  ScratchDir dir;
  const cv::Mat photo = LoadGray(SourcePath("tests/data/brick.png"));  // 512²
  const cv::Mat part = photo(cv::Rect(10, 20, 300, 280)).clone();
  MatRowReader reader(part);
  ImportOptions options;
  options.resolution_m = 0.001;
  options.origin_x_m = -1.5;
  options.origin_y_m = 2.25;
  Result<MosaicLayout> layout = ImportRows(reader, options, dir.File("rows.db"));
  ASSERT_TRUE(layout.ok()) << layout.status().message();
  EXPECT_EQ(layout->width_px, 300);
  EXPECT_EQ(layout->height_px, 280);
  EXPECT_DOUBLE_EQ(layout->geo.origin_x, -1.5);
  EXPECT_DOUBLE_EQ(layout->geo.origin_y, 2.25);
  EXPECT_FALSE(std::filesystem::exists(dir.File("rows.db.partial")));
  ExpectRandomBlocksMatch(*ViewOf(dir.File("rows.db")), 0, part, 0);
  MatRowReader again(part);
  EXPECT_EQ(ImportRows(again, options, dir.File("rows.db")).status().code(),
            StatusCode::kInvalidInput);  // never overwrites
}

}  // namespace
}  // namespace fleetloc::mosaic
