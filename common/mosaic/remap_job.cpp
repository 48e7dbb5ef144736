// Re-mapping job: stored patches → new tiles → next mosaic version.
#include "mosaic/remap_job.h"

#include <cmath>

#include "mapping/remap.h"
#include "mosaic/mosaic_view.h"

namespace fleetloc::mosaic {
namespace {

Status CheckRegion(const MapRect& r, const MosaicLayout& layout) {
  for (double v : {r.x_min, r.y_min, r.x_max, r.y_max}) {
    if (!std::isfinite(v)) return InvalidInput("remap region has a non-finite coordinate");
  }
  if (!(r.x_min < r.x_max && r.y_min < r.y_max)) return InvalidInput("remap region is empty or inverted");
  const double x0 = layout.geo.origin_x, y1 = layout.geo.origin_y;
  const double x1 = x0 + layout.width_px * layout.geo.resolution;
  const double y0 = y1 - layout.height_px * layout.geo.resolution;
  if (r.x_max <= x0 || r.x_min >= x1 || r.y_max <= y0 || r.y_min >= y1) {
    return InvalidInput("remap region lies outside the mosaic");
  }
  return Status::Ok();
}

Result<long long> Commit(TileStore& store, const std::map<TileKey, cv::Mat>& tiles) {
  FLEETLOC_RETURN_IF_ERROR(store.BeginVersion());
  for (const auto& [key, tile] : tiles) {
    if (Status put = store.PutTile(key, tile); !put.ok()) {
      (void)store.AbortVersion();
      return put;
    }
  }
  return store.CommitVersion();
}

}  // namespace

Result<RemapResult> RunRemap(TileStore& store, PatchStore& patches, const RemapRequest& request,
                             const std::function<void(const RemapProgress&)>& progress,
                             const std::atomic<bool>* cancel) {
  if (Result<long long> refreshed = store.Refresh(); !refreshed.ok()) return refreshed.status();
  const MosaicLayout layout = store.layout();
  FLEETLOC_RETURN_IF_ERROR(CheckRegion(request.region, layout));
  const auto report = [&](const std::string& phase, int done, int total) {
    if (progress) progress({phase, done, total});
  };
  FLEETLOC_RETURN_IF_ERROR(patches.ClearUncommittedMarks(layout.version));
  report("select", 0, 1);
  Result<PatchQuery> query = patches.Unfolded(request.region, layout.version);
  if (!query.ok()) return query.status();
  RemapResult result{layout.version, {}, 0, 0, query->unreadable};
  std::vector<mapping::Patch> inputs;
  for (const PatchRecord& p : query->patches) inputs.push_back({p.image, p.pose, p.covariance});
  MosaicView view(layout, [&store](const TileKey& k) { return store.ReadTile(k); },
                  std::make_shared<TileCache>(size_t{256} << 20));
  const auto fetch = [&](const TileKey& key) {
    Result<cv::Mat> tile = store.ReadTile(key);
    return tile.ok() ? *tile : cv::Mat(cv::Mat::zeros(layout.tile_size_px, layout.tile_size_px, CV_8UC1));
  };
  mapping::RemapOptions options;
  options.mode = request.mode == RemapMode::kReplace ? mapping::BlendMode::kReplace
                                                     : mapping::BlendMode::kBlend;
  Result<mapping::RemapTiles> computed = mapping::ComputeRemap(
      &view, fetch, inputs, options,
      [&](const mapping::RemapStep& step) { report(step.phase, step.done, step.total); }, cancel);
  if (!computed.ok()) return computed.status();
  result.patches_rejected = computed->rejected;
  std::vector<PatchRecord> folded;
  for (size_t i = 0; i < query->patches.size(); ++i) {
    if (computed->used[i]) folded.push_back(query->patches[i]);
  }
  result.patches_folded = static_cast<int>(folded.size());
  if (computed->tiles.empty()) return result;  // nothing to change
  if (cancel != nullptr && cancel->load()) return InvalidInput("cancelled");
  report("commit", 0, 1);
  // Marks first, tiles second: the marks only count once the version is committed.
  FLEETLOC_RETURN_IF_ERROR(patches.MarkFolded(folded, layout.version + 1));
  Result<long long> version = Commit(store, computed->tiles);
  if (!version.ok()) {
    (void)patches.ClearUncommittedMarks(layout.version);
    return version.status();
  }
  result.new_version = *version;
  for (const auto& [key, tile] : computed->tiles) result.changed_tiles.push_back(key);
  report("commit", 1, 1);
  return result;
}

}  // namespace fleetloc::mosaic
