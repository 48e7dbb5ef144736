// `fleetctl bench mosaic-distortion`: the file side of the distortion measurement — the true floor
// image and the built mosaic's level 0 over the same map extent, measured by the mapping library.
#include "harness/mosaic/bench_mosaic_distortion.h"

#include <iostream>
#include <memory>
#include <string>

#include "mosaic/mosaic_view.h"
#include "mosaic/tile_store.h"
#include "run_io/run.h"

namespace fleetloc::bench {

namespace fs = std::filesystem;

nlohmann::json DistortionJson(const mapping::DistortionReport& d) {
  return {{"patches", d.patches.size()},
          {"patches_tried", d.patches_tried},
          {"rms_px", d.rms_px},
          {"max_px", d.max_px},
          {"scale_error_ppm", d.scale_error * 1e6},
          {"rotation_mrad", d.rotation_rad * 1e3},
          {"translation_px", {d.translation_px.x(), d.translation_px.y()}},
          {"residual_rms_px", d.residual_rms_px},
          {"residual_max_px", d.residual_max_px}};
}

Result<mapping::DistortionReport> MeasureBuiltMosaicDistortion(const fs::path& built_db,
                                                               const fs::path& truth_image,
                                                               double resolution_m) {
  Result<cv::Mat> truth = run_io::ReadGrayImage(truth_image);
  if (!truth.ok()) return truth.status();
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(built_db.string(), mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  std::shared_ptr<mosaic::TileStore> store = std::move(*opened);
  const mosaic::MosaicLayout layout = store->layout();
  // The truth's top-left corner (map (0, rows · res)) in the built mosaic's level-0 pixels.
  const Eigen::Vector2d corner = layout.geo.MapToPixel({0.0, truth->rows * resolution_m});
  const Eigen::Vector2d rounded = corner.array().round();
  if ((corner - rounded).norm() > 1e-3 || std::abs(layout.geo.resolution - resolution_m) > 1e-12) {
    return InvalidInput(built_db.string() + ": its pixel grid does not coincide with " +
                        truth_image.string() + "'s at " + std::to_string(resolution_m) + " m/px");
  }
  mosaic::MosaicView view(layout, mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(64 << 20));
  const cv::Mat built =
      view.ReadBlock(0, cv::Rect(static_cast<int>(rounded.x()), static_cast<int>(rounded.y()),
                                 truth->cols, truth->rows));
  Result<mapping::DistortionReport> report = mapping::MeasureDistortion(built, *truth);
  if (!report.ok()) {
    return Status(report.status().code(), built_db.string() + ": " + report.status().message());
  }
  return report;
}

namespace {}  // namespace

Status RunMosaicDistortionBench(const MosaicDistortionBenchArgs& args) {
  Result<mapping::DistortionReport> report =
      MeasureBuiltMosaicDistortion(args.mosaic, args.truth, args.resolution_m);
  if (!report.ok()) return report.status();
  std::cout << DistortionJson(*report).dump(2) << "\n";
  return Status::Ok();
}

}  // namespace fleetloc::bench
