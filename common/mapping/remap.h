// The re-mapping computation (pure): judge each stored patch against the current mosaic on the
// server's own evidence (patch_admission.h), optionally require its change to be seen by several
// vehicles (change_corroboration.h), blend the admitted patches into every level-0 tile they touch
// (best ranked first, at most a bounded number per tile), and rebuild the pyramid tiles above
// them. Patches are read one at a time from a PatchSource, so memory stays bounded by the patches
// of one tile rather than the region's. Returns the new tiles (nothing is written here).
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "base/status.h"
#include "mapping/change_corroboration.h"
#include "mapping/patch_admission.h"
#include "mapping/patch_blender.h"
#include "mosaic/tile_key.h"

namespace fleetloc::mapping {

struct RemapOptions {
  BlendMode mode = BlendMode::kBlend;
  double feather_px = 24.0;
  AdmissionOptions admission;
  CorroborationOptions corroboration;
  // At most this many admitted patches (the best ranked) are blended into one tile.
  int max_patches_per_tile = 16;
  tracking::TrackerOptions tracker;
};

// The patches of a job, read on demand (decoding is the caller's: from memory, from SQLite).
class PatchSource {
 public:
  virtual ~PatchSource() = default;
  virtual int size() const = 0;
  // The patch `index` in [0, size()); an error when it cannot be read (it is then refused).
  virtual Result<Patch> Load(int index) = 0;
};

// Patches held in memory (tests, tools).
class VectorPatchSource : public PatchSource {
 public:
  explicit VectorPatchSource(std::vector<Patch> patches) : patches_(std::move(patches)) {}
  int size() const override { return static_cast<int>(patches_.size()); }
  Result<Patch> Load(int index) override { return patches_.at(static_cast<size_t>(index)); }

 private:
  std::vector<Patch> patches_;
};

enum class PatchFate {
  kFolded,   // admitted (and corroborated): blended into the new tiles
  kRefused,  // failed admission (or unreadable): never folded, counts against its vehicle
  kHeld,     // admitted, but its change awaits another vehicle's confirmation: stays unfolded
};
const char* FateName(PatchFate fate);

struct PatchOutcome {
  PatchFate fate = PatchFate::kRefused;
  Admission admission;
  std::string reason;  // why refused or held ("" when folded)
};

struct RemapStep {
  std::string phase;  // "judge", "corroborate", "blend", "pyramid"
  int done = 0;
  int total = 0;
};

struct RemapTiles {
  std::map<mosaic::TileKey, cv::Mat> tiles;  // every changed tile, all levels
  std::vector<PatchOutcome> outcomes;        // per input patch
  int Count(PatchFate fate) const;
};

// The current tile (CV_8UC1, tile size; zeros where the mosaic has none).
using TileFetch = std::function<cv::Mat(const mosaic::TileKey&)>;

// Cancelled (InvalidInput "cancelled") when *cancel becomes true between steps.
Result<RemapTiles> ComputeRemap(mosaic::RasterSource* mosaic, const TileFetch& fetch,
                                PatchSource& patches, const RemapOptions& options,
                                const std::function<void(const RemapStep&)>& progress,
                                const std::atomic<bool>* cancel);

}  // namespace fleetloc::mapping
