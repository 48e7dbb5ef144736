// Timing of the camera renderer on a 640×480 frame over a real 2048² floor photo: all effects,
// clean (sampling only), and the area sampler alone.
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>

#include "sim/area_sampler.h"
#include "sim/camera_renderer.h"

namespace fleetloc::sim {
namespace {

constexpr double kResolutionM = 0.0005;

mosaic::ImageRasterSource& Floor() {
  static mosaic::ImageRasterSource floor(
      cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                 cv::IMREAD_GRAYSCALE),
      geometry::Geotransform{0.0, 2048 * kResolutionM, kResolutionM});
  return floor;
}

void RenderFrames(benchmark::State& state, const RenderOptions& options) {
  geometry::CameraModel camera;  // 640×480 at 0.5 mm/px
  CameraRenderer renderer(&Floor(), camera, options, 1);
  std::uint64_t frame = 0;
  for (auto _ : state) {
    // A new pose every frame (heading and sub-pixel position change).
    const geometry::Pose2 base{0.3 + 1e-4 * (frame % 1000), 0.5, 0.01 * (frame % 628)};
    benchmark::DoNotOptimize(renderer.Render(base, {300.0, 0.0}, frame++).image.data);
  }
}

void BM_RenderAllEffects(benchmark::State& state) { RenderFrames(state, RenderOptions{}); }
void BM_RenderClean(benchmark::State& state) {
  RenderFrames(state, CleanRenderOptions(RenderOptions{}));
}

void BM_AreaSampleSupersample3(benchmark::State& state) {
  Eigen::Matrix<double, 2, 3> map;
  map << std::cos(0.3), -std::sin(0.3), 900.0, std::sin(0.3), std::cos(0.3), 700.0;
  const cv::Size size(640, 480);
  const AreaSampler sampler(map, 3);
  const cv::Rect rect = sampler.SourceRect(size);
  const cv::Mat block = Floor().ReadBlock(0, rect);
  for (auto _ : state) benchmark::DoNotOptimize(sampler.Sample(block, rect, size).data);
}

BENCHMARK(BM_RenderAllEffects)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RenderClean)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AreaSampleSupersample3)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace fleetloc::sim

BENCHMARK_MAIN();
