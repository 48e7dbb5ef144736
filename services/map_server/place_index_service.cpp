// Place index: build or load in a worker, publish from the DDS thread.
#include "map_server/place_index_service.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "mosaic/mosaic_view.h"
#include "mosaic/tile_store.h"
#include "mosaic_upkeep/place_index_cache.h"
#include "relocalization/self_similarity.h"

namespace fleetloc::map_server {

namespace {
constexpr std::size_t kBuildCacheBytes = std::size_t{64} << 20;  // tiles the build keeps decoded
}  // namespace

std::vector<std::string> PlaceIndexService::CounterNames() {
  return {"place_index_built",     "place_index_loaded",      "place_index_failed",
          "place_index_published", "self_similarity_checked", "self_similarity_skipped",
          "self_similar_places"};
}

PlaceIndexService::PlaceIndexService(std::string mosaic_path,
                                     transport::PlaceIndexPublisher* publisher,
                                     ServerCounters* counters, int self_similarity_grid)
    : mosaic_path_(std::move(mosaic_path)),
      publisher_(publisher),
      counters_(counters),
      self_similarity_grid_(self_similarity_grid),
      worker_([this] { Work(); }) {}

PlaceIndexService::~PlaceIndexService() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void PlaceIndexService::RequestCurrent() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    requested_ = true;
  }
  wake_.notify_all();
}

void PlaceIndexService::PublishReady() {
  std::optional<Ready> ready;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ready.swap(ready_);
  }
  if (!ready || ready->version <= published_version_) return;
  if (Status sent = publisher_->Publish(ready->mosaic_id, ready->version, ready->blob);
      !sent.ok()) {
    counters_->Add("place_index_failed");
    spdlog::error("place index of version {} not published: {}", ready->version, sent.message());
    return;
  }
  published_version_ = ready->version;
  counters_->Add("place_index_published");
  spdlog::info("place index of mosaic {} version {} published ({} bytes)", ready->mosaic_id,
               ready->version, ready->blob.size());
}

std::optional<PlaceIndexService::Ready> PlaceIndexService::LoadOrBuild() {
  // Its own read-write connection (the cache table is written), apart from the DDS loop's.
  auto opened = mosaic::TileStore::Open(mosaic_path_, mosaic::OpenMode::kReadWrite);
  if (!opened.ok()) {
    counters_->Add("place_index_failed");
    spdlog::error("place index: {}", opened.status().message());
    return std::nullopt;
  }
  std::shared_ptr<mosaic::TileStore> store = std::move(opened).value();
  mosaic::MosaicView view(store->layout(), mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(kBuildCacheBytes));
  Result<mosaic_upkeep::LoadedPlaceIndex> index =
      mosaic_upkeep::LoadOrBuildPlaceIndex(mosaic_path_, view, relocalization::PlaceIndexOptions{},
                                           mosaic_upkeep::IndexCache::kUse, &stopping_);
  if (!index.ok()) {
    counters_->Add("place_index_failed");
    if (!stopping_) spdlog::error("place index not available: {}", index.status().message());
    return std::nullopt;
  }
  counters_->Add(index->from_cache ? "place_index_loaded" : "place_index_built");
  spdlog::info("place index of version {}: {} features, {} in {:.2f} s", store->layout().version,
               index->index.size(), index->from_cache ? "loaded" : "built", index->seconds);
  return Ready{store->layout().mosaic_id, store->layout().version, std::move(index->blob)};
}

namespace {

// The camera the check imagines: the default 640×480 frame at the mosaic's resolution.
geometry::CameraModel CheckCamera(double resolution_m) {
  geometry::CameraModel camera;
  camera.width_px = 640;
  camera.height_px = 480;
  camera.cx_px = 320;
  camera.cy_px = 240;
  camera.resolution_m = resolution_m;
  return camera;
}

std::string Describe(const relocalization::SelfSimilarityReport& report) {
  std::string text = std::to_string(report.ambiguous.size()) + " of " +
                     std::to_string(report.sampled) + " places have a twin";
  char pair[128];
  constexpr std::size_t kNamed = 3;  // places named (the health message is bounded)
  for (std::size_t i = 0; i < std::min(kNamed, report.ambiguous.size()); ++i) {
    const relocalization::SimilarPlace& p = report.ambiguous[i];
    std::snprintf(pair, sizeof(pair), "%s(%.3f, %.3f) ~ (%.3f, %.3f)", i == 0 ? ": " : "; ",
                  p.place.x, p.place.y, p.twin.x, p.twin.y);
    text += pair;
  }
  if (report.ambiguous.size() > kNamed) text += "; ...";
  return text + " (camera poses in map, m)";
}

}  // namespace

std::optional<std::string> PlaceIndexService::self_similarity_warning() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return self_similarity_warning_;
}

void PlaceIndexService::CheckSelfSimilarity() {
  const auto start = std::chrono::steady_clock::now();
  auto opened = mosaic::TileStore::Open(mosaic_path_, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) {
    spdlog::error("self-similarity: {}", opened.status().message());
    return;
  }
  std::shared_ptr<mosaic::TileStore> store = std::move(opened).value();
  mosaic::MosaicView view(store->layout(), mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(kBuildCacheBytes));
  const geometry::CameraModel camera = CheckCamera(store->layout().geo.resolution);
  auto search = relocalization::DensePlaceSearch::Create(view, camera, {});
  if (!search.ok()) {
    counters_->Add("self_similarity_skipped");
    spdlog::info("self-similarity of version {} not checked: {}", store->layout().version,
                 search.status().message());
    return;
  }
  relocalization::SelfSimilarityOptions options;
  options.grid = self_similarity_grid_;
  Result<relocalization::SelfSimilarityReport> report =
      relocalization::FindSelfSimilarity(**search, view, camera, options, [&](int done, int total) {
        spdlog::info("self-similarity: {} of {} places searched", done, total);
        return !stopping_.load();
      });
  if (!report.ok()) {
    if (!stopping_) spdlog::warn("self-similarity not checked: {}", report.status().message());
    return;
  }
  counters_->Add("self_similarity_checked");
  counters_->Add("self_similar_places", report->ambiguous.size());
  const std::string text = Describe(*report);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (report->ambiguous.empty()) {
    spdlog::info("self-similarity of version {}: {} ({:.2f} s)", store->layout().version, text,
                 seconds);
  } else {
    spdlog::warn(
        "self-similarity of version {}: {} ({:.2f} s): a frame there cannot be "
        "relocalized alone",
        store->layout().version, text, seconds);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  self_similarity_warning_ =
      report->ambiguous.empty() ? std::nullopt : std::optional<std::string>(text);
}

void PlaceIndexService::Work() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || requested_; });
      if (stopping_) return;
      requested_ = false;
    }
    std::optional<Ready> ready = LoadOrBuild();
    if (!ready) continue;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_ = std::move(ready);
    }
    // After the index is handed over: the vehicles need not wait for the check.
    if (self_similarity_grid_ > 0) CheckSelfSimilarity();
  }
}

}  // namespace fleetloc::map_server
