// Google Benchmark of one tracker cycle on a 640×480 frame over a real floor (rock and dirt,
// 2048² px at 0.5 mm/px), frames rendered in memory by the simulator with all photometric
// effects, the mosaic in memory (a warm tile cache). Also the hot stages on their own.
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "imaging/correlation.h"
#include "imaging/dft_size.h"
#include "imaging/fast_patch.h"
#include "imaging/normalize.h"
#include "imaging/resample.h"
#include "imaging/spectral_ncc.h"
#include "imaging/texture.h"
#include "sim/run_simulator.h"
#include "tracking/mosaic_tracker.h"
#include "tracking/odometry_history.h"
#include "tracking/point_views.h"

namespace fleetloc {
namespace {

struct Fixture {
  std::unique_ptr<mosaic::ImageRasterSource> floor;
  geometry::CameraModel camera;
  std::unique_ptr<sim::RunSimulator> simulator;
  std::vector<cv::Mat> frames;

  Fixture() {
    cv::setNumThreads(1);  // one core, as the target states
    const cv::Mat gray = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                    cv::IMREAD_GRAYSCALE);
    floor = std::make_unique<mosaic::ImageRasterSource>(
        gray, geometry::Geotransform{0.0, gray.rows * 0.0005, 0.0005});
    camera.mount = {0.4, 0.0, 0.0};
    sim::SimOptions options;
    options.timing.frames = 100;
    simulator = std::move(sim::RunSimulator::Create(floor.get(), camera, options)).value();
    for (int i = 0; i < simulator->frame_count(); ++i) {
      frames.push_back(simulator->RenderFrame(i).image);
    }
  }
};

Fixture& Shared() {
  static Fixture fixture;
  return fixture;
}

void BM_TrackFrame640x480(benchmark::State& state) {
  Fixture& f = Shared();
  tracking::MosaicTracker tracker({}, f.camera, f.floor.get());
  const auto& truth = f.simulator->truth();
  const auto& odometry = f.simulator->odometry();
  size_t i = 0;
  tracking::OdometryHistory history(1e12, 0.0);
  for (const auto& sample : odometry) (void)history.Add(sample);
  auto odom_at = [&](double t) { return history.At(t).value(); };
  auto reset = [&] {
    tracker.Reset({truth[0].pose, Eigen::Vector3d(4e-6, 4e-6, 1e-4).asDiagonal()},
                  odom_at(truth[0].t));
    i = 0;
  };
  reset();
  int tracked = 0;
  double select_ms = 0, coarse_ms = 0, fine_ms = 0;
  for (auto _ : state) {
    if (i == f.frames.size()) {
      state.PauseTiming();
      reset();
      state.ResumeTiming();
    }
    const auto r = tracker.Track(f.frames[i], truth[i].t, odom_at(truth[i].t));
    tracked += r.state == tracking::LockState::kTracking;
    select_ms += r.select_ms;
    coarse_ms += r.coarse_ms;
    fine_ms += r.fine_ms;
    ++i;
  }
  state.counters["lock_rate"] = benchmark::Counter(tracked, benchmark::Counter::kAvgIterations);
  state.counters["select_ms"] = benchmark::Counter(select_ms, benchmark::Counter::kAvgIterations);
  state.counters["coarse_ms"] = benchmark::Counter(coarse_ms, benchmark::Counter::kAvgIterations);
  state.counters["fine_ms"] = benchmark::Counter(fine_ms, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_TrackFrame640x480)->Unit(benchmark::kMillisecond)->Iterations(300);

void BM_TextureScoreHalfResolution(benchmark::State& state) {
  cv::Mat half;
  cv::resize(Shared().frames[0], half, {320, 240}, 0, 0, cv::INTER_AREA);
  for (auto _ : state) benchmark::DoNotOptimize(imaging::TextureScore(half, 5));
}
BENCHMARK(BM_TextureScoreHalfResolution)->Unit(benchmark::kMicrosecond);

void BM_NormalizeAndMatch32(benchmark::State& state) {
  const int radius = static_cast<int>(state.range(0));
  const cv::Mat& frame = Shared().frames[0];
  const cv::Mat templ =
      imaging::LocalNormalize(frame(cv::Rect(300, 200, 44, 44)), 11)(cv::Rect(6, 6, 32, 32))
          .clone();
  const cv::Rect window(300 - radius, 200 - radius, 44 + 2 * radius, 44 + 2 * radius);
  for (auto _ : state) {
    const cv::Mat w = imaging::LocalNormalize(frame(window), 11);
    benchmark::DoNotOptimize(imaging::MatchTemplate(w, templ));
  }
}
BENCHMARK(BM_NormalizeAndMatch32)->Arg(2)->Arg(8)->Arg(24)->Unit(benchmark::kMicrosecond);

// A fixed scalar loop (bilinear sampling of a 48×48 patch, no library calls) whose time per
// pixel gauges how fast this host runs right now: on a shared VM the same binary's timings move
// with the host's load, so every timing is reported next to this.
void BM_ReferenceScalarLoop(benchmark::State& state) {
  std::vector<unsigned char> src(200 * 200);
  for (size_t i = 0; i < src.size(); ++i) src[i] = static_cast<unsigned char>(i * 37);
  std::vector<float> out(48 * 48);
  for (auto _ : state) {
    for (int i = 0; i < 48; ++i) {
      const float sx0 = 10 + 0.3f * i, sy0 = 20 + 0.96f * i;
      for (int j = 0; j < 48; ++j) {
        const float sx = sx0 + 0.96f * j, sy = sy0 - 0.28f * j;
        const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);
        const float ax = sx - x0, ay = sy - y0;
        const unsigned char* r0 = &src[y0 * 200 + x0];
        const unsigned char* r1 = r0 + 200;
        const float top = r0[0] + ax * (r0[1] - r0[0]), bottom = r1[0] + ax * (r1[1] - r1[0]);
        out[i * 48 + j] = top + ay * (bottom - top);
      }
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_px"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 2304,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ReferenceScalarLoop);

void BM_ResampleAffine(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const cv::Mat src = Shared().frames[0](cv::Rect(100, 100, size + 40, size + 40)).clone();
  const cv::Matx23d m(0.96, -0.28, 20.3, 0.28, 0.96, 5.7);
  for (auto _ : state) benchmark::DoNotOptimize(imaging::ResampleAffine(src, m, {size, size}));
}
BENCHMARK(BM_ResampleAffine)->Arg(52)->Arg(64)->Unit(benchmark::kMicrosecond);

// A 640×480 camera's polish view at level 1: ~660×500 pixels turned 11° from a mosaic block,
// from the block's 8-bit pixels (arg 0) or from the block converted to float first (arg 1, the
// path before session 45; the conversion is timed too).
void BM_ResamplePolishView(benchmark::State& state) {
  cv::Mat block;
  cv::resize(Shared().frames[0], block, {800, 680});
  const cv::Matx23d m(0.98, -0.199, 103.0, 0.199, 0.98, 10.0);
  for (auto _ : state) {
    if (state.range(0) == 0) {
      benchmark::DoNotOptimize(imaging::ResampleAffine(block, m, {660, 500}));
    } else {
      cv::Mat floats;
      block.convertTo(floats, CV_32F);
      benchmark::DoNotOptimize(imaging::ResampleAffine(floats, m, {660, 500}));
    }
  }
}
BENCHMARK(BM_ResamplePolishView)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// One Gauss–Newton iteration's view of a 640×480 camera's level 1 (320×240): the strongest pixel
// of every 3×3 cell, 8,533 of them, sampled from a texel block of the rock floor turned 11°, with
// the AVX2 loop (arg 0) or the scalar one (arg 1).
void BM_SamplePointViews(benchmark::State& state) {
  cv::Mat floats;
  Shared().frames[0](cv::Rect(0, 0, 400, 340)).convertTo(floats, CV_32F, 1.0 / 255);
  cv::Mat gx, gy;
  cv::Sobel(floats, gx, CV_32F, 1, 0, 1, 0.5);
  cv::Sobel(floats, gy, CV_32F, 0, 1, 1, 0.5);
  cv::Mat texels;
  cv::merge(std::vector<cv::Mat>{floats, gx, gy, cv::Mat::zeros(floats.size(), CV_32F)}, texels);
  tracking::PointSet points;
  for (int y = 1; y < 240; y += 3) {
    for (int x = 1; x < 320; x += 3) {
      points.u.push_back(x + 0.5f);
      points.v.push_back(y + 0.5f);
      points.value.push_back(0.0f);
    }
  }
  const float c = 0.982f, s = 0.191f;  // 11°
  const tracking::PointWarp warp{{{c, -s}, {s, c}}, {100.0f, 40.0f}, {{c, s}, {-s, c}}, 0.5f};
  const tracking::TexelBlock block{&texels, {20, 10}, {2048, 2048}};
  const auto path =
      state.range(0) == 0 ? tracking::SamplingPath::kFastest : tracking::SamplingPath::kScalar;
  tracking::PointViews views;
  for (auto _ : state) {
    tracking::SamplePointViews(warp, block, points, &views, path);
    benchmark::DoNotOptimize(views.value.data());
  }
  state.counters["points"] = static_cast<double>(points.size());
}
BENCHMARK(BM_SamplePointViews)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_NormalizePatch(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const cv::Mat patch = Shared().frames[0](cv::Rect(100, 100, size, size));
  for (auto _ : state) benchmark::DoNotOptimize(imaging::NormalizePatch(patch, 11));
}
BENCHMARK(BM_NormalizePatch)->Arg(56)->Arg(28)->Unit(benchmark::kMicrosecond);

void BM_NccSurface(benchmark::State& state) {
  const int t = static_cast<int>(state.range(0)), r = static_cast<int>(state.range(1));
  cv::Mat f;
  Shared().frames[0].convertTo(f, CV_32F);
  const cv::Mat window = f(cv::Rect(100, 100, t + 2 * r, t + 2 * r)).clone();
  const cv::Mat templ = f(cv::Rect(100 + r, 100 + r, t, t)).clone();
  for (auto _ : state) benchmark::DoNotOptimize(imaging::NccSurface(window, templ));
}
BENCHMARK(BM_NccSurface)
    ->Args({48, 2})
    ->Args({16, 8})
    ->Args({16, 13})
    ->Unit(benchmark::kMicrosecond);

// The dense alignment's coarse search: a whole 640×480 frame at pyramid level 2 (inner 152×112)
// correlated over ±r, ours against OpenCV's matchTemplate (the peer it replaced), same inputs.
struct SearchInputs {
  cv::Mat window, templ;
};
SearchInputs CoarseSearchInputs(int r) {
  cv::Mat f;
  Shared().frames[0].convertTo(f, CV_32F);
  const cv::Size inner(152, 112);
  return {f(cv::Rect(60, 60, inner.width + 2 * r, inner.height + 2 * r)).clone(),
          f(cv::Rect(60 + r, 60 + r, inner.width, inner.height)).clone()};
}
void BM_CoarseSearchNccSurface(benchmark::State& state) {
  const SearchInputs in = CoarseSearchInputs(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(imaging::NccSurface(in.window, in.templ));
}
BENCHMARK(BM_CoarseSearchNccSurface)->Arg(6)->Arg(10)->Arg(16)->Unit(benchmark::kMicrosecond);
void BM_CoarseSearchOpenCvMatchTemplate(benchmark::State& state) {
  const SearchInputs in = CoarseSearchInputs(static_cast<int>(state.range(0)));
  cv::Mat surface;
  for (auto _ : state) {
    cv::matchTemplate(in.window, in.templ, surface, cv::TM_CCOEFF_NORMED);
    benchmark::DoNotOptimize(surface.data);
  }
}
BENCHMARK(BM_CoarseSearchOpenCvMatchTemplate)
    ->Arg(6)
    ->Arg(10)
    ->Arg(16)
    ->Unit(benchmark::kMicrosecond);
// Ours with the template's spectrum taken once: a first search (spectrum included) and each
// further view of the same frame (the heading steps).
void BM_CoarseSearchSpectralNccFirst(benchmark::State& state) {
  const SearchInputs in = CoarseSearchInputs(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const imaging::SpectralNcc ncc(in.templ, in.window.size());
    benchmark::DoNotOptimize(ncc.Surface(in.window).data);
  }
}
BENCHMARK(BM_CoarseSearchSpectralNccFirst)->Arg(6)->Arg(10)->Arg(16)->Unit(benchmark::kMicrosecond);
void BM_CoarseSearchSpectralNccRepeat(benchmark::State& state) {
  const SearchInputs in = CoarseSearchInputs(static_cast<int>(state.range(0)));
  const imaging::SpectralNcc ncc(in.templ, in.window.size());
  for (auto _ : state) benchmark::DoNotOptimize(ncc.Surface(in.window).data);
}
BENCHMARK(BM_CoarseSearchSpectralNccRepeat)
    ->Arg(6)
    ->Arg(10)
    ->Arg(16)
    ->Unit(benchmark::kMicrosecond);

// OpenCV's real forward transform of a W × 400 image at getOptimalDFTSize(W), which may be odd,
// and at imaging::EvenDftSize(W), what the FFT correlators pad to (W: the fine dense search's
// refine level of the stress bench's pavement at 1280×1024, 622 → 625 or 640; 366 → 375 or 384).
void RealDft(benchmark::State& state, int width) {
  cv::Mat image(400, width, CV_32F), spectrum;
  cv::randu(image, -1.0, 1.0);
  for (auto _ : state) {
    cv::dft(image, spectrum);
    benchmark::DoNotOptimize(spectrum.data);
  }
}
void BM_RealDftOptimalLength(benchmark::State& state) {
  RealDft(state, cv::getOptimalDFTSize(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_RealDftOptimalLength)->Arg(366)->Arg(622)->Unit(benchmark::kMillisecond);
void BM_RealDftEvenLength(benchmark::State& state) {
  RealDft(state, imaging::EvenDftSize(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_RealDftEvenLength)->Arg(366)->Arg(622)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace fleetloc

BENCHMARK_MAIN();
