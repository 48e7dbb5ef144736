// Feathered, photometrically matched blending of patches into tiles (warpAffine per patch).
#include "mapping/patch_blender.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace fleetloc::mapping {

cv::Mat FeatherWeights(cv::Size size, double feather_px) {
  cv::Mat weights(size, CV_32F);
  for (int y = 0; y < size.height; ++y) {
    float* row = weights.ptr<float>(y);
    const double dy = std::min(y + 0.5, size.height - y - 0.5);
    for (int x = 0; x < size.width; ++x) {
      const double d = std::min(dy, std::min(x + 0.5, size.width - x - 0.5));
      const double s = std::clamp(d / feather_px, 0.0, 1.0);
      row[x] = static_cast<float>(s * s * (3 - 2 * s));
    }
  }
  return weights;
}

cv::Matx23d TileToPatch(const PlacedPatch& patch, cv::Point tile_origin_px,
                        const geometry::Geotransform& geo) {
  const double res = geo.resolution;
  const double cx = patch.image.cols / 2.0, cy = patch.image.rows / 2.0;
  const geometry::Pose2 to_patch = patch.pose.Inverse();
  auto patch_index = [&](double j, double i) {
    const Eigen::Vector2d map =
        geo.PixelToMap({tile_origin_px.x + j + 0.5, tile_origin_px.y + i + 0.5});
    const Eigen::Vector2d ab = to_patch * map;  // camera_ground (a forward/up, b left)
    return cv::Point2f(static_cast<float>(cx - ab.y() / res - 0.5),
                       static_cast<float>(cy - ab.x() / res - 0.5));
  };
  const cv::Point2f src[3] = {{0, 0}, {1000, 0}, {0, 1000}};
  const cv::Point2f dst[3] = {patch_index(0, 0), patch_index(1000, 0), patch_index(0, 1000)};
  return cv::Matx23d(cv::getAffineTransform(src, dst));
}

cv::Mat BlendTile(const cv::Mat& tile, cv::Point tile_origin_px, const geometry::Geotransform& geo,
                  const std::vector<PlacedPatch>& patches, BlendMode mode, double feather_px) {
  CV_Assert(tile.type() == CV_8UC1);
  cv::Mat weight_sum = cv::Mat::zeros(tile.size(), CV_32F);
  cv::Mat value_sum = cv::Mat::zeros(tile.size(), CV_32F);
  for (const PlacedPatch& patch : patches) {
    const cv::Matx23d m = TileToPatch(patch, tile_origin_px, geo);
    cv::Mat values, weights, image;
    patch.image.convertTo(image, CV_32F, patch.gain, patch.bias);
    const int flags = cv::INTER_LINEAR | cv::WARP_INVERSE_MAP;
    cv::warpAffine(image, values, m, tile.size(), flags, cv::BORDER_CONSTANT, 0);
    cv::warpAffine(FeatherWeights(patch.image.size(), feather_px), weights, m, tile.size(), flags,
                   cv::BORDER_CONSTANT, 0);
    weight_sum += weights;
    value_sum += weights.mul(values);
  }
  cv::Mat out = tile.clone();
  for (int y = 0; y < tile.rows; ++y) {
    const float* w = weight_sum.ptr<float>(y);
    const float* v = value_sum.ptr<float>(y);
    const uchar* base = tile.ptr<uchar>(y);
    uchar* o = out.ptr<uchar>(y);
    for (int x = 0; x < tile.cols; ++x) {
      if (w[x] <= 1e-6f) continue;
      const float patch_value = v[x] / w[x];
      float alpha = std::min(1.0f, w[x]);  // 1 inside a patch, falling to 0 at its border
      if (mode == BlendMode::kBlend && base[x] != 0) alpha *= 0.5f;
      if (base[x] == 0) alpha = 1.0f;  // nothing mapped here yet: the patch is all there is
      o[x] = cv::saturate_cast<uchar>(alpha * patch_value + (1 - alpha) * base[x]);
    }
  }
  return out;
}

std::pair<double, double> PhotometricFit(const cv::Mat& patch, const cv::Mat& mosaic) {
  CV_Assert(patch.size() == mosaic.size() && patch.type() == CV_8UC1 && mosaic.type() == CV_8UC1);
  // Robust line fit mosaic ≈ gain · patch + bias over pixel pairs: least squares, then pairs whose
  // residual exceeds 2.5 robust sigmas (floor that changed, dust) are dropped and the fit repeated.
  std::vector<std::pair<float, float>> pairs;  // (patch, mosaic)
  for (int y = 0; y < patch.rows; y += 2) {
    const uchar* p = patch.ptr<uchar>(y);
    const uchar* m = mosaic.ptr<uchar>(y);
    for (int x = 0; x < patch.cols; x += 2) {
      if (m[x] != 0) pairs.emplace_back(p[x], m[x]);
    }
  }
  double gain = 1.0, bias = 0.0;
  for (int iteration = 0; iteration < 4 && pairs.size() >= 100; ++iteration) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const auto& [x, y] : pairs) {
      n += 1;
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
    }
    const double var = sxx - sx * sx / n;
    if (var < 1e-3 * n) return {1.0, 0.0};  // a flat patch: nothing to fit
    gain = (sxy - sx * sy / n) / var;
    bias = (sy - gain * sx) / n;
    std::vector<float> residuals;
    residuals.reserve(pairs.size());
    for (const auto& [x, y] : pairs) residuals.push_back(std::abs(y - (gain * x + bias)));
    std::vector<float> sorted = residuals;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double limit = std::max(1.0, 2.5 * 1.4826 * sorted[sorted.size() / 2]);
    std::vector<std::pair<float, float>> kept;
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (residuals[i] <= limit) kept.push_back(pairs[i]);
    }
    pairs = std::move(kept);
  }
  return pairs.size() >= 100 ? std::make_pair(gain, bias) : std::make_pair(1.0, 0.0);
}

}  // namespace fleetloc::mapping
