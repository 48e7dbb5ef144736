// A simulated vehicle run (docs/formats.md) over a floor: the route, frame and odometry times,
// ground truth, drifting odometry, the perturbed initial pose and, frame by frame, the rendered
// camera images. Pure: the caller writes the files.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "mosaic/raster_source.h"
#include "sim/camera_renderer.h"
#include "sim/route.h"
#include "sim/sim_options.h"

namespace fleetloc::sim {

struct SimSummary {
  int frames = 0;
  double duration_s = 0.0;  // first to last frame
  double speed_px_s = 0.0;  // mean footprint speed, floor pixels per second
  double speed_m_s = 0.0;
  double distance_m = 0.0;      // footprint path length over the run
  double route_length_m = 0.0;  // one lap
  double laps = 0.0;
  double route_margin_m = 0.0;              // how far the route keeps inside the floor's edges
  double overlapping_pairs_fraction = 0.0;  // successive frame pairs whose footprints overlap
  double mean_pair_overlap = 0.0;    // mean shared area of successive footprints / frame area
  double floor_fraction_seen = 0.0;  // share of the floor inside at least one footprint
  double min_frame_on_floor = 0.0;   // smallest share of a frame's footprint on the floor
  double odometry_drift_m = 0.0;     // odometry's position error relative to truth at the end
  double odometry_drift_rad = 0.0;   // and its heading error
};

// The simulated vehicles' downward camera: principal point at the image centre, mounted 0.40 m
// ahead of base_link, at `resolution_m` metres per pixel.
geometry::CameraModel DefaultSimCameraModel(int width_px, int height_px, double resolution_m);

class RunSimulator {
 public:
  // Plans a run over `floor` (level 0; must outlive the simulator) seen by `camera`.
  // InvalidInput for invalid options or camera, or a floor too small for the footprint.
  static Result<std::unique_ptr<RunSimulator>> Create(mosaic::RasterSource* floor,
                                                      const geometry::CameraModel& camera,
                                                      const SimOptions& options);

  int frame_count() const { return static_cast<int>(truth_.size()); }
  // base_link in map at each frame's capture time (truth.csv); the frame times are their t.
  const std::vector<geometry::StampedPose>& truth() const { return truth_; }
  // base_link in odom (odometry.csv), covering the frame times.
  const std::vector<geometry::StampedPose>& odometry() const { return odometry_; }
  // run.json's initial_pose: truth at the first frame perturbed by a draw from `sigma`.
  const geometry::Pose2& initial_pose() const { return initial_pose_; }
  const Eigen::Vector3d& initial_sigma() const { return options_.initial_pose.sigma; }
  const SimSummary& summary() const { return summary_; }
  // base_link in map at any time t (seconds, the run's clock).
  geometry::Pose2 TruthAt(double t_s) const { return BaseAt(t_s - options_.timing.start_time_s); }
  const Route& route() const { return route_; }

  // Renders frame i (0 ≤ i < frame_count()); deterministic for the seed, in any order.
  RenderedFrame RenderFrame(int i);

 private:
  RunSimulator(mosaic::RasterSource* floor, const geometry::CameraModel& camera,
               const SimOptions& options, Route route);
  void PlanTimes();
  void Summarize();
  // The floor's velocity across the image at elapsed time `elapsed_s` (for motion blur).
  Eigen::Vector2d ImageVelocity(double elapsed_s) const;
  // camera_ground in map at `elapsed_s`: on the route, a jump further after a kidnap.
  geometry::Pose2 CameraAt(double elapsed_s) const;
  geometry::Pose2 BaseAt(double elapsed_s) const;
  // What the wheels saw: base_link in map until a kidnap, then continued from where the vehicle
  // was picked up by its motion since being set down (no jump).
  geometry::Pose2 WheelBaseAt(double elapsed_s) const;

  geometry::CameraModel camera_;
  SimOptions options_;
  Route route_;
  CameraRenderer renderer_;
  mosaic::MosaicLayout layout_;
  geometry::ConvexPolygon floor_m_;
  std::vector<double> frame_elapsed_s_;
  std::vector<geometry::StampedPose> truth_;
  std::vector<geometry::StampedPose> odometry_;
  geometry::Pose2 initial_pose_;
  SimSummary summary_;
};

// The floor's outline in map metres (the level-0 raster's rectangle).
geometry::ConvexPolygon FloorOutline(const mosaic::MosaicLayout& layout);

}  // namespace fleetloc::sim
