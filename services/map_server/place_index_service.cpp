// Place index: build or load in a worker, publish from the DDS thread.
#include "map_server/place_index_service.h"

#include <spdlog/spdlog.h>

#include "mosaic/mosaic_view.h"
#include "mosaic/place_index_cache.h"
#include "mosaic/tile_store.h"

namespace fleetloc::map_server {

namespace {
constexpr std::size_t kBuildCacheBytes = std::size_t{64} << 20;  // tiles the build keeps decoded
}  // namespace

std::vector<std::string> PlaceIndexService::CounterNames() {
  return {"place_index_built", "place_index_loaded", "place_index_failed", "place_index_published"};
}

PlaceIndexService::PlaceIndexService(std::string mosaic_path,
                                     transport::PlaceIndexPublisher* publisher,
                                     ServerCounters* counters)
    : mosaic_path_(std::move(mosaic_path)),
      publisher_(publisher),
      counters_(counters),
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
  if (Status sent = publisher_->Publish(ready->mosaic_id, ready->version, ready->blob); !sent.ok()) {
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
  Result<mosaic::LoadedPlaceIndex> index = mosaic::LoadOrBuildPlaceIndex(
      mosaic_path_, view, mapmatch::PlaceIndexOptions{}, mosaic::IndexCache::kUse, &stopping_);
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
    std::lock_guard<std::mutex> lock(mutex_);
    ready_ = std::move(ready);
  }
}

}  // namespace fleetloc::map_server
