// `fleetctl bench mosaic-distortion`: the file side of the distortion measurement — the true floor
// image and the built mosaic's level 0 over the same map extent, measured by the mapping library.
#include "bench_mosaic_distortion.h"

#include <iostream>
#include <memory>
#include <string>

#include "io/run.h"
#include "mosaic/mosaic_view.h"
#include "mosaic/tile_store.h"

namespace fleetloc::fleetctl {

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
  Result<cv::Mat> truth = io::ReadGrayImage(truth_image);
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

namespace {

struct DistortionArgs {
  std::string mosaic;
  std::string truth;
  double resolution_m = 0.0005;
};

Status RunBenchDistortion(const DistortionArgs& args) {
  Result<mapping::DistortionReport> report =
      MeasureBuiltMosaicDistortion(args.mosaic, args.truth, args.resolution_m);
  if (!report.ok()) return report.status();
  std::cout << DistortionJson(*report).dump(2) << "\n";
  return Status::Ok();
}

}  // namespace

void RegisterBenchMosaicDistortion(CLI::App& bench, Status* result) {
  auto args = std::make_shared<DistortionArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "mosaic-distortion", "Local distortion of a mosaic against the true floor image (JSON)");
  cmd->add_option("--mosaic", args->mosaic, "Built mosaic")->required();
  cmd->add_option("--truth", args->truth,
                  "True floor image, top-left corner at map (0, height * resolution)")
      ->required();
  cmd->add_option("--resolution", args->resolution_m, "Metres per pixel of the image")
      ->capture_default_str();
  cmd->callback([args, result] { *result = RunBenchDistortion(*args); });
}

}  // namespace fleetloc::fleetctl
