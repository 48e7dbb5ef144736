// Route fitting, arc-length parametrization and the speed profile.
#include "sim/route.h"

#include <algorithm>
#include <cmath>

#include "geometry/camera_model.h"

namespace fleetloc::sim {
namespace {

constexpr int kCurveSamples = 16384;  // arc-length table size (spacing ≤ length / 16384)
constexpr int kFitIterations = 24;    // bisection steps on the margin

// The normalized curve in [-1, 1]² at tau and its derivative.
void UnitCurve(RouteShape shape, double tau, Eigen::Vector2d* p, Eigen::Vector2d* dp) {
  const double c = std::cos(tau), s = std::sin(tau);
  if (shape == RouteShape::kFigureEight) {
    *p = {s, std::sin(2.0 * tau)};
    *dp = {c, 2.0 * std::cos(2.0 * tau)};
    return;
  }
  // Superellipse |x|^4 + |y|^4 = 1 in polar form r(tau) = (c^4 + s^4)^(-1/4).
  const double u = c * c * c * c + s * s * s * s;
  const double r = std::pow(u, -0.25);
  const double dr = (c * c * c * s - s * s * s * c) * std::pow(u, -1.25);
  *p = {r * c, r * s};
  *dp = {dr * c - r * s, dr * s + r * c};
}

struct Box {
  Eigen::Vector2d min, max;
};

Box BoundingBox(const geometry::ConvexPolygon& polygon) {
  Box box{polygon.front(), polygon.front()};
  for (const auto& p : polygon) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

}  // namespace

Route::Route(const geometry::ConvexPolygon& floor_m, double margin_m, const RouteOptions& options,
             double floor_resolution_m)
    : options_(options), speed_m_s_(options.speed_px_s * floor_resolution_m), margin_m_(margin_m) {
  const Box box = BoundingBox(floor_m);
  centre_m_ = 0.5 * (box.min + box.max);
  half_extent_m_ = (0.5 * (box.max - box.min)).array() - margin_m;
  half_extent_m_ = half_extent_m_.cwiseMax(1e-9);
  tau_.resize(kCurveSamples + 1);
  cumulative_m_.resize(kCurveSamples + 1);
  Eigen::Vector2d previous, tangent;
  Evaluate(0.0, &previous, &tangent);
  cumulative_m_[0] = tau_[0] = 0.0;
  for (int i = 1; i <= kCurveSamples; ++i) {
    tau_[i] = 2.0 * M_PI * i / kCurveSamples;
    Eigen::Vector2d point;
    Evaluate(tau_[i], &point, &tangent);
    cumulative_m_[i] = cumulative_m_[i - 1] + (point - previous).norm();
    previous = point;
  }
}

void Route::Evaluate(double tau, Eigen::Vector2d* point, Eigen::Vector2d* tangent) const {
  Eigen::Vector2d p, dp;
  UnitCurve(options_.shape, tau, &p, &dp);
  *point = centre_m_ + half_extent_m_.cwiseProduct(p);
  *tangent = half_extent_m_.cwiseProduct(dp);
}

geometry::Pose2 Route::CameraPoseAtArcLength(double s_m) const {
  const double length = length_m();
  double s = std::fmod(s_m, length);
  if (s < 0) s += length;
  const auto it = std::upper_bound(cumulative_m_.begin(), cumulative_m_.end(), s);
  const size_t i = std::clamp<size_t>(it - cumulative_m_.begin(), 1, cumulative_m_.size() - 1);
  const double span = cumulative_m_[i] - cumulative_m_[i - 1];
  const double f = span > 0 ? (s - cumulative_m_[i - 1]) / span : 0.0;
  const double tau = tau_[i - 1] + f * (tau_[i] - tau_[i - 1]);
  Eigen::Vector2d point, tangent;
  Evaluate(tau, &point, &tangent);
  return {point.x(), point.y(),
          geometry::WrapAngle(std::atan2(tangent.y(), tangent.x()) + options_.crab_rad)};
}

double Route::ArcLengthAt(double elapsed_s) const {
  double travelled = elapsed_s;
  const double f = options_.speed_variation_fraction;
  if (f > 0) {
    const double w = 2.0 * M_PI / options_.speed_variation_period_s;
    travelled += f / w * (1.0 - std::cos(w * elapsed_s));  // ∫ f·sin(w t) dt
  }
  return options_.start_fraction * length_m() + speed_m_s_ * travelled;
}

double Route::SpeedAt(double elapsed_s) const {
  const double w = 2.0 * M_PI / options_.speed_variation_period_s;
  return speed_m_s_ * (1.0 + options_.speed_variation_fraction * std::sin(w * elapsed_s));
}

double Route::MinFloorOverlap(const geometry::ConvexPolygon& floor_m,
                              const geometry::ConvexPolygon& footprint_ground, int samples) const {
  const double footprint_area = std::abs(geometry::Area(footprint_ground));
  double worst = 1.0;
  for (int i = 0; i < samples; ++i) {
    const geometry::Pose2 pose = CameraPoseAtArcLength(length_m() * i / samples);
    const auto inside = geometry::ClipConvex(PlaceFootprint(footprint_ground, pose), floor_m);
    worst = std::min(worst, std::abs(geometry::Area(inside)) / footprint_area);
  }
  return worst;
}

Result<Route> Route::Fit(const geometry::ConvexPolygon& floor_m,
                         const geometry::ConvexPolygon& footprint_ground,
                         const RouteOptions& options, double floor_resolution_m) {
  const Box floor = BoundingBox(floor_m);
  const Box frame = BoundingBox(footprint_ground);
  const double half_diagonal = 0.5 * (frame.max - frame.min).norm();
  const double half_floor = 0.5 * (floor.max - floor.min).minCoeff();
  // Sample the route at least every quarter of the frame's shorter side.
  const double frame_side = (frame.max - frame.min).minCoeff();
  auto samples_for = [&](const Route& route) {
    return static_cast<int>(std::clamp(4.0 * route.length_m() / frame_side, 720.0, 20000.0));
  };
  auto good = [&](const Route& route) {
    return route.MinFloorOverlap(floor_m, footprint_ground, samples_for(route)) >=
           options.min_floor_overlap_fraction;
  };
  double lo = 0.0, hi = std::min(half_diagonal, 0.98 * half_floor);
  Route best(floor_m, hi, options, floor_resolution_m);
  if (!good(best)) {
    return InvalidInput("the floor (" + std::to_string(floor.max.x() - floor.min.x()) + " × " +
                        std::to_string(floor.max.y() - floor.min.y()) +
                        " m) is too small for the camera footprint to keep " +
                        std::to_string(options.min_floor_overlap_fraction) + " of it on the floor");
  }
  if (Route widest(floor_m, lo, options, floor_resolution_m); good(widest)) return widest;
  for (int i = 0; i < kFitIterations; ++i) {
    const double mid = 0.5 * (lo + hi);
    Route candidate(floor_m, mid, options, floor_resolution_m);
    if (good(candidate)) {
      hi = mid;
      best = candidate;
    } else {
      lo = mid;
    }
  }
  return best;
}

}  // namespace fleetloc::sim
