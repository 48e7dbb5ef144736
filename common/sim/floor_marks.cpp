// Procedural tyre marks and debris (per-cell Poisson fields) and the vehicle's shadow.
#include "sim/floor_marks.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "sim/cell_field.h"

namespace fleetloc::sim {
namespace {

constexpr std::uint64_t kTyreStream = 0x74797265;    // "tyre"
constexpr std::uint64_t kDebrisStream = 0x64656272;  // "debr"
constexpr int kAreaSamples = 2048;                   // Monte Carlo draws for the mean mark area

// Sizes in camera pixels (0.5 mm at the default resolution).
constexpr double kTyreMinWidthPx = 20.0, kTyreMaxWidthPx = 80.0;
constexpr double kTyreMinHalfLengthPx = 100.0, kTyreMaxHalfLengthPx = 600.0;
constexpr double kTyreMinRadiusPx = 400.0, kTyreMaxRadiusPx = 6000.0;
constexpr double kTreadMinPeriodPx = 6.0, kTreadMaxPeriodPx = 20.0;
constexpr double kTyreEdgePx = 2.0;     // soft edge across the band
constexpr double kTyreFadeShare = 0.2;  // share of the half length over which the ends fade out
constexpr double kDebrisMinRadiusPx = 4.0, kDebrisMaxRadiusPx = 30.0;
constexpr int kDebrisShift = 4;  // sub-pixel bits of the polygon fill

double LogUniform(double lo, double hi, cv::RNG& rng) {
  return lo * std::pow(hi / lo, rng.uniform(0.0, 1.0));
}

double PolygonArea(const std::vector<Eigen::Vector2d>& v) {
  double twice = 0.0;
  for (size_t i = 0; i < v.size(); ++i) {
    const Eigen::Vector2d& a = v[i];
    const Eigen::Vector2d& b = v[(i + 1) % v.size()];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return std::abs(twice) / 2.0;
}

// The pixel box within `reach_m` of map point `centre_m` (not clipped to the image).
cv::Rect PixelBox(const Affine2& map_to_pixel, const Eigen::Vector2d& centre_m, double reach_m) {
  const Eigen::Vector2d c = map_to_pixel * centre_m.homogeneous();
  const double reach_px = reach_m * std::max(map_to_pixel.row(0).head<2>().norm(),
                                             map_to_pixel.row(1).head<2>().norm());
  const int u0 = static_cast<int>(std::floor(c.x() - reach_px));
  const int v0 = static_cast<int>(std::floor(c.y() - reach_px));
  const int u1 = static_cast<int>(std::ceil(c.x() + reach_px)) + 1;
  const int v1 = static_cast<int>(std::ceil(c.y() + reach_px)) + 1;
  return {u0, v0, u1 - u0, v1 - v0};
}

// The mark's opacity at map point p: the band across the arc, faded at the ends, with the tread.
double TyreAlpha(const TyreMark& mark, const Eigen::Vector2d& p, double edge_m) {
  const Eigen::Vector2d normal(-std::sin(mark.angle_rad), std::cos(mark.angle_rad));
  const Eigen::Vector2d curvature_centre = mark.centre_m + mark.radius_m * normal;
  const Eigen::Vector2d from = mark.centre_m - curvature_centre, to = p - curvature_centre;
  const double turn = std::atan2(from.x() * to.y() - from.y() * to.x(), from.dot(to));
  if (std::abs(turn) > M_PI / 2) return 0.0;
  const double along = std::abs(turn * mark.radius_m);
  const double across = std::abs(to.norm() - std::abs(mark.radius_m));
  const double band = std::clamp(0.5 + (mark.width_m / 2 - across) / edge_m, 0.0, 1.0);
  const double fade =
      std::clamp((mark.half_length_m - along) / (kTyreFadeShare * mark.half_length_m), 0.0, 1.0);
  const bool stripe = std::sin(2 * M_PI * along / mark.tread_period_m) > 0;
  return mark.opacity * band * fade * (stripe ? 1.0 : 0.6);
}

void CompositeTyreMark(const TyreMark& mark, const Affine2& pixel_to_map,
                       const Affine2& map_to_pixel, double reach_m, double edge_m, cv::Mat* image,
                       cv::Mat* covered) {
  const cv::Rect box =
      PixelBox(map_to_pixel, mark.centre_m, reach_m) & cv::Rect(0, 0, image->cols, image->rows);
  for (int v = box.y; v < box.y + box.height; ++v) {
    auto* row = image->ptr<float>(v);
    auto* cover = covered->ptr<std::uint8_t>(v);
    for (int u = box.x; u < box.x + box.width; ++u) {
      const double alpha =
          TyreAlpha(mark, pixel_to_map * Eigen::Vector2d(u + 0.5, v + 0.5).homogeneous(), edge_m);
      if (alpha <= 0) continue;
      row[u] = static_cast<float>(row[u] * (1.0 - alpha) + alpha * mark.level_dn);
      if (alpha >= 0.5 * mark.opacity) cover[u] = 1;
    }
  }
}

void CompositeDebris(const Debris& debris, const Affine2& pixel_to_map, const Affine2& map_to_pixel,
                     double reach_m, cv::Mat* image, cv::Mat* covered) {
  // The polygon is filled over its whole box, then clipped: anti-aliasing clipped at the image
  // edge would differ from one view to the next.
  const cv::Rect box = PixelBox(map_to_pixel, debris.centre_m, reach_m);
  const cv::Rect inside = box & cv::Rect(0, 0, image->cols, image->rows);
  if (inside.area() == 0) return;
  std::vector<cv::Point> polygon;
  for (const Eigen::Vector2d& vertex : debris.vertices_m) {
    const Eigen::Vector2d px =
        map_to_pixel * (debris.centre_m + vertex).homogeneous() - Eigen::Vector2d(box.x, box.y);
    polygon.emplace_back(static_cast<int>(std::lround((px.x() - 0.5) * (1 << kDebrisShift))),
                         static_cast<int>(std::lround((px.y() - 0.5) * (1 << kDebrisShift))));
  }
  cv::Mat mask = cv::Mat::zeros(box.size(), CV_8UC1);
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{polygon}, 255, cv::LINE_AA, kDebrisShift);
  for (int v = inside.y; v < inside.y + inside.height; ++v) {
    auto* row = image->ptr<float>(v);
    auto* cover = covered->ptr<std::uint8_t>(v);
    const auto* m = mask.ptr<std::uint8_t>(v - box.y) - box.x;
    for (int u = inside.x; u < inside.x + inside.width; ++u) {
      if (m[u] == 0) continue;
      const double alpha = m[u] / 255.0;
      const Eigen::Vector2d p = pixel_to_map * Eigen::Vector2d(u + 0.5, v + 0.5).homogeneous();
      const double level = debris.level_dn + debris.shading_dn_per_m.dot(p - debris.centre_m);
      row[u] = static_cast<float>(row[u] * (1.0 - alpha) + alpha * level);
      if (alpha >= 0.5) cover[u] = 1;
    }
  }
}

// Items per cell for an average `fraction` of the floor covered by items of mean area `area_m2`
// (Boolean model: coverage = 1 − exp(−density · mean area)).
double PerCell(double fraction, double area_m2, double cell_m) {
  if (fraction <= 0 || area_m2 <= 0) return 0.0;
  return -std::log(1.0 - fraction) / area_m2 * cell_m * cell_m;
}

}  // namespace

FloorMarks::FloorMarks(const RenderOptions& options, double pixel_size_m, std::uint64_t seed)
    : options_(options), pixel_size_m_(pixel_size_m), seed_(seed) {
  tyre_reach_m_ = (kTyreMaxHalfLengthPx + kTyreMaxWidthPx) * pixel_size_m;
  debris_reach_m_ = (kDebrisMaxRadiusPx + 2.0) * pixel_size_m;
  cell_m_ = 4.0 * tyre_reach_m_;
  cv::RNG rng(MixSeed(seed, kTyreStream + 1));
  double tyre_area = 0.0, debris_area = 0.0;
  for (int i = 0; i < kAreaSamples; ++i) {
    const TyreMark mark = DrawTyreMark(rng, Eigen::Vector2d::Zero());
    tyre_area += 2.0 * mark.half_length_m * mark.width_m / kAreaSamples;
    debris_area += PolygonArea(DrawDebris(rng, Eigen::Vector2d::Zero()).vertices_m) / kAreaSamples;
  }
  tyre_marks_per_cell_ = PerCell(options.tyre_mark_fraction, tyre_area, cell_m_);
  debris_per_cell_ = PerCell(options.debris_fraction, debris_area, cell_m_);
}

TyreMark FloorMarks::DrawTyreMark(cv::RNG& rng, const Eigen::Vector2d& cell_origin_m) const {
  TyreMark mark;
  mark.centre_m =
      cell_origin_m + Eigen::Vector2d(rng.uniform(0.0, cell_m_), rng.uniform(0.0, cell_m_));
  mark.angle_rad = rng.uniform(0.0, 2 * M_PI);
  const double radius_px = LogUniform(kTyreMinRadiusPx, kTyreMaxRadiusPx, rng);
  mark.radius_m = (rng.uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0) * radius_px * pixel_size_m_;
  mark.half_length_m = rng.uniform(kTyreMinHalfLengthPx, kTyreMaxHalfLengthPx) * pixel_size_m_;
  mark.width_m = rng.uniform(kTyreMinWidthPx, kTyreMaxWidthPx) * pixel_size_m_;
  mark.tread_period_m = rng.uniform(kTreadMinPeriodPx, kTreadMaxPeriodPx) * pixel_size_m_;
  mark.opacity = rng.uniform(0.25, 0.6);
  mark.level_dn = rng.uniform(15.0, 45.0);
  return mark;
}

Debris FloorMarks::DrawDebris(cv::RNG& rng, const Eigen::Vector2d& cell_origin_m) const {
  Debris debris;
  debris.centre_m =
      cell_origin_m + Eigen::Vector2d(rng.uniform(0.0, cell_m_), rng.uniform(0.0, cell_m_));
  const double radius_m = LogUniform(kDebrisMinRadiusPx, kDebrisMaxRadiusPx, rng) * pixel_size_m_;
  const int count = rng.uniform(5, 9);
  std::vector<double> angles(count);
  for (double& angle : angles) angle = rng.uniform(0.0, 2 * M_PI);
  std::sort(angles.begin(), angles.end());
  for (const double angle : angles) {
    debris.vertices_m.push_back(radius_m * rng.uniform(0.5, 1.0) *
                                Eigen::Vector2d(std::cos(angle), std::sin(angle)));
  }
  debris.level_dn = rng.uniform(0.0, 255.0);  // dark screws to white paper
  const double shading_angle = rng.uniform(0.0, 2 * M_PI);
  debris.shading_dn_per_m = rng.uniform(0.0, 30.0) / radius_m *
                            Eigen::Vector2d(std::cos(shading_angle), std::sin(shading_angle));
  return debris;
}

std::vector<TyreMark> FloorMarks::TyreMarksNear(const Eigen::Vector2d& min_m,
                                                const Eigen::Vector2d& max_m) const {
  return ItemsInBox<TyreMark>(
      seed_, kTyreStream, cell_m_, tyre_marks_per_cell_, min_m.array() - tyre_reach_m_,
      max_m.array() + tyre_reach_m_,
      [this](cv::RNG& rng, const Eigen::Vector2d& origin) { return DrawTyreMark(rng, origin); });
}

std::vector<Debris> FloorMarks::DebrisNear(const Eigen::Vector2d& min_m,
                                           const Eigen::Vector2d& max_m) const {
  return ItemsInBox<Debris>(
      seed_, kDebrisStream, cell_m_, debris_per_cell_, min_m.array() - debris_reach_m_,
      max_m.array() + debris_reach_m_,
      [this](cv::RNG& rng, const Eigen::Vector2d& origin) { return DrawDebris(rng, origin); });
}

double FloorMarks::Apply(const Eigen::Matrix<double, 2, 3>& pixel_to_map,
                         const cv::Rect& count_region, cv::Mat* image) const {
  CV_Assert(image->type() == CV_32FC1);
  if (tyre_marks_per_cell_ <= 0 && debris_per_cell_ <= 0) return 0.0;
  Eigen::Vector2d min_m, max_m;
  ImageFootprint(pixel_to_map, image->size(), &min_m, &max_m);
  const Affine2 map_to_pixel = InvertAffine(pixel_to_map);
  cv::Mat covered = cv::Mat::zeros(image->size(), CV_8UC1);
  for (const TyreMark& mark : TyreMarksNear(min_m, max_m)) {
    CompositeTyreMark(mark, pixel_to_map, map_to_pixel, tyre_reach_m_, kTyreEdgePx * pixel_size_m_,
                      image, &covered);
  }
  for (const Debris& debris : DebrisNear(min_m, max_m)) {
    CompositeDebris(debris, pixel_to_map, map_to_pixel, debris_reach_m_, image, &covered);
  }
  return CoveredShare(covered, count_region);
}

cv::Mat ShadowField(cv::Size size, double fraction, double depth, double angle_rad,
                    double edge_px) {
  if (fraction <= 0) return {};
  // t: each pixel centre's distance along the direction towards the vehicle.
  const double nx = std::cos(angle_rad), ny = std::sin(angle_rad);
  cv::Mat t(size, CV_32FC1);
  for (int v = 0; v < size.height; ++v) {
    auto* row = t.ptr<float>(v);
    for (int u = 0; u < size.width; ++u)
      row[u] = static_cast<float>(nx * (u + 0.5) + ny * (v + 0.5));
  }
  // The edge where `fraction` of the pixels lie beyond it.
  std::vector<float> sorted(t.begin<float>(), t.end<float>());
  const size_t k =
      std::min(sorted.size() - 1,
               static_cast<size_t>((1.0 - fraction) * static_cast<double>(sorted.size())));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(k), sorted.end());
  const double edge = sorted[k];
  cv::Mat field(size, CV_32FC1);
  for (int v = 0; v < size.height; ++v) {
    const auto* in = t.ptr<float>(v);
    auto* out = field.ptr<float>(v);
    for (int u = 0; u < size.width; ++u) {
      const double shade = std::clamp(0.5 + (in[u] - edge) / std::max(edge_px, 1e-3), 0.0, 1.0);
      out[u] = static_cast<float>(1.0 - depth * shade);
    }
  }
  return field;
}

}  // namespace fleetloc::sim
