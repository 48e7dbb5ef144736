// Relocalization trials (see bench_reloc.h).
#include "bench_reloc.h"

#include <chrono>
#include <random>

#include "io/progress_log.h"
#include "sim/camera_renderer.h"
#include "sim/random_pose.h"

namespace fleetloc::fleetctl {
namespace {

// The bench's camera: 640×480 at the mosaic's resolution, mounted 0.40 m ahead of base_link.
geometry::CameraModel BenchCamera(const mosaic::MosaicLayout& layout) {
  geometry::CameraModel camera;
  camera.resolution_m = layout.geo.resolution;
  camera.mount = {0.40, 0.0, 0.0};
  return camera;
}

// Whether the whole frame stays on the mosaic at any heading.
bool FrameFits(const mosaic::MosaicLayout& layout, const geometry::CameraModel& camera,
               const geometry::Pose2& base) {
  const geometry::Pose2 cam = base * camera.mount;
  const Eigen::Vector2d px = layout.geo.MapToPixel({cam.x, cam.y});
  const double r = 0.5 * std::hypot(camera.width_px, camera.height_px);
  return px.x() >= r && px.y() >= r && px.x() <= layout.width_px - r &&
         px.y() <= layout.height_px - r;
}

// The vehicle's pose at frame `k`: driven straight ahead from `start`, or backwards when ahead
// leaves the mosaic.
geometry::Pose2 PoseAtFrame(const mosaic::MosaicLayout& layout, const geometry::CameraModel& camera,
                            const geometry::Pose2& start, int k, double step_m) {
  const geometry::Pose2 ahead = start * geometry::Pose2{k * step_m, 0.0, 0.0};
  return FrameFits(layout, camera, ahead) ? ahead : start * geometry::Pose2{-k * step_m, 0.0, 0.0};
}

double Ms(const mapmatch::Relocalization& r) {
  return r.detect_ms + r.match_ms + r.cluster_ms + r.verify_ms;
}

// One trial; the relocalizer starts from a cold tile cache (and cold normalized tiles).
Result<RelocTrial> RunTrial(std::shared_ptr<mosaic::TileStore> store,
                            const mapmatch::PlaceIndex& index, sim::CameraRenderer& renderer,
                            const geometry::Pose2& start, int trial, const RelocTrialSettings& s) {
  const mosaic::MosaicLayout layout = store->layout();
  mosaic::MosaicView view(layout, mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(s.tile_cache_bytes));
  auto relocalizer = mapmatch::Relocalizer::Create(&index, &view, renderer.camera(), s.relocalizer);
  if (!relocalizer.ok()) return relocalizer.status();
  RelocTrial out;
  for (int k = 0; k < s.attempts && !out.found; ++k) {
    const geometry::Pose2 truth = PoseAtFrame(layout, renderer.camera(), start, k, s.step_m);
    const cv::Mat frame =
        renderer.Render(truth, {0, 0}, static_cast<std::uint64_t>(trial) * 16 + k).image;
    Result<mapmatch::Relocalization> r = (*relocalizer)->Relocalize(frame);
    if (!r.ok()) return Internal("trial " + std::to_string(trial) + ": " + r.status().message());
    out.runs.push_back(*r);
    out.attempts = k + 1;
    out.time_to_pose_s += Ms(*r) / 1000.0 + (k > 0 ? s.frame_period_s : 0.0);
    if (!r->found) continue;
    out.found = true;
    const geometry::Pose2& pose = r->base_in_map.pose;
    out.error_m = std::hypot(pose.x - truth.x, pose.y - truth.y);
    out.error_rad = std::abs(geometry::WrapAngle(pose.theta - truth.theta));
    out.correct = out.error_m < s.max_error_m && out.error_rad < s.max_error_rad;
  }
  return out;
}

}  // namespace

Result<std::vector<RelocTrial>> RunRelocTrials(std::shared_ptr<mosaic::TileStore> store,
                                               const mapmatch::PlaceIndex& index,
                                               const RelocTrialSettings& settings) {
  const mosaic::MosaicLayout layout = store->layout();
  // The renderer reads the same mosaic through its own view and cache, so it never warms the
  // relocalizer's tiles.
  mosaic::MosaicView floor(layout, mosaic::MakeTileLoader(store),
                           std::make_shared<mosaic::TileCache>(256LL << 20));
  sim::CameraRenderer renderer(&floor, BenchCamera(layout), sim::RenderOptions{}, settings.seed);
  std::mt19937_64 rng(settings.seed);
  io::PercentLog log("relocalization trials", "trials", 5);
  std::vector<RelocTrial> trials;
  for (int t = 0; t < settings.trials; ++t) {
    const geometry::Pose2 start = sim::RandomFullFramePose(layout, renderer.camera(), rng);
    Result<RelocTrial> trial = RunTrial(store, index, renderer, start, t, settings);
    if (!trial.ok()) return trial.status();
    trials.push_back(std::move(trial).value());
    log(t + 1, settings.trials);
  }
  return trials;
}

}  // namespace fleetloc::fleetctl
