// `fleetctl bench dense-probe`: how the dense place search sees a run's frames (issue 17). For
// every k-th frame of a run with truth over a mosaic, the refine-level correlation at the true
// camera pose (DensePlaceSearch::Refine started at the truth), the search's best and second
// peaks and the best's distance from the truth — the measurement that showed why dust hid the
// plainest floors at the default levels and not one level finer (docs/benchmarks.md, issue 17).
#include "harness/reloc/run_dense_probe.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <opencv2/core/utility.hpp>

#include "mosaic/mosaic_view.h"
#include "mosaic/tile_store.h"
#include "relocalization/dense_place_search.h"
#include "run_io/run.h"

namespace fleetloc::bench {
namespace {

// One frame's line; true when the best peak is within 1 cm of the truth.
Result<bool> ProbeFrame(const relocalization::DensePlaceSearch& search, const run_io::Run& run,
                        std::size_t k) {
  Result<cv::Mat> frame = run_io::ReadFrame(run.frames[k], run.camera.model);
  if (!frame.ok()) return frame.status();
  const geometry::Pose2 truth = run.truth[k].pose * run.camera.model.mount;
  const relocalization::DensePeak at_truth = search.Refine(*frame, {truth, 0.0});
  const std::vector<relocalization::DensePeak> peaks = search.Search(*frame);
  const double best = peaks.empty() ? 0.0 : peaks[0].correlation;
  const double second = peaks.size() < 2 ? 0.0 : peaks[1].correlation;
  const double error_m = peaks.empty() ? -1.0
                                       : std::hypot(peaks[0].camera_in_map.x - truth.x,
                                                    peaks[0].camera_in_map.y - truth.y);
  const bool right = !peaks.empty() && error_m < 0.01;
  std::printf("frame %3zu truth %.3f best %.3f second %.3f ratio %.2f error %.3f m%s\n", k,
              at_truth.correlation, best, second, best > 0 ? second / best : 0.0, error_m,
              right ? " OK" : "");
  return right;
}

}  // namespace

Status RunDenseProbe(const DenseProbeArgs& args) {
  cv::setNumThreads(1);
  Result<run_io::Run> run = run_io::ReadRun(args.run);
  if (!run.ok()) return run.status();
  if (run->truth.size() != run->frames.size())
    return InvalidInput(args.run + ": needs one truth row per frame");
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(args.mosaic, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  std::shared_ptr<mosaic::TileStore> store = std::move(*opened);
  mosaic::MosaicView view(store->layout(), mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(256LL << 20));
  auto search = relocalization::DensePlaceSearch::Create(view, run->camera.model, args.dense);
  if (!search.ok()) return search.status();
  int right = 0, frames = 0;
  for (std::size_t k = 0; k < run->frames.size(); k += args.every, ++frames) {
    Result<bool> r = ProbeFrame(**search, *run, k);
    if (!r.ok()) return r.status();
    right += *r;
  }
  std::printf("best at the truth: %d of %d frames\n", right, frames);
  return Status::Ok();
}

}  // namespace fleetloc::bench
