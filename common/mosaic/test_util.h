// Test helpers for the mosaic tests: real test photos as gray images, scratch directories and a
// pixel comparison with tolerance.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "mosaic/tile_key.h"

namespace fleetloc::mosaic::testing {

// A layout of `width` x `height` level-0 pixels in `tile`-pixel tiles with its full pyramid.
inline MosaicLayout Layout(int width, int height, int tile) {
  MosaicLayout layout;
  layout.width_px = width;
  layout.height_px = height;
  layout.tile_size_px = tile;
  layout.levels = PyramidLevelCount(width, height, tile);
  return layout;
}

// Absolute path of a file in the source tree, e.g. "tests/data/gravel.png".
inline std::string SourcePath(const std::string& relative) {
  return std::string(FLEETLOC_SOURCE_DIR) + "/" + relative;
}

// A photo as 8-bit gray, the way the importer converts it (IMREAD_COLOR then BGR2GRAY).
inline cv::Mat LoadGray(const std::string& path) {
  const cv::Mat colour = cv::imread(path, cv::IMREAD_COLOR);
  EXPECT_FALSE(colour.empty()) << path;
  cv::Mat gray;
  if (!colour.empty()) cv::cvtColor(colour, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

// A fresh directory under the system temp dir, removed with everything in it on destruction.
class ScratchDir {
 public:
  ScratchDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("fleetloc_mosaic_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// The whole content of a file (empty if it cannot be read).
inline std::string ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Writes the first `size` bytes of `bytes` to a new file (to make truncated copies).
inline void WriteFileBytes(const std::string& path, const std::string& bytes, std::size_t size) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(size));
}

// Largest absolute pixel difference of two same-sized 8-bit images (255 + 1 if sizes differ).
inline int MaxAbsDiff(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return 256;
  if (a.empty()) return 0;
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  double max_diff = 0;
  cv::minMaxLoc(diff.reshape(1), nullptr, &max_diff);
  return static_cast<int>(max_diff);
}

}  // namespace fleetloc::mosaic::testing
