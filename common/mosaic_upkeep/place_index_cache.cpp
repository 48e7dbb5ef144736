// Loading, building and caching a mosaic's place index (see place_index_cache.h).
#include "mosaic_upkeep/place_index_cache.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <optional>

#include "mosaic/place_index_store.h"
#include "runtime/progress_log.h"

namespace fleetloc::mosaic_upkeep {

// The mosaic file the cache lives in.
using mosaic::RasterSource;
using mosaic::ReadPlaceIndexBlob;
using mosaic::WritePlaceIndexBlob;

namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The cached index, or nullopt when there is none or it cannot be used.
std::optional<LoadedPlaceIndex> LoadCached(const std::string& path, long long version,
                                           const std::string& key) {
  const auto start = std::chrono::steady_clock::now();
  auto blob = ReadPlaceIndexBlob(path, version, key);
  if (!blob.ok()) {
    spdlog::warn("{}: cannot read the cached place index: {}", path, blob.status().message());
    return std::nullopt;
  }
  if (!blob->has_value()) return std::nullopt;
  Result<relocalization::PlaceIndex> index = relocalization::PlaceIndex::Deserialize(**blob);
  if (!index.ok()) {
    spdlog::warn("{}: cached place index unusable, rebuilding: {}", path, index.status().message());
    return std::nullopt;
  }
  return LoadedPlaceIndex{std::move(index).value(), std::move(**blob), true, SecondsSince(start)};
}

}  // namespace

std::string PlaceIndexKey(const relocalization::PlaceIndexOptions& o) {
  const relocalization::FloorFeatureOptions& f = o.features;
  return "orb level=" + std::to_string(f.level) + " cell=" + std::to_string(f.cell_px) +
         " per_cell=" + std::to_string(f.features_per_cell) +
         " fast=" + std::to_string(f.fast_threshold) + " patch=" + std::to_string(f.patch_size_px) +
         " blur=" + std::to_string(f.blur_sigma_px) + " lsh=" + std::to_string(o.lsh_tables) + "x" +
         std::to_string(o.lsh_key_bits) + "x" + std::to_string(o.lsh_multiprobe_level);
}

Result<LoadedPlaceIndex> LoadOrBuildPlaceIndex(const std::string& mosaic_path, RasterSource& view,
                                               const relocalization::PlaceIndexOptions& options,
                                               IndexCache cache, const std::atomic<bool>* cancel) {
  const long long version = view.layout().version;
  const std::string key = PlaceIndexKey(options);
  if (cache == IndexCache::kUse) {
    if (std::optional<LoadedPlaceIndex> cached = LoadCached(mosaic_path, version, key)) {
      return std::move(*cached);
    }
  }
  const auto start = std::chrono::steady_clock::now();
  runtime::PercentLog log("place index of " + mosaic_path, "strips");
  Result<relocalization::PlaceIndex> built = relocalization::PlaceIndex::Build(
      view, options, [&](int done, int total) { log(done, total); }, cancel);
  if (!built.ok()) return built.status();
  LoadedPlaceIndex loaded{std::move(built).value(), {}, false, SecondsSince(start)};
  loaded.blob = loaded.index.Serialize();
  const std::vector<std::uint8_t>& blob = loaded.blob;
  spdlog::info("place index: {} features, {} bytes, built in {:.2f} s", loaded.index.size(),
               blob.size(), loaded.seconds);
  if (cache != IndexCache::kIgnore) {
    if (Status stored = WritePlaceIndexBlob(mosaic_path, version, key, blob); !stored.ok())
      spdlog::warn("place index not cached: {}", stored.message());
  }
  return loaded;
}

}  // namespace fleetloc::mosaic_upkeep
