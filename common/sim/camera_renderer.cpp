// Camera rendering: geometric sampling of the floor block under the footprint, then the
// photometric chain of photometric.h.
#include "sim/camera_renderer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "sim/area_sampler.h"
#include "sim/photometric.h"
#include "sim/random.h"

namespace fleetloc::sim {
namespace {

constexpr std::uint64_t kFrameStream = 0x6672616d;   // "fram"
constexpr std::uint64_t kShadowStream = 0x73686477;  // "shdw"

using Affine = Eigen::Matrix<double, 2, 3>;

// Continuous mosaic pixel coordinates of map points: the geotransform as an affine matrix.
Affine MapToMosaic(const geometry::Geotransform& geo) {
  Affine a;
  a << 1.0 / geo.resolution, 0.0, -geo.origin_x / geo.resolution,  //
      0.0, -1.0 / geo.resolution, geo.origin_y / geo.resolution;
  return a;
}

// a ∘ b for 2×3 affine matrices.
Affine Chain(const Affine& a, const Affine& b) {
  Affine c;
  c.leftCols<2>() = a.leftCols<2>() * b.leftCols<2>();
  c.col(2) = a.leftCols<2>() * b.col(2) + a.col(2);
  return c;
}

// The affine map of image coordinates shifted by `offset` (p = uv + offset ↦ a · uv).
Affine Shifted(const Affine& a, double offset) {
  Affine s = a;
  s.col(2) -= a.leftCols<2>() * Eigen::Vector2d(offset, offset);
  return s;
}

}  // namespace

CameraRenderer::CameraRenderer(mosaic::RasterSource* floor, geometry::CameraModel camera,
                               RenderOptions options, std::uint64_t seed)
    : floor_(floor),
      camera_(camera),
      options_(options),
      seed_(seed),
      grain_(options.floor_grain_dn, seed),
      dust_(options, camera.resolution_m, seed),
      marks_(options, camera.resolution_m, seed),
      vignetting_(VignettingField(camera, options.vignetting_corner_loss)) {}

Affine CameraRenderer::ImageToMap(const geometry::Pose2& camera_in_map) const {
  const Eigen::Vector2d origin = camera_in_map * camera_.PixelToGround({0, 0});
  Affine a;
  a.col(0) = camera_in_map * camera_.PixelToGround({1, 0}) - origin;
  a.col(1) = camera_in_map * camera_.PixelToGround({0, 1}) - origin;
  a.col(2) = origin;
  return a;
}

Eigen::Vector2d CameraRenderer::ImageToMosaic(const geometry::Pose2& base_in_map,
                                              const Eigen::Vector2d& uv) const {
  const Affine a =
      Chain(MapToMosaic(floor_->layout().geo), ImageToMap(base_in_map * camera_.mount));
  return a * uv.homogeneous();
}

cv::Mat CameraRenderer::ReadMirrored(const cv::Rect& rect) {
  const int width = floor_->layout().width_px, height = floor_->layout().height_px;
  if ((rect & cv::Rect(0, 0, width, height)) == rect) return floor_->ReadBlock(0, rect);
  std::vector<int> cols(rect.width), rows(rect.height);
  for (int i = 0; i < rect.width; ++i) {
    cols[i] = cv::borderInterpolate(rect.x + i, width, cv::BORDER_REFLECT_101);
  }
  for (int j = 0; j < rect.height; ++j) {
    rows[j] = cv::borderInterpolate(rect.y + j, height, cv::BORDER_REFLECT_101);
  }
  const auto [c0, c1] = std::minmax_element(cols.begin(), cols.end());
  const auto [r0, r1] = std::minmax_element(rows.begin(), rows.end());
  const cv::Mat source = floor_->ReadBlock(0, cv::Rect(*c0, *r0, *c1 - *c0 + 1, *r1 - *r0 + 1));
  cv::Mat block(rect.size(), CV_8UC1);
  for (int j = 0; j < rect.height; ++j) {
    const std::uint8_t* in = source.ptr<std::uint8_t>(rows[j] - *r0);
    std::uint8_t* out = block.ptr<std::uint8_t>(j);
    for (int i = 0; i < rect.width; ++i) out[i] = in[cols[i] - *c0];
  }
  return block;
}

cv::Mat CameraRenderer::RenderFloor(const geometry::Pose2& camera_in_map, int margin_px) {
  const cv::Size size(camera_.width_px + 2 * margin_px, camera_.height_px + 2 * margin_px);
  // Rendered pixel p (continuous) ↦ mosaic pixel coordinates.
  const AreaSampler sampler(
      Shifted(Chain(MapToMosaic(floor_->layout().geo), ImageToMap(camera_in_map)), margin_px),
      options_.supersample);
  const cv::Rect block_rect = sampler.SourceRect(size);
  cv::Mat block = ReadMirrored(block_rect);
  grain_.Apply(block_rect, &block);
  return sampler.Sample(block, block_rect, size);
}

// The vehicle's shadow: its side of the frame is fixed by the run's seed; the edge wavers a
// little from frame to frame (the vehicle sways, the light source is not a point).
cv::Mat CameraRenderer::Shadow(cv::Size size, std::uint64_t frame_index) const {
  if (options_.shadow_fraction <= 0) return {};
  const double run_angle = cv::RNG(MixSeed(seed_, kShadowStream)).uniform(0.0, 2 * M_PI);
  cv::RNG rng(MixSeed(MixSeed(seed_, kShadowStream), frame_index));
  const double fraction = std::min(0.9, options_.shadow_fraction * rng.uniform(0.85, 1.15));
  return ShadowField(size, fraction, options_.shadow_depth, run_angle + rng.uniform(-0.05, 0.05),
                     options_.shadow_edge_px);
}

RenderedFrame CameraRenderer::Render(const geometry::Pose2& base_in_map,
                                     const Eigen::Vector2d& image_velocity_px_s,
                                     std::uint64_t frame_index) {
  const geometry::Pose2 camera_in_map = base_in_map * camera_.mount;
  const Eigen::Vector2d motion_px = image_velocity_px_s * options_.exposure_s;
  const int margin = MarginForBlur(options_.blur_sigma_px, motion_px);
  cv::Mat floor = RenderFloor(camera_in_map, margin);
  const cv::Rect frame_rect(margin, margin, camera_.width_px, camera_.height_px);
  RenderedFrame frame;
  frame.dust_coverage = dust_.Apply(Shifted(ImageToMap(camera_in_map), margin), frame_rect, &floor);
  frame.marks_coverage =
      marks_.Apply(Shifted(ImageToMap(camera_in_map), margin), frame_rect, &floor);
  ApplyBlur(options_.blur_sigma_px, motion_px, &floor);
  cv::RNG rng(MixSeed(MixSeed(seed_, kFrameStream), frame_index));
  cv::Mat shading = LightingField(frame_rect.size(), options_.lighting_amplitude, rng);
  for (const cv::Mat& field : {vignetting_, Shadow(frame_rect.size(), frame_index)}) {
    if (field.empty()) continue;
    if (shading.empty()) {
      shading = field;
    } else {
      cv::Mat product;  // never in place: `shading` may share the vignetting field's data
      cv::multiply(shading, field, product);
      shading = product;
    }
  }
  const SensorDraw draw = DrawSensor(options_, rng);
  frame.image = JpegRoundTrip(ApplySensor(floor(frame_rect), shading, draw, options_, rng),
                              options_.jpeg_quality);
  frame.gain = draw.gain;
  frame.bias_dn = draw.bias_dn;
  return frame;
}

}  // namespace fleetloc::sim
