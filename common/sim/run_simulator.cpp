// Run planning (times, truth, odometry, initial pose), its summary, and frame rendering.
#include "sim/run_simulator.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "sim/odometry_model.h"
#include "sim/random.h"

namespace fleetloc::sim {

geometry::CameraModel DefaultSimCameraModel(int width_px, int height_px, double resolution_m) {
  geometry::CameraModel camera;
  camera.width_px = width_px;
  camera.height_px = height_px;
  camera.cx_px = 0.5 * width_px;
  camera.cy_px = 0.5 * height_px;
  camera.resolution_m = resolution_m;
  camera.mount = {0.40, 0.0, 0.0};
  return camera;
}

namespace {

constexpr std::uint64_t kTimeStream = 0x74696d65;     // "time"
constexpr std::uint64_t kInitialStream = 0x696e6974;  // "init"
constexpr int kCoverageGridPx = 1024;                 // longest side of the seen-floor grid
constexpr int kPolygonShiftBits = 4;                  // sub-cell precision of fillConvexPoly
constexpr double kVelocityStepS = 1e-3;
constexpr double kMaxResolutionRatio = 8.0;  // camera vs floor metres per pixel

Status ValidateCamera(const geometry::CameraModel& c) {
  if (c.width_px < 8 || c.height_px < 8 || c.width_px > 16384 || c.height_px > 16384) {
    return InvalidInput("camera size " + std::to_string(c.width_px) + "×" +
                        std::to_string(c.height_px) + " must be within 8..16384 pixels");
  }
  if (!(c.resolution_m > 0) || !std::isfinite(c.resolution_m) || !std::isfinite(c.cx_px) ||
      !std::isfinite(c.cy_px)) {
    return InvalidInput("camera resolution must be positive and the principal point finite");
  }
  return Status::Ok();
}

double SharedFraction(const geometry::ConvexPolygon& a, const geometry::ConvexPolygon& b) {
  return std::abs(geometry::Area(geometry::ClipConvex(a, b))) / std::abs(geometry::Area(a));
}

// Share of the floor inside at least one of the footprints (map metres), rasterized on a grid of
// at most kCoverageGridPx cells per side.
double FloorFractionSeen(const mosaic::MosaicLayout& layout,
                         const std::vector<geometry::ConvexPolygon>& footprints) {
  const double cell_px = std::max(
      1.0, static_cast<double>(std::max(layout.width_px, layout.height_px)) / kCoverageGridPx);
  cv::Mat seen = cv::Mat::zeros(static_cast<int>(std::ceil(layout.height_px / cell_px)),
                                static_cast<int>(std::ceil(layout.width_px / cell_px)), CV_8UC1);
  for (const geometry::ConvexPolygon& footprint : footprints) {
    std::vector<cv::Point> cells;
    for (const Eigen::Vector2d& corner : footprint) {
      const Eigen::Vector2d uv =
          layout.geo.MapToPixel(corner) / cell_px * static_cast<double>(1 << kPolygonShiftBits);
      cells.emplace_back(static_cast<int>(std::lround(uv.x())),
                         static_cast<int>(std::lround(uv.y())));
    }
    cv::fillConvexPoly(seen, cells, cv::Scalar(255), cv::LINE_8, kPolygonShiftBits);
  }
  return static_cast<double>(cv::countNonZero(seen)) / static_cast<double>(seen.total());
}

}  // namespace

geometry::ConvexPolygon FloorOutline(const mosaic::MosaicLayout& layout) {
  const Eigen::Vector2d top_left = layout.geo.PixelToMap({0, 0});
  const Eigen::Vector2d bottom_right = layout.geo.PixelToMap({layout.width_px, layout.height_px});
  return geometry::Rectangle(top_left.x(), bottom_right.y(), bottom_right.x(), top_left.y());
}

Result<std::unique_ptr<RunSimulator>> RunSimulator::Create(mosaic::RasterSource* floor,
                                                           const geometry::CameraModel& camera,
                                                           const SimOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  FLEETLOC_RETURN_IF_ERROR(ValidateCamera(camera));
  const mosaic::MosaicLayout& layout = floor->layout();
  if (layout.width_px <= 0 || layout.height_px <= 0 || !(layout.geo.resolution > 0)) {
    return InvalidInput("the floor raster is empty or has no positive resolution");
  }
  const double scale = camera.resolution_m / layout.geo.resolution;
  if (scale < 1.0 / kMaxResolutionRatio || scale > kMaxResolutionRatio) {
    return InvalidInput("camera resolution " + std::to_string(camera.resolution_m) +
                        " m/px is too far from the floor's " +
                        std::to_string(layout.geo.resolution) + " m/px (at most 8× apart)");
  }
  Result<Route> route = Route::Fit(FloorOutline(layout), FootprintInGround(camera), options.route,
                                   layout.geo.resolution);
  if (!route.ok()) return route.status();
  std::unique_ptr<RunSimulator> sim(
      new RunSimulator(floor, camera, options, std::move(route).value()));
  sim->PlanTimes();
  sim->Summarize();
  return sim;
}

RunSimulator::RunSimulator(mosaic::RasterSource* floor, const geometry::CameraModel& camera,
                           const SimOptions& options, Route route)
    : camera_(camera),
      options_(options),
      route_(std::move(route)),
      renderer_(floor, camera, options.render, options.seed),
      layout_(floor->layout()),
      floor_m_(FloorOutline(floor->layout())) {}

geometry::Pose2 RunSimulator::CameraAt(double elapsed_s) const {
  const KidnapOptions& kidnap = options_.kidnap;
  const double jump_m =
      kidnap.enabled() && elapsed_s >= kidnap.at_s ? kidnap.jump_fraction * route_.length_m() : 0.0;
  return route_.CameraPoseAtArcLength(route_.ArcLengthAt(elapsed_s) + jump_m);
}

geometry::Pose2 RunSimulator::BaseAt(double elapsed_s) const {
  return CameraAt(elapsed_s) * camera_.mount.Inverse();
}

geometry::Pose2 RunSimulator::WheelBaseAt(double elapsed_s) const {
  const KidnapOptions& kidnap = options_.kidnap;
  if (!kidnap.enabled() || elapsed_s < kidnap.at_s) return BaseAt(elapsed_s);
  const geometry::Pose2 picked_up = route_.CameraPoseAt(kidnap.at_s) * camera_.mount.Inverse();
  return picked_up * geometry::Between(BaseAt(kidnap.at_s), BaseAt(elapsed_s));
}

void RunSimulator::PlanTimes() {
  const TimingOptions& timing = options_.timing;
  cv::RNG rng(MixSeed(options_.seed, kTimeStream));
  for (int i = 0; i < timing.frames; ++i) {
    const double jitter = rng.uniform(-timing.frame_jitter_s, timing.frame_jitter_s);
    const double elapsed = timing.frame_delay_s + i / timing.frame_rate_hz + jitter;
    frame_elapsed_s_.push_back(elapsed);
    truth_.push_back({timing.start_time_s + elapsed, BaseAt(elapsed)});
  }
  // Odometry from the start to one period past the last frame.
  const double period = 1.0 / timing.odometry_rate_hz;
  const int samples = static_cast<int>(std::ceil((frame_elapsed_s_.back() + period) / period)) + 1;
  std::vector<geometry::StampedPose> odometry_truth;
  for (int k = 0; k < samples; ++k) {
    const double jitter =
        k == 0 ? 0.0 : rng.uniform(-timing.odometry_jitter_s, timing.odometry_jitter_s);
    const double elapsed = k * period + jitter;
    odometry_truth.push_back({timing.start_time_s + elapsed, WheelBaseAt(elapsed)});
  }
  odometry_ = SimulateOdometry(odometry_truth, options_.odometry, options_.seed);
  // Odometry drift at the end, with odom aligned to truth at the start.
  const geometry::Pose2 align = odometry_truth.front().pose * odometry_.front().pose.Inverse();
  const geometry::Pose2 drift =
      geometry::Between(odometry_truth.back().pose, align * odometry_.back().pose);
  summary_.odometry_drift_m = std::hypot(drift.x, drift.y);
  summary_.odometry_drift_rad = std::abs(drift.theta);

  cv::RNG init_rng(MixSeed(options_.seed, kInitialStream));
  initial_pose_ = truth_.front().pose;
  if (options_.initial_pose.perturb) {
    const Eigen::Vector3d& sigma = options_.initial_pose.sigma;
    initial_pose_.x += init_rng.gaussian(sigma.x());
    initial_pose_.y += init_rng.gaussian(sigma.y());
    initial_pose_.theta = geometry::WrapAngle(initial_pose_.theta + init_rng.gaussian(sigma.z()));
  }
}

void RunSimulator::Summarize() {
  SimSummary& s = summary_;
  s.frames = frame_count();
  s.duration_s = truth_.back().t - truth_.front().t;
  s.distance_m =
      route_.ArcLengthAt(frame_elapsed_s_.back()) - route_.ArcLengthAt(frame_elapsed_s_.front());
  s.speed_m_s =
      s.duration_s > 0 ? s.distance_m / s.duration_s : route_.SpeedAt(frame_elapsed_s_.front());
  s.speed_px_s = s.speed_m_s / layout_.geo.resolution;
  s.route_length_m = route_.length_m();
  s.laps = s.distance_m / s.route_length_m;
  s.route_margin_m = route_.margin_m();

  const geometry::ConvexPolygon footprint = FootprintInGround(camera_);
  std::vector<geometry::ConvexPolygon> footprints;
  for (const geometry::StampedPose& base : truth_) {
    footprints.push_back(PlaceFootprint(footprint, base.pose * camera_.mount));
  }
  s.min_frame_on_floor = 1.0;
  for (const auto& placed : footprints) {
    s.min_frame_on_floor = std::min(s.min_frame_on_floor, SharedFraction(placed, floor_m_));
  }
  int overlapping = 0;
  double shared_sum = 0.0;
  for (size_t i = 1; i < footprints.size(); ++i) {
    const double shared = SharedFraction(footprints[i], footprints[i - 1]);
    overlapping += shared > 0 ? 1 : 0;
    shared_sum += shared;
  }
  const int pairs = frame_count() - 1;
  s.overlapping_pairs_fraction = pairs > 0 ? static_cast<double>(overlapping) / pairs : 0.0;
  s.mean_pair_overlap = pairs > 0 ? shared_sum / pairs : 0.0;
  s.floor_fraction_seen = FloorFractionSeen(layout_, footprints);
}

Eigen::Vector2d RunSimulator::ImageVelocity(double elapsed_s) const {
  // Image position of the floor point under the principal point, differentiated numerically.
  const geometry::Pose2 now = CameraAt(elapsed_s);
  const Eigen::Vector2d point(now.x, now.y);
  auto image_of_point = [&](double t) {
    return camera_.GroundToPixel(CameraAt(t).Inverse() * point);
  };
  return (image_of_point(elapsed_s + kVelocityStepS) - image_of_point(elapsed_s - kVelocityStepS)) /
         (2.0 * kVelocityStepS);
}

RenderedFrame RunSimulator::RenderFrame(int i) {
  FLEETLOC_CHECK(i >= 0 && i < frame_count());
  return renderer_.Render(truth_[i].pose, ImageVelocity(frame_elapsed_s_[i]),
                          static_cast<std::uint64_t>(i));
}

}  // namespace fleetloc::sim
