// Feathered, gain-normalized blending into a float canvas.
#include "mapping/mosaic_blender.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "geometry/footprint.h"
#include "imaging/resample.h"
#include "tracking/frame_mosaic_warp.h"

namespace fleetloc::mapping {
namespace {

// Distance of each pixel centre to the frame's border over half the shorter side, ^ power.
cv::Mat FeatherWeights(int width, int height, double power) {
  cv::Mat weights(height, width, CV_32F);
  const double half = 0.5 * std::min(width, height);
  for (int j = 0; j < height; ++j) {
    float* row = weights.ptr<float>(j);
    const double dy = std::min(j + 0.5, height - j - 0.5);
    for (int i = 0; i < width; ++i) {
      const double d = std::min({i + 0.5, width - i - 0.5, dy});
      row[i] = static_cast<float>(std::pow(std::min(1.0, d / half), power));
    }
  }
  return weights;
}

}  // namespace

Status Validate(const BlendOptions& o) {
  if (!(o.feather_power > 0)) return InvalidInput("blend.feather_power must be > 0");
  if (o.min_gain_samples < 2) return InvalidInput("blend.min_gain_samples must be ≥ 2");
  if (!(o.min_gain > 0 && o.min_gain < o.max_gain)) {
    return InvalidInput("blend.min_gain must be in (0, max_gain)");
  }
  if (!(o.max_canvas_mb > 0)) return InvalidInput("blend.max_canvas_mb must be > 0");
  return Status::Ok();
}

Result<Canvas> CanvasFor(const std::vector<geometry::Pose2>& camera_in_map,
                         const geometry::CameraModel& camera, const BlendOptions& options) {
  if (camera_in_map.empty()) return InvalidInput("no frames to blend");
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Vector2d lo(inf, inf), hi(-inf, -inf);
  const geometry::ConvexPolygon ground = geometry::FootprintInGround(camera);
  for (const geometry::Pose2& pose : camera_in_map) {
    for (const Eigen::Vector2d& corner : geometry::PlaceFootprint(ground, pose)) {
      lo = lo.cwiseMin(corner);
      hi = hi.cwiseMax(corner);
    }
  }
  const double res = camera.resolution_m;
  Canvas canvas;
  canvas.geo = {std::floor(lo.x() / res) * res, std::ceil(hi.y() / res) * res, res};
  const double width = std::ceil((hi.x() - canvas.geo.origin_x) / res);
  const double height = std::ceil((canvas.geo.origin_y - lo.y()) / res);
  const double mb = 8.0 * width * height / (1 << 20);
  if (!(mb <= options.max_canvas_mb)) {
    std::ostringstream m;
    m << "the mapped area (" << width << " x " << height << " px) needs a " << mb
      << " MB blending canvas, above the " << options.max_canvas_mb << " MB limit";
    return InvalidInput(m.str());
  }
  canvas.width_px = static_cast<int>(width);
  canvas.height_px = static_cast<int>(height);
  return canvas;
}

MosaicBlender::MosaicBlender(const Canvas& canvas, const geometry::CameraModel& camera,
                             const BlendOptions& options)
    : canvas_(canvas),
      camera_(camera),
      options_(options),
      feather_(FeatherWeights(camera.width_px, camera.height_px, options.feather_power)),
      sum_(cv::Mat::zeros(canvas.height_px, canvas.width_px, CV_32F)),
      weight_(cv::Mat::zeros(canvas.height_px, canvas.width_px, CV_32F)) {}

cv::Rect MosaicBlender::FootprintRoi(const geometry::Pose2& camera_in_map) const {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Vector2d lo(inf, inf), hi(-inf, -inf);
  for (const Eigen::Vector2d& corner :
       geometry::PlaceFootprint(geometry::FootprintInGround(camera_), camera_in_map)) {
    const Eigen::Vector2d px = canvas_.geo.MapToPixel(corner);
    lo = lo.cwiseMin(px);
    hi = hi.cwiseMax(px);
  }
  const cv::Point tl(static_cast<int>(std::floor(lo.x())), static_cast<int>(std::floor(lo.y())));
  const cv::Point br(static_cast<int>(std::ceil(hi.x())), static_cast<int>(std::ceil(hi.y())));
  return cv::Rect(tl, br) & cv::Rect(0, 0, canvas_.width_px, canvas_.height_px);
}

cv::Matx23d MosaicBlender::CanvasToFrame(const geometry::Pose2& camera_in_map,
                                         const cv::Rect& roi) const {
  // Continuous coordinates have pixel centres at index + 0.5 on both sides.
  const tracking::FrameMosaicWarp to_frame =
      tracking::FrameMosaicWarp::For(camera_in_map, camera_, canvas_.geo).Inverse();
  const Eigen::Vector2d origin =
      to_frame(Eigen::Vector2d(roi.x + 0.5, roi.y + 0.5)) - Eigen::Vector2d(0.5, 0.5);
  const Eigen::Matrix2d& l = to_frame.linear;
  return {l(0, 0), l(0, 1), origin.x(), l(1, 0), l(1, 1), origin.y()};
}

cv::Vec2d MosaicBlender::FitGain(const cv::Mat& values, const cv::Mat& weights,
                                 const cv::Rect& roi) const {
  double n = 0, sf = 0, sm = 0, sff = 0, sfm = 0;
  for (int j = 0; j < roi.height; ++j) {
    const float* v = values.ptr<float>(j);
    const float* w = weights.ptr<float>(j);
    const float* s = sum_.ptr<float>(roi.y + j) + roi.x;
    const float* a = weight_.ptr<float>(roi.y + j) + roi.x;
    for (int i = 0; i < roi.width; ++i) {
      if (w[i] <= 0.0f || a[i] <= 0.0f) continue;
      const double f = v[i], m = s[i] / a[i];
      n += 1;
      sf += f;
      sm += m;
      sff += f * f;
      sfm += f * m;
    }
  }
  const double variance = sff - sf * sf / std::max(n, 1.0);
  if (n < options_.min_gain_samples || !(variance > 0)) return {1.0, 0.0};
  const double gain = (sfm - sf * sm / n) / variance;
  if (!(gain >= options_.min_gain && gain <= options_.max_gain)) return {1.0, 0.0};
  return {gain, (sm - gain * sf) / n};
}

double MosaicBlender::Add(const cv::Mat& frame, const geometry::Pose2& camera_in_map) {
  FLEETLOC_CHECK(frame.type() == CV_8UC1 && frame.cols == camera_.width_px &&
                 frame.rows == camera_.height_px);
  const cv::Rect roi = FootprintRoi(camera_in_map);
  if (roi.empty()) return 1.0;
  const cv::Matx23d to_frame = CanvasToFrame(camera_in_map, roi);
  cv::Mat values = imaging::ResampleAffine(frame, to_frame, roi.size());
  const cv::Mat weights = imaging::ResampleAffine(feather_, to_frame, roi.size());
  const cv::Vec2d gain_bias =
      options_.normalize_gain ? FitGain(values, weights, roi) : cv::Vec2d(1.0, 0.0);
  values.convertTo(values, CV_32F, gain_bias[0], gain_bias[1]);
  sum_(roi) += values.mul(weights);
  weight_(roi) += weights;
  return gain_bias[0];
}

void MosaicBlender::Row(int v, std::span<std::uint8_t> out) const {
  FLEETLOC_CHECK(v >= 0 && v < canvas_.height_px &&
                 static_cast<int>(out.size()) == canvas_.width_px);
  const float* s = sum_.ptr<float>(v);
  const float* w = weight_.ptr<float>(v);
  for (int u = 0; u < canvas_.width_px; ++u) {
    out[u] =
        w[u] > 0.0f ? static_cast<std::uint8_t>(std::clamp(std::lround(s[u] / w[u]), 1L, 255L)) : 0;
  }
}

}  // namespace fleetloc::mapping
