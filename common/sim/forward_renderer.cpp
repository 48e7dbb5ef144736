// Forward-camera rendering of the corridor (see forward_renderer.h).
#include "sim/forward_renderer.h"

#include <cmath>

#include "sim/corridor_raycast.h"
#include "sim/photometric.h"
#include "sim/random.h"

namespace fleetloc::sim {
namespace {

// Ambient light and two directional lights from either side of the corridor: walls (±y faces)
// are lit, cross faces (±x: door reveals, cupboard fronts, wall ends) are darker, so every
// vertical corner between them shows as an edge.
double Shading(const Eigen::Vector3d& normal) {
  static const Eigen::Vector3d kLight1 = Eigen::Vector3d(0.15, 0.8, 0.6).normalized();
  static const Eigen::Vector3d kLight2 = Eigen::Vector3d(-0.1, -0.8, 0.6).normalized();
  return 0.35 + 0.5 * std::max(0.0, normal.dot(kLight1)) +
         0.45 * std::max(0.0, normal.dot(kLight2));
}

Eigen::Vector3d ToMap(const geometry::Pose2& vehicle, const Eigen::Vector3d& base) {
  const Eigen::Vector2d xy = vehicle * Eigen::Vector2d(base.x(), base.y());
  return {xy.x(), xy.y(), base.z()};
}

Eigen::Vector3d RotateToMap(const geometry::Pose2& vehicle, const Eigen::Vector3d& direction) {
  const double c = std::cos(vehicle.theta), s = std::sin(vehicle.theta);
  return {c * direction.x() - s * direction.y(), s * direction.x() + c * direction.y(),
          direction.z()};
}

}  // namespace

Status Validate(const ForwardRenderOptions& options) {
  if (options.supersample < 1 || options.supersample > 8) {
    return InvalidInput("forward render: supersample must be in [1, 8]");
  }
  if (!(options.exposure_dn > 0)) return InvalidInput("forward render: exposure_dn must be > 0");
  const RenderOptions& p = options.photometric;
  if (!(p.lighting_amplitude >= 0 && p.lighting_amplitude < 1)) {
    return InvalidInput("forward render: photometric.lighting_amplitude must be in [0, 1)");
  }
  if (!(p.blur_sigma_px >= 0))
    return InvalidInput("forward render: photometric.blur_sigma_px must be >= 0");
  return Status::Ok();
}

ForwardRenderer::ForwardRenderer(const mapmatch::ForwardCamera& camera,
                                 const ForwardRenderOptions& options)
    : camera_(camera), options_(options) {
  FLEETLOC_CHECK(Validate(options).ok());
  const int k = options.supersample;
  const cv::Size size = camera.image_size();
  std::vector<Eigen::Vector2d> subpixels;
  subpixels.reserve(static_cast<std::size_t>(size.area()) * k * k);
  for (int v = 0; v < size.height; ++v) {
    for (int u = 0; u < size.width; ++u) {
      for (int i = 0; i < k * k; ++i) {
        // Pixel centres are at integer coordinates (OpenCV); subpixels tile [-0.5, 0.5)².
        subpixels.emplace_back(u - 0.5 + (i % k + 0.5) / k, v - 0.5 + (i / k + 0.5) / k);
      }
    }
  }
  const std::vector<Eigen::Vector2d> normalized = camera.Undistort(subpixels);
  rays_.reserve(normalized.size());
  for (const Eigen::Vector2d& n : normalized) rays_.push_back(camera.RayDirection(n).normalized());
}

double ForwardRenderer::RayRadiance(const CorridorScene& scene, const Eigen::Vector3d& origin,
                                    const Eigen::Vector3d& direction) const {
  const std::optional<RayHit> hit = CastRay(scene, origin, direction);
  return hit ? options_.exposure_dn * hit->albedo * Shading(hit->normal) : 0.0;
}

cv::Mat ForwardRenderer::Radiance(const CorridorScene& scene,
                                  const geometry::Pose2& vehicle) const {
  const int samples = options_.supersample * options_.supersample;
  const Eigen::Vector3d origin = ToMap(vehicle, camera_.center());
  cv::Mat radiance(camera_.image_size(), CV_32FC1);
  auto ray = rays_.begin();
  for (int v = 0; v < radiance.rows; ++v) {
    for (int u = 0; u < radiance.cols; ++u) {
      double sum = 0.0;
      for (int i = 0; i < samples; ++i, ++ray) {
        sum += RayRadiance(scene, origin, RotateToMap(vehicle, *ray));
      }
      radiance.at<float>(v, u) = static_cast<float>(sum / samples);
    }
  }
  return radiance;
}

cv::Mat ForwardRenderer::Render(const CorridorScene& scene, const geometry::Pose2& vehicle,
                                std::uint64_t seed) const {
  cv::RNG rng(MixSeed(seed, 0xf02a));
  const RenderOptions& photometric = options_.photometric;
  cv::Mat radiance = Radiance(scene, vehicle);
  const cv::Mat light = LightingField(radiance.size(), photometric.lighting_amplitude, rng);
  ApplyBlur(photometric.blur_sigma_px, Eigen::Vector2d::Zero(), &radiance);
  return ApplySensor(radiance, light, DrawSensor(photometric, rng), photometric, rng);
}

double ForwardRenderer::EdgeContrast(const CorridorScene& scene, const geometry::Pose2& vehicle,
                                     const Eigen::Vector2d& base, double height_m) const {
  constexpr double kOffsetPx = 3.0;
  const Eigen::Vector3d origin = ToMap(vehicle, camera_.center());
  const auto radiance_at = [&](const Eigen::Vector2d& pixel) {
    const Eigen::Vector2d normalized = camera_.Undistort(std::span(&pixel, 1))[0];
    const Eigen::Vector3d ray = camera_.RayDirection(normalized).normalized();
    return RayRadiance(scene, origin, RotateToMap(vehicle, ray));
  };
  double weakest = INFINITY;
  for (double z = 0.02; z <= height_m + 1e-9; z += 0.04) {
    const Eigen::Vector2d p = camera_.Project({base.x(), base.y(), z}).value();
    const Eigen::Vector2d up = camera_.Project({base.x(), base.y(), z + 0.05}).value() - p;
    const Eigen::Vector2d across = Eigen::Vector2d(-up.y(), up.x()).normalized() * kOffsetPx;
    weakest = std::min(weakest, std::abs(radiance_at(p + across) - radiance_at(p - across)));
  }
  return weakest;
}

std::vector<VisibleLandmark> ForwardRenderer::VisibleLandmarks(
    const CorridorScene& scene, const geometry::Pose2& vehicle,
    const VisibilityOptions& options) const {
  const Eigen::Vector3d origin = ToMap(vehicle, camera_.center());
  const cv::Size size = camera_.image_size();
  const auto seen = [&](const Eigen::Vector2d& base, double z) {
    Result<Eigen::Vector2d> pixel = camera_.Project({base.x(), base.y(), z});
    if (!pixel.ok() || pixel->x() < options.margin_px || pixel->y() < options.margin_px ||
        pixel->x() > size.width - 1 - options.margin_px ||
        pixel->y() > size.height - 1 - options.margin_px) {
      return false;
    }
    const Eigen::Vector3d to_point = ToMap(vehicle, {base.x(), base.y(), z}) - origin;
    const std::optional<double> hit = HitDistance(scene, origin, to_point.normalized());
    return hit && *hit > to_point.norm() - options.occlusion_tolerance_m;
  };
  std::vector<VisibleLandmark> visible;
  for (std::size_t i = 0; i < scene.landmarks.size(); ++i) {
    const Eigen::Vector2d base = vehicle.Inverse() * scene.landmarks[i];
    bool edge_seen = true;
    for (double z = 0.0; edge_seen && z <= options.edge_height_m + 1e-9; z += 0.05) {
      edge_seen = seen(base, z);
    }
    if (!edge_seen) continue;
    VisibleLandmark landmark{static_cast<int>(i), scene.landmarks[i], base,
                             camera_.Project({base.x(), base.y(), 0.0}).value(),
                             (base - camera_.center().head<2>()).norm()};
    landmark.contrast_dn = EdgeContrast(scene, vehicle, base, options.edge_height_m);
    visible.push_back(landmark);
  }
  return visible;
}

}  // namespace fleetloc::sim
