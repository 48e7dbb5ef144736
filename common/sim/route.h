// The simulated vehicle's closed route: the camera footprint centre follows a smooth closed curve
// fitted inside the floor, parametrized by arc length, driven with a (possibly varying) speed.
#pragma once

#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "geometry/convex_polygon.h"
#include "geometry/footprint.h"
#include "geometry/pose2.h"
#include "sim/sim_options.h"

namespace fleetloc::sim {

class Route {
 public:
  // Fits the curve of `options.shape` into the axis-aligned map rectangle `floor_m` shrunk by the
  // smallest margin at which every footprint along the route keeps
  // options.min_floor_overlap_fraction of its area on the floor. `footprint_ground` is the
  // camera frame's outline in camera_ground metres (around the origin); `floor_resolution_m`
  // converts options.speed_px_s to metres. InvalidInput when even a route shrunk to the floor's
  // centre leaves too little of the frame on the floor.
  static Result<Route> Fit(const geometry::ConvexPolygon& floor_m,
                           const geometry::ConvexPolygon& footprint_ground,
                           const RouteOptions& options, double floor_resolution_m);

  double length_m() const { return cumulative_m_.back(); }
  double margin_m() const { return margin_m_; }

  // camera_ground in map at arc length s (any real s: the route is closed): the point on the curve,
  // theta = direction of travel + crab.
  geometry::Pose2 CameraPoseAtArcLength(double s_m) const;
  // Arc length reached `elapsed_s` after the start (start point plus the integrated speed).
  double ArcLengthAt(double elapsed_s) const;
  // Footprint speed at `elapsed_s`, metres per second.
  double SpeedAt(double elapsed_s) const;
  geometry::Pose2 CameraPoseAt(double elapsed_s) const {
    return CameraPoseAtArcLength(ArcLengthAt(elapsed_s));
  }

  // Smallest share of the footprint on the floor over `samples` points spread along the route.
  double MinFloorOverlap(const geometry::ConvexPolygon& floor_m,
                         const geometry::ConvexPolygon& footprint_ground, int samples) const;

 private:
  Route(const geometry::ConvexPolygon& floor_m, double margin_m, const RouteOptions& options,
        double floor_resolution_m);
  // The curve in map metres at parameter tau ∈ [0, 2π) and its derivative d/dtau.
  void Evaluate(double tau, Eigen::Vector2d* point, Eigen::Vector2d* tangent) const;

  RouteOptions options_;
  double speed_m_s_ = 0.0;
  double margin_m_ = 0.0;
  Eigen::Vector2d centre_m_;
  Eigen::Vector2d half_extent_m_;
  std::vector<double> tau_;           // dense samples of the curve parameter ...
  std::vector<double> cumulative_m_;  // ... and the arc length reached there (closed: last = 2π)
};

// Footprints live in geometry (shared with mapping); the simulator's code names them here.
using geometry::FootprintInGround;
using geometry::PlaceFootprint;

}  // namespace fleetloc::sim
