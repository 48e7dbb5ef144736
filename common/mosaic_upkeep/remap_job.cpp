// Re-mapping job: stored patches → verdicts and new tiles → next mosaic version.
#include "mosaic_upkeep/remap_job.h"

#include <cmath>
#include <set>
#include <sstream>

#include "mosaic/mosaic_view.h"

namespace fleetloc::mosaic_upkeep {

// The stored mosaic this job works on.
using mosaic::MapRect;
using mosaic::MosaicLayout;
using mosaic::MosaicView;
using mosaic::OpenMode;
using mosaic::PatchRecord;
using mosaic::PatchStore;
using mosaic::Refusal;
using mosaic::TileCache;
using mosaic::TileKey;
using mosaic::TileStore;

namespace {

constexpr const char* kQuarantined = "quarantined";

Status CheckRegion(const MapRect& r, const MosaicLayout& layout) {
  for (double v : {r.x_min, r.y_min, r.x_max, r.y_max}) {
    if (!std::isfinite(v)) return InvalidInput("remap region has a non-finite coordinate");
  }
  if (!(r.x_min < r.x_max && r.y_min < r.y_max))
    return InvalidInput("remap region is empty or inverted");
  const double x0 = layout.geo.origin_x, y1 = layout.geo.origin_y;
  const double x1 = x0 + layout.width_px * layout.geo.resolution;
  const double y0 = y1 - layout.height_px * layout.geo.resolution;
  if (r.x_max <= x0 || r.x_min >= x1 || r.y_max <= y0 || r.y_min >= y1) {
    return InvalidInput("remap region lies outside the mosaic");
  }
  return Status::Ok();
}

Status CheckPolicy(const RemapPolicy& p) {
  if (std::string problem = mapping::OptionsProblem(p.admission); !problem.empty()) {
    return InvalidInput("remap policy: admission: " + problem);
  }
  if (std::string problem = mapping::OptionsProblem(p.reputation); !problem.empty()) {
    return InvalidInput("remap policy: reputation: " + problem);
  }
  if (p.corroboration.min_vehicles < 1)
    return InvalidInput("remap policy: min_vehicles must be >= 1");
  if (p.max_patches_per_tile < 1)
    return InvalidInput("remap policy: max_patches_per_tile must be >= 1");
  return Status::Ok();
}

// Writes the tiles as the next version in one transaction; `report(done, total)` after each tile
// (the version still uncommitted) and once committed.
Result<long long> Commit(TileStore& store, const std::map<TileKey, cv::Mat>& tiles,
                         const std::function<void(int, int)>& report) {
  FLEETLOC_RETURN_IF_ERROR(store.BeginVersion());
  const int total = static_cast<int>(tiles.size()) + 1;
  int done = 0;
  for (const auto& [key, tile] : tiles) {
    if (Status put = store.PutTile(key, tile); !put.ok()) {
      (void)store.AbortVersion();
      return put;
    }
    report(++done, total);
  }
  Result<long long> version = store.CommitVersion();
  if (version.ok()) report(total, total);
  return version;
}

// The verdicts of one job: what to write back (refusals, standings, folded patches) and the report.
class Verdicts {
 public:
  Verdicts(std::map<std::string, mapping::VehicleStanding> standings,
           const mapping::ReputationOptions& reputation, RemapResult* result)
      : standings_(std::move(standings)), reputation_(reputation), result_(result) {}

  bool Quarantined(const std::string& vehicle) const {
    const auto it = standings_.find(vehicle);
    return it != standings_.end() && it->second.quarantined;
  }
  // A patch of a vehicle already quarantined: refused unjudged (its standing does not change).
  void RefuseUnjudged(const PatchRecord& p) {
    Report(p.vehicle_id).refused_by[kQuarantined]++;
    Report(p.vehicle_id).refused++;
    refusals_.push_back({p.vehicle_id, p.sequence, "vehicle quarantined"});
  }
  void Record(const PatchRecord& p, const mapping::PatchOutcome& o) {
    VehicleRemapReport& report = Report(p.vehicle_id);
    switch (o.fate) {
      case mapping::PatchFate::kHeld:
        ++report.held;
        return;  // not judged yet: no effect on the standing
      case mapping::PatchFate::kFolded:
        ++report.folded;
        folded_.push_back(p);
        break;
      case mapping::PatchFate::kRefused:
        ++report.refused;
        report.refused_by[mapping::VerdictName(o.admission.verdict)]++;
        refusals_.push_back(
            {p.vehicle_id, p.sequence,
             std::string(mapping::VerdictName(o.admission.verdict)) + ": " + o.reason});
        break;
    }
    mapping::VehicleStanding& standing = standings_[p.vehicle_id];
    if (mapping::RecordVerdict(&standing, o.fate == mapping::PatchFate::kFolded,
                               mapping::VerdictName(o.admission.verdict), reputation_)) {
      result_->newly_quarantined.push_back(p.vehicle_id);
    }
    changed_.insert(p.vehicle_id);
  }
  // Writes the refusals and the changed standings (before any tile is committed: a verdict is
  // about the committed version and holds whatever happens to this job).
  // Each vehicle's standing after the job, in its report.
  void Conclude() {
    for (auto& [vehicle, report] : result_->vehicles) report.quarantined = Quarantined(vehicle);
  }
  Status Persist(PatchStore& patches, VehicleStandingStore& store) {
    FLEETLOC_RETURN_IF_ERROR(patches.MarkRefused(refusals_));
    std::map<std::string, mapping::VehicleStanding> changed;
    for (const std::string& vehicle : changed_) changed[vehicle] = standings_[vehicle];
    return store.PutAll(changed);
  }
  const std::vector<PatchRecord>& folded() const { return folded_; }

 private:
  VehicleRemapReport& Report(const std::string& vehicle) { return result_->vehicles[vehicle]; }

  std::map<std::string, mapping::VehicleStanding> standings_;
  const mapping::ReputationOptions& reputation_;
  RemapResult* result_;
  std::vector<Refusal> refusals_;
  std::vector<PatchRecord> folded_;
  std::set<std::string> changed_;
};

// The job's patches read from the store one image at a time (memory bounded by the few images in
// use, not by the number of patches); images that do not decode are remembered.
class StorePatchSource : public mapping::PatchSource {
 public:
  StorePatchSource(PatchStore* store, std::vector<const PatchRecord*> headers)
      : store_(store), headers_(std::move(headers)) {}
  int size() const override { return static_cast<int>(headers_.size()); }
  Result<mapping::Patch> Load(int index) override {
    const PatchRecord& h = *headers_.at(static_cast<size_t>(index));
    Result<cv::Mat> image = store_->LoadImage(h.vehicle_id, h.sequence);
    if (!image.ok()) {
      unreadable_.insert(index);
      return image.status();
    }
    return mapping::Patch{std::move(image).value(), h.pose, h.covariance, h.quality, h.vehicle_id};
  }
  bool Unreadable(int index) const { return unreadable_.count(index) > 0; }

 private:
  PatchStore* store_;
  std::vector<const PatchRecord*> headers_;
  std::set<int> unreadable_;
};

mapping::RemapOptions ComputeOptions(const RemapRequest& request) {
  mapping::RemapOptions options;
  options.mode = request.mode == RemapMode::kReplace ? mapping::BlendMode::kReplace
                                                     : mapping::BlendMode::kBlend;
  options.admission = request.policy.admission;
  options.corroboration = request.policy.corroboration;
  options.max_patches_per_tile = request.policy.max_patches_per_tile;
  return options;
}

// The patches to judge; those of quarantined vehicles are refused unjudged.
std::vector<const PatchRecord*> ToJudge(const std::vector<PatchRecord>& query, Verdicts& verdicts) {
  std::vector<const PatchRecord*> judged;
  for (const PatchRecord& p : query) {
    if (verdicts.Quarantined(p.vehicle_id)) {
      verdicts.RefuseUnjudged(p);
    } else {
      judged.push_back(&p);
    }
  }
  return judged;
}

// The computed tiles committed as version + 1 (`result` completed), unless none changed or the job
// was cancelled.
Result<RemapResult> CommitRemap(TileStore& store, PatchStore& patches,
                                const std::vector<PatchRecord>& folded,
                                const mapping::RemapTiles& computed, long long version,
                                RemapResult result,
                                const std::function<void(const std::string&, int, int)>& report,
                                const std::atomic<bool>* cancel) {
  if (computed.tiles.empty()) return result;  // nothing to change
  if (cancel != nullptr && cancel->load()) return InvalidInput("cancelled");
  report("commit", 0, 1);
  // Marks first, tiles second: the marks only count once the version is committed.
  FLEETLOC_RETURN_IF_ERROR(patches.MarkFolded(folded, version + 1));
  Result<long long> committed =
      Commit(store, computed.tiles, [&](int done, int total) { report("commit", done, total); });
  if (!committed.ok()) {
    (void)patches.ClearUncommittedMarks(version);
    return committed.status();
  }
  result.new_version = *committed;
  for (const auto& [key, tile] : computed.tiles) result.changed_tiles.push_back(key);
  return result;
}

}  // namespace

std::string RemapSummary(const RemapResult& r, size_t max_chars) {
  std::ostringstream out;
  out << r.patches_folded << " folded, " << r.patches_rejected << " refused, " << r.patches_held
      << " held";
  for (const auto& [vehicle, v] : r.vehicles) {
    out << "; " << vehicle << ": " << v.folded << " folded";
    if (v.refused > 0) {
      out << ", " << v.refused << " refused (";
      const char* separator = "";
      for (const auto& [reason, n] : v.refused_by)
        out << separator << reason << " " << n, separator = ", ";
      out << ")";
    }
    if (v.held > 0) out << ", " << v.held << " held";
    if (v.quarantined) out << ", QUARANTINED";
  }
  std::string text = out.str();
  if (text.size() > max_chars) text = text.substr(0, max_chars > 3 ? max_chars - 3 : 0) + "...";
  return text;
}

Result<RemapStores> OpenRemapStores(const std::string& path, OpenMode tile_mode) {
  RemapStores stores;
  auto tiles = TileStore::Open(path, tile_mode);
  if (!tiles.ok()) return tiles.status();
  auto patches = PatchStore::Open(path);
  if (!patches.ok()) return patches.status();
  auto standing = VehicleStandingStore::Open(path);
  if (!standing.ok()) return standing.status();
  return RemapStores{std::move(tiles).value(), std::move(patches).value(),
                     std::move(standing).value()};
}

Result<RemapResult> RunRemap(TileStore& store, PatchStore& patches, VehicleStandingStore& standing,
                             const RemapRequest& request,
                             const std::function<void(const RemapProgress&)>& progress,
                             const std::atomic<bool>* cancel) {
  if (Result<long long> refreshed = store.Refresh(); !refreshed.ok()) return refreshed.status();
  const MosaicLayout layout = store.layout();
  FLEETLOC_RETURN_IF_ERROR(CheckRegion(request.region, layout));
  FLEETLOC_RETURN_IF_ERROR(CheckPolicy(request.policy));
  const auto report = [&](const std::string& phase, int done, int total) {
    if (progress) progress({phase, done, total});
  };
  if (!request.dry_run) FLEETLOC_RETURN_IF_ERROR(patches.ClearUncommittedMarks(layout.version));
  report("select", 0, 1);
  Result<std::vector<PatchRecord>> query = patches.UnfoldedHeaders(request.region, layout.version);
  if (!query.ok()) return query.status();
  Result<std::map<std::string, mapping::VehicleStanding>> standings = standing.All();
  if (!standings.ok()) return standings.status();
  RemapResult result{layout.version, {}, 0, 0, 0, 0, {}, {}};
  Verdicts verdicts(std::move(standings).value(), request.policy.reputation, &result);
  const std::vector<const PatchRecord*> judged = ToJudge(*query, verdicts);
  MosaicView view(
      layout, [&store](const TileKey& k) { return store.ReadTile(k); },
      std::make_shared<TileCache>(size_t{64} << 20));
  const auto fetch = [&](const TileKey& key) {
    Result<cv::Mat> tile = store.ReadTile(key);
    return tile.ok() ? *tile
                     : cv::Mat(cv::Mat::zeros(layout.tile_size_px, layout.tile_size_px, CV_8UC1));
  };
  StorePatchSource source(&patches, judged);
  Result<mapping::RemapTiles> computed = mapping::ComputeRemap(
      &view, fetch, source, ComputeOptions(request),
      [&](const mapping::RemapStep& step) { report(step.phase, step.done, step.total); }, cancel);
  if (!computed.ok()) return computed.status();
  for (size_t i = 0; i < judged.size(); ++i) {
    // A stored image that does not decode is the file's fault, not the vehicle's: left as it is.
    if (source.Unreadable(static_cast<int>(i))) {
      ++result.patches_unreadable;
      continue;
    }
    verdicts.Record(*judged[i], computed->outcomes[i]);
  }
  verdicts.Conclude();
  if (!request.dry_run) FLEETLOC_RETURN_IF_ERROR(verdicts.Persist(patches, standing));
  result.patches_folded = static_cast<int>(verdicts.folded().size());
  result.patches_held = computed->Count(mapping::PatchFate::kHeld);
  result.patches_rejected = static_cast<int>(query->size()) - result.patches_folded -
                            result.patches_held - result.patches_unreadable;
  if (request.dry_run) {
    for (const auto& [key, tile] : computed->tiles) result.changed_tiles.push_back(key);
    return result;
  }
  return CommitRemap(store, patches, verdicts.folded(), *computed, layout.version,
                     std::move(result), report, cancel);
}

}  // namespace fleetloc::mosaic_upkeep
