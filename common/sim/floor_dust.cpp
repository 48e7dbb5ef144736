// Procedural floor dust: per-cell Poisson blob fields and their soft compositing.
#include "sim/floor_dust.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "sim/cell_field.h"
#include "sim/random.h"

namespace fleetloc::sim {
namespace {

constexpr double kDarkShare = 0.7;     // share of dirt darker than a typical floor
constexpr double kMaxSoftness = 0.8;   // the opacity ramp reaches r = 1 + softness / 2
constexpr double kStreakLength = 3.0;  // streak semi-major axis in units of the drawn radius
constexpr double kMinStreakWidthPx = 0.75;
constexpr int kAreaSamples = 4096;  // Monte Carlo draws for the mean blob area

constexpr std::uint64_t kDustStream = 0x64757374;  // "dust"

}  // namespace

FloorDust::FloorDust(const RenderOptions& options, double pixel_size_m, std::uint64_t seed)
    : options_(options), pixel_size_m_(pixel_size_m), seed_(seed) {
  const double max_extent_px =
      options.dust_max_radius_px * kStreakLength * (1.0 + 0.5 * kMaxSoftness);
  max_extent_m_ = max_extent_px * pixel_size_m;
  cell_m_ = std::max(256.0, 8.0 * max_extent_px) * pixel_size_m;
  if (options.dust_fraction <= 0) return;
  // Boolean model: coverage = 1 - exp(-density · mean blob area).
  cv::RNG rng(MixSeed(seed, kDustStream + 1));
  double area_sum_m2 = 0.0;
  for (int i = 0; i < kAreaSamples; ++i) {
    const DustBlob blob = DrawBlob(rng, Eigen::Vector2d::Zero());
    area_sum_m2 += M_PI * blob.semi_major_m * blob.semi_minor_m;
  }
  density_per_m2_ = -std::log(1.0 - options.dust_fraction) / (area_sum_m2 / kAreaSamples);
}

DustBlob FloorDust::DrawBlob(cv::RNG& rng, const Eigen::Vector2d& cell_origin_m) const {
  DustBlob blob;
  blob.centre_m =
      cell_origin_m + Eigen::Vector2d(rng.uniform(0.0, cell_m_), rng.uniform(0.0, cell_m_));
  const double ratio = options_.dust_max_radius_px / options_.dust_min_radius_px;
  const double radius_px = options_.dust_min_radius_px * std::pow(ratio, rng.uniform(0.0, 1.0));
  if (rng.uniform(0.0, 1.0) < options_.dust_streak_fraction) {
    blob.semi_major_m = kStreakLength * radius_px * pixel_size_m_;
    blob.semi_minor_m =
        std::max(kMinStreakWidthPx, radius_px * rng.uniform(0.05, 0.15)) * pixel_size_m_;
  } else {
    blob.semi_major_m = radius_px * pixel_size_m_;
    blob.semi_minor_m = blob.semi_major_m * rng.uniform(0.5, 1.0);
  }
  blob.angle_rad = rng.uniform(0.0, M_PI);
  blob.softness = rng.uniform(0.2, kMaxSoftness);
  blob.opacity = rng.uniform(0.2, options_.dust_max_opacity);
  blob.level_dn =
      rng.uniform(0.0, 1.0) < kDarkShare ? rng.uniform(10.0, 70.0) : rng.uniform(180.0, 250.0);
  return blob;
}

std::vector<DustBlob> FloorDust::BlobsNear(const Eigen::Vector2d& min_m,
                                           const Eigen::Vector2d& max_m) const {
  const Eigen::Vector2d lo = min_m.array() - max_extent_m_, hi = max_m.array() + max_extent_m_;
  return ItemsInBox<DustBlob>(
      seed_, kDustStream, cell_m_, density_per_m2_ * cell_m_ * cell_m_, lo, hi,
      [this](cv::RNG& rng, const Eigen::Vector2d& origin) { return DrawBlob(rng, origin); });
}

double FloorDust::Apply(const Eigen::Matrix<double, 2, 3>& pixel_to_map,
                        const cv::Rect& count_region, cv::Mat* image) const {
  CV_Assert(image->type() == CV_32FC1);
  if (density_per_m2_ <= 0) return 0.0;
  const Affine2 map_to_pixel = InvertAffine(pixel_to_map);
  Eigen::Vector2d min_m, max_m;
  ImageFootprint(pixel_to_map, image->size(), &min_m, &max_m);
  cv::Mat covered = cv::Mat::zeros(image->size(), CV_8UC1);
  for (const DustBlob& blob : BlobsNear(min_m, max_m)) {
    Composite(blob, map_to_pixel, image, &covered);
  }
  return CoveredShare(covered, count_region);
}

void FloorDust::Composite(const DustBlob& blob, const Eigen::Matrix<double, 2, 3>& map_to_pixel,
                          cv::Mat* image, cv::Mat* covered) const {
  // q = Q · (pixel offset from the centre) is the offset in blob units (|q| = 1 on the ellipse).
  const Eigen::Matrix2d pixel_to_map = map_to_pixel.leftCols<2>().inverse();
  const double c = std::cos(blob.angle_rad), s = std::sin(blob.angle_rad);
  Eigen::Matrix2d axes;
  axes << c / blob.semi_major_m, s / blob.semi_major_m,  //
      -s / blob.semi_minor_m, c / blob.semi_minor_m;
  const Eigen::Matrix2d q_of_d = axes * pixel_to_map;
  const Eigen::Matrix2d d_of_q = q_of_d.inverse();
  const double reach = 1.0 + 0.5 * blob.softness;
  const Eigen::Vector2d centre = map_to_pixel * blob.centre_m.homogeneous();
  const double half_u = reach * d_of_q.row(0).norm(), half_v = reach * d_of_q.row(1).norm();
  const int u0 = std::max(0, static_cast<int>(std::floor(centre.x() - half_u)));
  const int u1 = std::min(image->cols - 1, static_cast<int>(std::ceil(centre.x() + half_u)));
  const int v0 = std::max(0, static_cast<int>(std::floor(centre.y() - half_v)));
  const int v1 = std::min(image->rows - 1, static_cast<int>(std::ceil(centre.y() + half_v)));
  for (int v = v0; v <= v1; ++v) {
    auto* row = image->ptr<float>(v);
    auto* cover = covered->ptr<std::uint8_t>(v);
    for (int u = u0; u <= u1; ++u) {
      const Eigen::Vector2d q =
          q_of_d * Eigen::Vector2d(u + 0.5 - centre.x(), v + 0.5 - centre.y());
      const double r = q.norm();
      const double mask = std::clamp(0.5 + (1.0 - r) / blob.softness, 0.0, 1.0);
      if (mask <= 0) continue;
      const double alpha = blob.opacity * mask;
      row[u] = static_cast<float>(row[u] * (1.0 - alpha) + alpha * blob.level_dn);
      if (r < 1.0) cover[u] = 1;
    }
  }
}

}  // namespace fleetloc::sim
