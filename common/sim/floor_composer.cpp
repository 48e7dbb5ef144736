// Floor composition from blocks of real photographs.
#include "sim/floor_composer.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>

#include "sim/random.h"

namespace fleetloc::sim {
namespace {

// Uniform in [0, n) from 64 random bits (n > 0; the bias is below 2^-32 for the sizes used).
int UniformInt(std::uint64_t bits, int n) { return static_cast<int>((bits >> 32) % n); }

// Uniform in [0, 1) from 64 random bits.
double Uniform01(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

// Lookup table v -> round(gain * v), saturated to 0..255.
cv::Mat GainTable(double gain) {
  cv::Mat table(1, 256, CV_8UC1);
  for (int v = 0; v < 256; ++v)
    table.at<std::uint8_t>(v) = cv::saturate_cast<std::uint8_t>(gain * v);
  return table;
}

}  // namespace

Status Validate(const FloorComposerOptions& options) {
  if (options.width_px <= 0 || options.height_px <= 0) {
    return InvalidInput("floor size must be positive, got " + std::to_string(options.width_px) +
                        "x" + std::to_string(options.height_px));
  }
  if (options.block_px < 16) return InvalidInput("block_px must be at least 16");
  if (!(options.max_gain_change >= 0.0 && options.max_gain_change <= 0.5)) {
    return InvalidInput("max_gain_change must be in [0, 0.5]");
  }
  if (!(options.min_scale > 0.0 && options.max_scale >= options.min_scale &&
        options.max_scale <= 4.0)) {
    return InvalidInput("scales must satisfy 0 < min_scale <= max_scale <= 4");
  }
  return Status::Ok();
}

namespace {

// Half the side of the photo square a freely rotated and scaled block reads, with a margin for
// bilinear interpolation.
int FreeBlockReachPx(const FloorComposerOptions& options) {
  return static_cast<int>(std::ceil(0.5 * options.block_px * options.max_scale * std::sqrt(2.0))) +
         2;
}

}  // namespace

FloorComposer::FloorComposer(std::vector<cv::Mat> photos, FloorComposerOptions options)
    : photos_(std::move(photos)), options_(options) {}

Result<FloorComposer> FloorComposer::Create(std::vector<cv::Mat> photos,
                                            FloorComposerOptions options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  if (photos.empty()) return InvalidInput("floor composer: no photos");
  for (std::size_t i = 0; i < photos.size(); ++i) {
    const cv::Mat& photo = photos[i];
    const int needed_px =
        options.free_rotation_and_scale ? 2 * FreeBlockReachPx(options) : options.block_px;
    if (photo.type() != CV_8UC1 || photo.cols < needed_px || photo.rows < needed_px) {
      return InvalidInput("photo " + std::to_string(i) + " must be 8-bit gray and at least " +
                          std::to_string(needed_px) + " px on both sides (block_px" +
                          (options.free_rotation_and_scale ? " · max_scale · √2)" : ")"));
    }
  }
  return FloorComposer(std::move(photos), options);
}

BlockPlacement FloorComposer::PlacementOf(int col, int row) const {
  const std::uint64_t block_id =
      (static_cast<std::uint64_t>(static_cast<std::uint32_t>(row)) << 32) |
      static_cast<std::uint32_t>(col);
  std::uint64_t bits = MixSeed(options_.seed, block_id);
  const auto next = [&bits] { return bits = SplitMix64(bits); };
  BlockPlacement p;
  p.photo = UniformInt(next(), static_cast<int>(photos_.size()));
  const cv::Mat& photo = photos_[p.photo];
  p.crop_origin.x = UniformInt(next(), photo.cols - options_.block_px + 1);
  p.crop_origin.y = UniformInt(next(), photo.rows - options_.block_px + 1);
  // Orientation 0..7 = 2 × parity class + one random bit: neighbours never share an orientation.
  const int parity_class = (col & 1) + 2 * (row & 1);
  const int orientation = 2 * parity_class + static_cast<int>(next() >> 63);
  p.transpose = (orientation & 4) != 0;
  p.flip_x = (orientation & 2) != 0;
  p.flip_y = (orientation & 1) != 0;
  p.gain = 1.0 + options_.max_gain_change * (2.0 * Uniform01(next()) - 1.0);
  if (options_.free_rotation_and_scale) {
    const int reach = FreeBlockReachPx(options_);
    p.center = {reach + Uniform01(next()) * (photo.cols - 2 * reach),
                reach + Uniform01(next()) * (photo.rows - 2 * reach)};
    p.angle_rad = 2.0 * M_PI * Uniform01(next());
    p.scale = options_.min_scale + (options_.max_scale - options_.min_scale) * Uniform01(next());
    p.transpose = p.flip_y = false;
  }
  return p;
}

cv::Mat FloorComposer::RenderFreeBlock(const BlockPlacement& p) const {
  const double b = options_.block_px, c = std::cos(p.angle_rad), s = std::sin(p.angle_rad);
  // Block pixel (x, y) → photo: center + scale · R · ((x, y) − b/2) (pixel centres alike).
  const cv::Matx23d to_photo(p.scale * c, -p.scale * s, 0, p.scale * s, p.scale * c, 0);
  cv::Matx23d m = to_photo;
  m(0, 2) = p.center.x - 0.5 - (to_photo(0, 0) + to_photo(0, 1)) * (0.5 * b - 0.5);
  m(1, 2) = p.center.y - 0.5 - (to_photo(1, 0) + to_photo(1, 1)) * (0.5 * b - 0.5);
  cv::Mat block;
  cv::warpAffine(photos_[p.photo], block, m, cv::Size(options_.block_px, options_.block_px),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REFLECT);
  if (p.flip_x) cv::flip(block, block, 1);
  return block;
}

cv::Mat FloorComposer::RenderBlock(int col, int row) const {
  const BlockPlacement p = PlacementOf(col, row);
  if (options_.free_rotation_and_scale) {
    cv::Mat block;
    cv::LUT(RenderFreeBlock(p), GainTable(p.gain), block);
    return block;
  }
  const int b = options_.block_px;
  const cv::Mat crop = photos_[p.photo](cv::Rect(p.crop_origin, cv::Size(b, b)));
  cv::Mat oriented;
  if (p.transpose) {
    cv::transpose(crop, oriented);
  } else {
    oriented = crop;
  }
  if (p.flip_x || p.flip_y) {
    cv::Mat flipped;
    cv::flip(oriented, flipped, p.flip_x && p.flip_y ? -1 : (p.flip_x ? 1 : 0));
    oriented = flipped;
  }
  cv::Mat block;
  cv::LUT(oriented, GainTable(p.gain), block);
  return block;
}

cv::Mat FloorComposer::RenderBlockRow(int row) const {
  FLEETLOC_CHECK(row >= 0 && row < block_rows());
  const int b = options_.block_px;
  const int height = std::min(b, options_.height_px - row * b);
  cv::Mat strip(height, options_.width_px, CV_8UC1);
  for (int col = 0; col < block_cols(); ++col) {
    const int width = std::min(b, options_.width_px - col * b);
    RenderBlock(col, row)(cv::Rect(0, 0, width, height))
        .copyTo(strip(cv::Rect(col * b, 0, width, height)));
  }
  return strip;
}

}  // namespace fleetloc::sim
