// Judge, corroborate, blend, rebuild the pyramid.
#include "mapping/remap.h"

#include <algorithm>
#include <list>
#include <set>

#include "mosaic/pyramid_builder.h"

namespace fleetloc::mapping {
namespace {

using mosaic::TileKey;

bool Cancelled(const std::atomic<bool>* cancel) { return cancel != nullptr && cancel->load(); }

// Level-0 pixel rectangle covered by a patch of `size` at `pose`.
cv::Rect FootprintPx(cv::Size size, const geometry::Pose2& pose,
                     const geometry::Geotransform& geo) {
  double min_u = 1e300, min_v = 1e300, max_u = -1e300, max_v = -1e300;
  const double ha = size.height * geo.resolution / 2, hb = size.width * geo.resolution / 2;
  for (const auto& [a, b] : {std::pair{ha, hb}, {ha, -hb}, {-ha, hb}, {-ha, -hb}}) {
    const Eigen::Vector2d m = pose * Eigen::Vector2d(a, b);
    const double u = (m.x() - geo.origin_x) / geo.resolution,
                 v = (geo.origin_y - m.y()) / geo.resolution;
    min_u = std::min(min_u, u);
    max_u = std::max(max_u, u);
    min_v = std::min(min_v, v);
    max_v = std::max(max_v, v);
  }
  return cv::Rect(
      cv::Point(static_cast<int>(std::floor(min_u)) - 1, static_cast<int>(std::floor(min_v)) - 1),
      cv::Point(static_cast<int>(std::ceil(max_u)) + 1, static_cast<int>(std::ceil(max_v)) + 1));
}

// The last few decoded patches: a patch touching several tiles is read once, not once per tile,
// while memory stays bounded by `capacity` images.
class PatchCache {
 public:
  PatchCache(PatchSource* source, size_t capacity) : source_(source), capacity_(capacity) {}
  // Null when the patch cannot be read.
  const Patch* Get(int index) {
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
      if (it->first != index) continue;
      entries_.splice(entries_.begin(), entries_, it);
      return &entries_.front().second;
    }
    Result<Patch> patch = source_->Load(index);
    if (!patch.ok()) return nullptr;
    entries_.emplace_front(index, std::move(patch).value());
    if (entries_.size() > capacity_) entries_.pop_back();
    return &entries_.front().second;
  }

 private:
  PatchSource* source_;
  size_t capacity_;
  std::list<std::pair<int, Patch>> entries_;  // most recently used first
};

// An admitted patch without its image (re-read through the cache when blended).
struct Accepted {
  int index = 0;
  cv::Rect footprint;
  double rank = 0;
};

class RemapComputation {
 public:
  RemapComputation(mosaic::RasterSource* mosaic, const TileFetch& fetch, PatchSource& patches,
                   const RemapOptions& options,
                   const std::function<void(const RemapStep&)>& progress,
                   const std::atomic<bool>* cancel)
      : mosaic_(mosaic),
        layout_(mosaic->layout()),
        fetch_(fetch),
        patches_(patches),
        options_(options),
        progress_(progress),
        cancel_(cancel),
        cache_(&patches, static_cast<size_t>(std::max(4, options.max_patches_per_tile))) {}

  Result<RemapTiles> Run() {
    FLEETLOC_RETURN_IF_ERROR(Judge());
    FLEETLOC_RETURN_IF_ERROR(Corroborate());
    FLEETLOC_RETURN_IF_ERROR(Blend());
    FLEETLOC_RETURN_IF_ERROR(Pyramid());
    return std::move(out_);
  }

 private:
  void Report(const char* phase, int done, int total) const {
    if (progress_) progress_({phase, done, total});
  }

  Status Judge() {
    PatchAdmission admission(mosaic_, options_.admission, options_.tracker);
    const int n = patches_.size();
    out_.outcomes.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      if (Cancelled(cancel_)) return InvalidInput("cancelled");
      PatchOutcome& outcome = out_.outcomes[static_cast<size_t>(i)];
      Result<Patch> patch = patches_.Load(i);
      if (!patch.ok()) {
        outcome.admission.verdict = Verdict::kMalformed;
        outcome.reason = outcome.admission.reason = patch.status().message();
      } else {
        outcome.admission = admission.Evaluate(*patch);
        outcome.reason = outcome.admission.reason;
        if (outcome.admission.admitted()) {
          outcome.fate = PatchFate::kFolded;
          accepted_.push_back(
              {i, FootprintPx(patch->image.size(), outcome.admission.pose, layout_.geo),
               outcome.admission.rank});
        }
      }
      Report("judge", i + 1, n);
    }
    return Status::Ok();
  }

  // Holds back the admitted patches whose change no other vehicle confirms.
  Status Corroborate() {
    if (options_.corroboration.min_vehicles <= 1 || accepted_.empty()) return Status::Ok();
    if (Cancelled(cancel_)) return InvalidInput("cancelled");
    // Corroboration compares images pairwise: the admitted patches that changed something (the
    // only ones that can need or give a confirmation) are read once here, and held together.
    std::vector<Patch> images;
    std::vector<ObservedChange> changes;
    std::vector<size_t> which;  // index into accepted_
    images.reserve(accepted_.size());
    for (size_t k = 0; k < accepted_.size(); ++k) {
      const PatchOutcome& o = out_.outcomes[static_cast<size_t>(accepted_[k].index)];
      if (o.admission.changed_blocks.empty()) continue;
      Result<Patch> p = patches_.Load(accepted_[k].index);
      if (!p.ok()) continue;
      images.push_back(std::move(p).value());
      which.push_back(k);
      changes.push_back(
          {nullptr, o.admission.pose, images.back().vehicle_id, o.admission.changed_blocks});
    }
    for (size_t c = 0; c < changes.size(); ++c) changes[c].image = &images[c].image;
    const std::vector<bool> ok =
        CorroborateChanges(changes, layout_.geo.resolution, options_.corroboration);
    std::vector<bool> keep(accepted_.size(), true);
    for (size_t c = 0; c < changes.size(); ++c) {
      if (ok[c]) continue;
      keep[which[c]] = false;
      PatchOutcome& o = out_.outcomes[static_cast<size_t>(accepted_[which[c]].index)];
      o.fate = PatchFate::kHeld;
      o.reason = "its change awaits confirmation by " +
                 std::to_string(options_.corroboration.min_vehicles - 1) + " other vehicle(s)";
    }
    std::vector<Accepted> kept;
    for (size_t k = 0; k < accepted_.size(); ++k) {
      if (keep[k]) kept.push_back(accepted_[k]);
    }
    accepted_ = std::move(kept);
    Report("corroborate", 1, 1);
    return Status::Ok();
  }

  Status Blend() {
    std::stable_sort(accepted_.begin(), accepted_.end(),
                     [](const Accepted& a, const Accepted& b) { return a.rank > b.rank; });
    for (const Accepted& a : accepted_) {
      mosaic::TilesCovering(layout_, 0, a.footprint).ForEach([&](const TileKey& k) {
        level0_.insert(k);
      });
    }
    int done = 0;
    for (const TileKey& key : level0_) {
      if (Cancelled(cancel_)) return InvalidInput("cancelled");
      out_.tiles[key] = BlendOne(key);
      Report("blend", ++done, static_cast<int>(level0_.size()));
    }
    return Status::Ok();
  }

  cv::Mat BlendOne(const TileKey& key) {
    const cv::Rect tile_rect = mosaic::TilePixelRect(layout_, key);
    std::vector<PlacedPatch> touching;
    for (const Accepted& a : accepted_) {
      if (static_cast<int>(touching.size()) >= options_.max_patches_per_tile) break;
      if ((a.footprint & tile_rect).area() == 0) continue;
      const Patch* patch = cache_.Get(a.index);
      if (patch == nullptr) continue;
      const Admission& admission = out_.outcomes[static_cast<size_t>(a.index)].admission;
      touching.push_back({patch->image, admission.pose, admission.gain, admission.bias});
    }
    cv::Mat blended = BlendTile(fetch_(key), tile_rect.tl(), layout_.geo, touching, options_.mode,
                                options_.feather_px);
    // Padding past the mosaic's edge stays 0, as the importer leaves it.
    const cv::Rect inside =
        (tile_rect & cv::Rect(0, 0, layout_.width_px, layout_.height_px)) - tile_rect.tl();
    cv::Mat clean = cv::Mat::zeros(blended.size(), CV_8UC1);
    blended(inside).copyTo(clean(inside));
    return clean;
  }

  Status Pyramid() {
    std::set<TileKey> changed = level0_;
    for (int level = 1; level < layout_.levels && !changed.empty(); ++level) {
      if (Cancelled(cancel_)) return InvalidInput("cancelled");
      std::set<TileKey> parents;
      for (const TileKey& k : changed) parents.insert({level, k.col / 2, k.row / 2});
      for (const TileKey& parent : parents) {
        out_.tiles[parent] = mosaic::DownsampleTile(layout_, parent, [&](const TileKey& child) {
          const auto it = out_.tiles.find(child);
          return it != out_.tiles.end() ? it->second : fetch_(child);
        });
      }
      Report("pyramid", level, layout_.levels - 1);
      changed = std::move(parents);
    }
    return Status::Ok();
  }

  mosaic::RasterSource* mosaic_;
  const mosaic::MosaicLayout layout_;
  const TileFetch& fetch_;
  PatchSource& patches_;
  const RemapOptions& options_;
  const std::function<void(const RemapStep&)>& progress_;
  const std::atomic<bool>* cancel_;
  PatchCache cache_;
  std::vector<Accepted> accepted_;
  std::set<TileKey> level0_;
  RemapTiles out_;
};

}  // namespace

const char* FateName(PatchFate fate) {
  switch (fate) {
    case PatchFate::kFolded:
      return "folded";
    case PatchFate::kRefused:
      return "refused";
    case PatchFate::kHeld:
      return "held";
  }
  return "unknown";
}

int RemapTiles::Count(PatchFate fate) const {
  return static_cast<int>(std::count_if(outcomes.begin(), outcomes.end(),
                                        [&](const PatchOutcome& o) { return o.fate == fate; }));
}

Result<RemapTiles> ComputeRemap(mosaic::RasterSource* mosaic, const TileFetch& fetch,
                                PatchSource& patches, const RemapOptions& options,
                                const std::function<void(const RemapStep&)>& progress,
                                const std::atomic<bool>* cancel) {
  if (const std::string problem = OptionsProblem(options.admission); !problem.empty()) {
    return InvalidInput("remap admission options: " + problem);
  }
  if (options.max_patches_per_tile < 1)
    return InvalidInput("remap options: max_patches_per_tile must be >= 1");
  return RemapComputation(mosaic, fetch, patches, options, progress, cancel).Run();
}

}  // namespace fleetloc::mapping
