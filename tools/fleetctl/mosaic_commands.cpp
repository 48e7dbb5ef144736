// fleetctl mosaic import | build | info | export | export-mbtiles (docs/formats.md; `vehicles`
// lives in mosaic_upkeep_commands.cpp): thin wrappers over the mosaic store and mapping libraries.
// Progress and diagnostics go to stderr (spdlog); `info` and `build` print JSON on stdout.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "io/file_util.h"
#include "mosaic/export_georef.h"
#include "mosaic/exporter.h"
#include "mosaic/importer.h"
#include "mosaic/mbtiles_writer.h"
#include "mosaic/mosaic_info.h"
#include "mosaic/mosaic_view.h"
#include "mosaic/tile_store.h"
#include "mosaic_build.h"
#include "runtime/progress_log.h"
#include "served_mosaics.h"
#include "support/parse_numbers.h"

namespace fleetloc::fleetctl {
namespace {

struct ImportArgs {
  std::string image;
  double resolution_m = 0.0;
  std::string origin;  // "X,Y" or empty
  std::string out;
};

struct ExportArgs {
  std::string mosaic;
  std::string out;
  int level = 0;
  std::string region;     // "x0,y0,x1,y1" or empty
  std::string nav2_yaml;  // also write a Nav2 map.yaml there
};

Status RunImport(const ImportArgs& args) {
  mosaic::ImportOptions options;
  options.resolution_m = args.resolution_m;
  if (!args.origin.empty()) {
    Result<std::vector<double>> origin = ParseNumbers(args.origin, 2, "--origin", "X,Y (metres)");
    if (!origin.ok()) return origin.status();
    options.origin_x_m = (*origin)[0];
    options.origin_y_m = (*origin)[1];
  }
  runtime::PercentLog progress("import " + args.image, "rows", 10);
  Result<mosaic::MosaicLayout> layout =
      mosaic::ImportImage(args.image, options, args.out, std::ref(progress));
  if (!layout.ok()) return layout.status();
  spdlog::info("wrote {}: {}x{} px, {} levels, {} m/px, origin ({}, {}), mosaic_id {}", args.out,
               layout->width_px, layout->height_px, layout->levels, layout->geo.resolution,
               layout->geo.origin_x, layout->geo.origin_y, layout->mosaic_id);
  return Status::Ok();
}

struct BuildArgs {
  std::string run;
  std::string out;
};

Status RunBuild(const BuildArgs& args) {
  Result<MosaicBuildSummary> built = BuildMosaicFromRun(args.run, args.out, MosaicBuildOptions{});
  if (!built.ok()) return built.status();
  spdlog::info("wrote {}: {}x{} px, {} levels, {} m/px, origin ({}, {})", args.out,
               built->layout.width_px, built->layout.height_px, built->layout.levels,
               built->layout.geo.resolution, built->layout.geo.origin_x,
               built->layout.geo.origin_y);
  std::cout << BuildSummaryJson(*built).dump(2) << "\n";
  return Status::Ok();
}

Status RunInfo(const std::string& path) {
  Result<std::unique_ptr<mosaic::TileStore>> store =
      mosaic::TileStore::Open(path, mosaic::OpenMode::kReadOnly);
  if (!store.ok()) return store.status();
  Result<nlohmann::json> info = mosaic::DescribeMosaic(**store);
  if (!info.ok()) return info.status();
  std::cout << info->dump(2) << "\n";
  return Status::Ok();
}

Status RunExport(const ExportArgs& args) {
  std::optional<mosaic::MapRegion> region;
  if (!args.region.empty()) {
    Result<std::vector<double>> r =
        ParseNumbers(args.region, 4, "--region", "x0,y0,x1,y1 (metres)");
    if (!r.ok()) return r.status();
    region = mosaic::MapRegion{(*r)[0], (*r)[1], (*r)[2], (*r)[3]};
  }
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(args.mosaic, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  std::shared_ptr<mosaic::TileStore> store = std::move(opened).value();
  // Export walks strips of one tile height that need at most two tile rows at a time.
  const mosaic::MosaicLayout layout = store->layout();
  const int tiles_across =
      mosaic::TileColumns(layout, std::clamp(args.level, 0, layout.levels - 1));
  const std::size_t cache_bytes =
      2 * static_cast<std::size_t>(tiles_across + 1) * layout.tile_size_px * layout.tile_size_px;
  mosaic::MosaicView view(layout, mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(cache_bytes));
  Result<cv::Rect> rect = mosaic::ExportImage(view, args.level, region, args.out);
  if (!rect.ok()) {
    return Status(rect.status().code(), args.mosaic + ": " + rect.status().message());
  }
  if (view.missing_tiles() + view.unreadable_tiles() > 0) {
    spdlog::warn("{}: {} missing and {} unreadable tiles exported as black", args.mosaic,
                 view.missing_tiles(), view.unreadable_tiles());
  }
  spdlog::info("wrote {}: level {}, pixels x {}..{}, y {}..{}", args.out, args.level, rect->x,
               rect->x + rect->width, rect->y, rect->y + rect->height);
  // Georeference beside it: the world file always, the Nav2 map.yaml on request.
  const std::string world = mosaic::WorldFilePath(args.out);
  FLEETLOC_RETURN_IF_ERROR(
      io::WriteFileAtomically(world, mosaic::WorldFileText(layout, args.level, *rect)));
  spdlog::info("wrote {} (world file: map coordinates of the pixels)", world);
  if (!args.nav2_yaml.empty()) {
    // The image as Nav2 finds it: relative to the yaml's directory when beside it.
    namespace fs = std::filesystem;
    const fs::path image = fs::absolute(args.out),
                   yaml_dir = fs::absolute(args.nav2_yaml).parent_path();
    const std::string ref =
        image.parent_path() == yaml_dir ? image.filename().string() : image.string();
    FLEETLOC_RETURN_IF_ERROR(io::WriteFileAtomically(
        args.nav2_yaml, mosaic::Nav2MapYaml(layout, args.level, *rect, ref)));
    spdlog::info("wrote {} (Nav2 map_server)", args.nav2_yaml);
  }
  return Status::Ok();
}

struct MbtilesArgs {
  std::string mosaic;
  std::string out;
  mosaic::MbtilesOptions options;
};

Status RunExportMbtiles(const MbtilesArgs& args) {
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(args.mosaic, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  std::shared_ptr<mosaic::TileStore> store = std::move(opened).value();
  const mosaic::MosaicLayout layout = store->layout();
  // A tile needs about one tile of the source level (a few when it straddles tile borders).
  const std::size_t cache_bytes =
      16 * static_cast<std::size_t>(layout.tile_size_px) * layout.tile_size_px;
  mosaic::MosaicView view(layout, mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(cache_bytes));
  runtime::PercentLog progress("export-mbtiles " + args.out, "tiles", 10);
  Result<mosaic::MbtilesPlan> plan =
      mosaic::ExportMbtiles(view, args.options, args.out, std::ref(progress));
  if (!plan.ok()) return Status(plan.status().code(), args.mosaic + ": " + plan.status().message());
  if (view.missing_tiles() + view.unreadable_tiles() > 0) {
    spdlog::warn("{}: {} missing and {} unreadable tiles exported as black", args.mosaic,
                 view.missing_tiles(), view.unreadable_tiles());
  }
  if (plan->zooms.full_detail_zoom > plan->zooms.max_zoom) {
    spdlog::warn("{}: the mosaic's full detail needs zoom {}; written up to zoom {} ({} m/px)",
                 args.mosaic, plan->zooms.full_detail_zoom, plan->zooms.max_zoom,
                 mosaic::MapMetresPerPixel(plan->zooms.max_zoom, plan->placement));
  }
  spdlog::info("wrote {}: {} tiles, zooms {}..{}, map origin at lat {} lon {}", args.out,
               plan->total_tiles, plan->zooms.min_zoom, plan->zooms.max_zoom,
               args.options.anchor.lat_deg, args.options.anchor.lon_deg);
  return Status::Ok();
}

void RegisterMosaicExportMbtilesCommand(CLI::App& mosaic, Status* result) {
  auto args = std::make_shared<MbtilesArgs>();
  CLI::App* cmd = mosaic.add_subcommand(
      "export-mbtiles", "Write a mosaic as MBTiles (Web Mercator PNG tiles for QGIS or a web map)");
  cmd->add_option("MOSAIC", args->mosaic, "Mosaic file")->required();
  cmd->add_option("--out", args->out, "MBTiles file to write (replaced when complete)")->required();
  cmd->add_option("--anchor-lat", args->options.anchor.lat_deg,
                  "Latitude of the map origin, degrees (default 0; |lat| <= 85)");
  cmd->add_option("--anchor-lon", args->options.anchor.lon_deg,
                  "Longitude of the map origin, degrees (default 0)");
  cmd->add_option("--max-tiles", args->options.max_tiles,
                  "Refuse an export of more tiles (default 100000)");
  cmd->add_option("--max-zoom", args->options.max_zoom,
                  "Finest zoom written (default 22: GDAL and QGIS open no finer; at most 30)");
  cmd->add_option("--name", args->options.name, "Metadata name (default: the mosaic id)");
  cmd->callback([args, result] { *result = RunExportMbtiles(*args); });
}

void RegisterMosaicImportCommand(CLI::App& mosaic, Status* result) {
  auto args = std::make_shared<ImportArgs>();
  CLI::App* cmd = mosaic.add_subcommand(
      "import", "Cut an image into a tiled, versioned SQLite mosaic with its pyramid");
  cmd->add_option("IMAGE", args->image, "Image file (PNG, PGM/PPM, JPEG, ...)")->required();
  cmd->add_option("--resolution", args->resolution_m, "Metres per pixel")->required();
  cmd->add_option("--origin", args->origin,
                  "Map X,Y of the image's top-left corner (default 0,height*resolution)");
  cmd->add_option("--out", args->out, "Mosaic file to create (must not exist)")->required();
  cmd->callback([args, result] { *result = RunImport(*args); });
}

void RegisterMosaicBuildCommand(CLI::App& mosaic, Status* result) {
  auto args = std::make_shared<BuildArgs>();
  CLI::App* cmd = mosaic.add_subcommand(
      "build", "Build a mosaic from a mapping run (overlapping frames + odometry)");
  cmd->add_option("--run", args->run, "Mapping run directory (docs/formats.md)")->required();
  cmd->add_option("--out", args->out, "Mosaic file to create (must not exist)")->required();
  cmd->callback([args, result] { *result = RunBuild(*args); });
}

struct InfoArgs {
  std::string path;
  int domain = -1;
  double wait_s = 2.0;
  std::string dds_config;
};

void RegisterMosaicInfoCommand(CLI::App& mosaic, Status* result) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = mosaic.add_subcommand(
      "info", "Print a mosaic's metadata as JSON (of a file, or as the map servers announce it)");
  CLI::Option* file = cmd->add_option("MOSAIC", args->path, "Mosaic file");
  CLI::Option* domain =
      cmd->add_option("--domain", args->domain, "Ask the running map servers on this DDS domain")
          ->check(CLI::Range(0, 232));
  file->excludes(domain);
  cmd->add_option("--wait", args->wait_s, "Seconds to listen for servers (with --domain)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--dds-config", args->dds_config, "Cyclone DDS XML (default: built-in loopback)");
  cmd->callback([args, result] {
    if (args->domain >= 0) {
      *result = PrintServedMosaics(args->domain, args->wait_s, args->dds_config);
    } else if (args->path.empty()) {
      *result = InvalidInput("mosaic info: give a MOSAIC file or --domain");
    } else {
      *result = RunInfo(args->path);
    }
  });
}

void RegisterMosaicExportCommand(CLI::App& mosaic, Status* result) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = mosaic.add_subcommand("export", "Render (part of) a mosaic level to an image");
  cmd->add_option("MOSAIC", args->mosaic, "Mosaic file")->required();
  cmd->add_option("--out", args->out, "Image file to write (.png streams; others whole)")
      ->required();
  cmd->add_option("--level", args->level, "Pyramid level (0 = full resolution)");
  cmd->add_option("--region", args->region, "Map region x0,y0,x1,y1 in metres (default: all)");
  cmd->add_option("--nav2-yaml", args->nav2_yaml,
                  "Also write a Nav2/ROS map_server map.yaml for the image (a world file is always "
                  "written beside it)");
  cmd->callback([args, result] { *result = RunExport(*args); });
}

}  // namespace

void RegisterMosaicCommands(CLI::App& app, Status* result) {
  CLI::App* mosaic = app.add_subcommand("mosaic", "Create, inspect and export mosaics");
  mosaic->require_subcommand(1);
  RegisterMosaicImportCommand(*mosaic, result);
  RegisterMosaicBuildCommand(*mosaic, result);
  RegisterMosaicInfoCommand(*mosaic, result);
  RegisterMosaicExportCommand(*mosaic, result);
  RegisterMosaicExportMbtilesCommand(*mosaic, result);
  RegisterMosaicUpkeepCommands(*mosaic, result);
}

}  // namespace fleetloc::fleetctl
