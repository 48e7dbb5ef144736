// fleetctl reloc: global relocalization of one frame of a run against a mosaic, with no prior
// pose (issue 5). The mosaic's place index is loaded from its cache table or built and cached; a
// floor without detectable features has none, and is relocalized by the dense place search alone
// (issue 17; a log line says so); --self-similarity also reports where the floor repeats itself.
// Prints JSON on stdout (the pose, or found: false and why; with truth.csv, the error); exit 1
// when the frame could not be relocalized.
#include <spdlog/spdlog.h>

#include <chrono>
#include <iostream>
#include <opencv2/core/utility.hpp>

#include "commands.h"
#include "mosaic/tile_store.h"
#include "mosaic_upkeep/place_index_cache.h"
#include "relocalization/self_similarity.h"
#include "run_io/run.h"
#include "support/reloc_index.h"

namespace fleetloc::fleetctl {
namespace {

struct RelocArgs {
  std::string mosaic;
  std::string run;
  int frame = 0;
  bool no_cache = false;
  bool self_similarity = false;
  long long cache_mb = 256;
};

Result<cv::Mat> ReadRunFrame(const run_io::Run& run, int k) {
  if (k >= static_cast<int>(run.frames.size())) {
    return InvalidInput("--frame " + std::to_string(k) + ": the run has " +
                        std::to_string(run.frames.size()) + " frames");
  }
  return run_io::ReadFrame(run.frames[k], run.camera.model);
}

// Places where the floor repeats itself (relocalization/self_similarity.h) as JSON, with a warning;
// the relocalizer then refuses poses there (Relocalizer::SetTwinPlaces).
Result<nlohmann::json> SelfSimilarityJson(relocalization::Relocalizer& relocalizer,
                                          mosaic::RasterSource& mosaic,
                                          const geometry::CameraModel& camera) {
  if (relocalizer.dense_search() == nullptr)
    return InvalidInput("--self-similarity: the mosaic is too large for the dense place search");
  const auto start = std::chrono::steady_clock::now();
  Result<relocalization::SelfSimilarityReport> report = relocalization::FindSelfSimilarity(
      *relocalizer.dense_search(), mosaic, camera, relocalization::SelfSimilarityOptions{});
  if (!report.ok()) return report.status();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  relocalizer.SetTwinPlaces(report->ambiguous);
  nlohmann::json places = nlohmann::json::array();
  for (const relocalization::SimilarPlace& p : report->ambiguous) {
    places.push_back({{"place", {p.place.x, p.place.y}},
                      {"twin", {p.twin.x, p.twin.y, p.twin.theta}},
                      {"correlation", p.own},
                      {"twin_correlation", p.twin_correlation}});
  }
  if (!places.empty()) {
    spdlog::warn(
        "the floor repeats itself: {} of {} sampled places have a twin (relocalization "
        "there is refused as ambiguous)",
        places.size(), report->sampled);
  }
  return nlohmann::json{{"sampled", report->sampled}, {"ambiguous", places}, {"seconds", seconds}};
}

// Position and heading error against truth.csv's row of frame k.
nlohmann::json TruthError(const run_io::Run& run, int k, const geometry::Pose2& pose) {
  const geometry::Pose2& truth = run.truth[k].pose;
  return {{"position_m", std::hypot(pose.x - truth.x, pose.y - truth.y)},
          {"heading_rad", std::abs(geometry::WrapAngle(pose.theta - truth.theta))}};
}

Status RunReloc(const RelocArgs& args) {
  cv::setNumThreads(1);
  Result<run_io::Run> run = run_io::ReadRun(args.run);
  if (!run.ok()) return run.status();
  Result<cv::Mat> frame = ReadRunFrame(*run, args.frame);
  if (!frame.ok()) return frame.status();
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(args.mosaic, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  std::shared_ptr<mosaic::TileStore> store = std::move(*opened);
  mosaic::MosaicView view(store->layout(), mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(args.cache_mb << 20));
  Result<mosaic_upkeep::LoadedPlaceIndex> index = mosaic_upkeep::LoadOrBuildPlaceIndex(
      args.mosaic, view, relocalization::PlaceIndexOptions{},
      args.no_cache ? mosaic_upkeep::IndexCache::kIgnore : mosaic_upkeep::IndexCache::kUse);
  // A mosaic the place index refuses (no distinctive features): the dense place search alone.
  if (!index.ok() && index.status().code() != StatusCode::kInvalidInput) return index.status();
  if (!index.ok())
    spdlog::warn("{}; relocalizing by the dense place search alone", index.status().message());
  auto relocalizer =
      relocalization::Relocalizer::Create(index.ok() ? &index->index : nullptr, &view,
                                          run->camera.model, relocalization::RelocalizerOptions{});
  if (!relocalizer.ok()) {
    if (index.ok()) return relocalizer.status();
    return InvalidInput(index.status().message() + "; and " + relocalizer.status().message());
  }
  nlohmann::json similar_json;
  if (args.self_similarity) {
    Result<nlohmann::json> similar = SelfSimilarityJson(**relocalizer, view, run->camera.model);
    if (!similar.ok()) return similar.status();
    similar_json = *similar;
  }
  Result<relocalization::Relocalization> result = (*relocalizer)->Relocalize(*frame);
  if (!result.ok()) return result.status();
  nlohmann::json json = RelocalizationJson(*result);
  if (args.self_similarity) json["self_similarity"] = similar_json;
  json["frame"] = args.frame;
  json["index"] = index.ok() ? nlohmann::json{{"features", index->index.size()},
                                              {"from_cache", index->from_cache},
                                              {"seconds", index->seconds}}
                             : nlohmann::json{{"features", 0}, {"error", index.status().message()}};
  if (result->found && args.frame < static_cast<int>(run->truth.size()))
    json["error"] = TruthError(*run, args.frame, result->base_in_map.pose);
  std::cout << json.dump(2) << "\n";
  if (!result->found)
    return Internal("frame " + std::to_string(args.frame) + ": " + result->reason);
  return Status::Ok();
}

}  // namespace

void RegisterRelocCommand(CLI::App& app, Status* result) {
  auto args = std::make_shared<RelocArgs>();
  CLI::App* cmd = app.add_subcommand(
      "reloc", "Find a run frame's pose on a mosaic with no prior (global relocalization)");
  cmd->add_option("--mosaic", args->mosaic, "Mosaic file (SQLite)")->required();
  cmd->add_option("--run", args->run, "Run directory (docs/formats.md)")->required();
  cmd->add_option("--frame", args->frame, "Index of the frame in frames.csv")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("--no-cache", args->no_cache,
                "Build the place index without reading or writing the mosaic's cache table");
  cmd->add_flag("--self-similarity", args->self_similarity,
                "Also report places where the floor repeats itself (frame-sized crops on a 3×3 "
                "grid searched densely; a few seconds)");
  cmd->add_option("--cache-mb", args->cache_mb, "Tile cache bound in MiB")
      ->check(CLI::Range(1, 1 << 20));
  cmd->callback([args, result] { *result = RunReloc(*args); });
}

}  // namespace fleetloc::fleetctl
