// A re-mapping job against the stored mosaic (the map server's, and any tool's): select the
// unfolded patches of a region, judge each on the server's own evidence and fold the admitted
// ones into new tiles (mapping::ComputeRemap), record the refusals and each vehicle's standing
// (quarantining a vehicle whose patches keep failing), then mark the folded patches and commit
// the tiles as the next mosaic version. A job that fails, is cancelled or dies at any point leaves
// the previous version intact, and can simply be run again.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "base/status.h"
#include "mapping/remap.h"
#include "mapping/vehicle_reputation.h"
#include "mosaic/patch_store.h"
#include "mosaic/tile_store.h"
#include "mosaic_upkeep/vehicle_standing_store.h"

namespace fleetloc::mosaic_upkeep {

enum class RemapMode { kBlend, kReplace };

// How patches are judged (the map server's configuration, "patch_admission").
struct RemapPolicy {
  mapping::AdmissionOptions admission;
  mapping::CorroborationOptions corroboration;
  mapping::ReputationOptions reputation;
  int max_patches_per_tile = 16;
};

struct RemapRequest {
  mosaic::MapRect region;
  RemapMode mode = RemapMode::kBlend;
  RemapPolicy policy;
  // A preview: every patch judged and every tile computed as a real job would, but nothing
  // written — no version, no folded marks, no refusals or vehicle standing recorded, no
  // quarantine. The result lists the tiles that would change (new_version stays the current).
  bool dry_run = false;
};

struct RemapProgress {
  // select, judge, corroborate, blend, pyramid, commit (done 1 .. total - 1: tiles written into the
  // still uncommitted version; total: committed)
  std::string phase;
  int done = 0;
  int total = 0;
};

// What one job did with one vehicle's patches.
struct VehicleRemapReport {
  int folded = 0;
  int refused = 0;
  int held = 0;                           // awaiting another vehicle's confirmation
  std::map<std::string, int> refused_by;  // verdict name (or "quarantined") → count
  bool quarantined = false;               // quarantined now (before or by this job)
};

struct RemapResult {
  long long new_version = 0;                   // the previous version when nothing changed
  std::vector<mosaic::TileKey> changed_tiles;  // every level
  int patches_folded = 0;
  int patches_rejected = 0;  // refused (failed admission, unreadable, quarantined sender)
  int patches_held = 0;
  int patches_unreadable = 0;  // stored image did not decode
  std::map<std::string, VehicleRemapReport> vehicles;
  std::vector<std::string> newly_quarantined;
};

// One line for operators (RemapStatus message, logs): per vehicle what was folded, refused (by
// reason) and held, and who is quarantined; at most `max_chars`, ending "..." when cut.
std::string RemapSummary(const RemapResult& result, size_t max_chars = 255);

// The three stores of one mosaic file a job works with, each on its own connection.
struct RemapStores {
  std::unique_ptr<mosaic::TileStore> tiles;
  std::unique_ptr<mosaic::PatchStore> patches;
  std::unique_ptr<VehicleStandingStore> standing;
};
Result<RemapStores> OpenRemapStores(const std::string& path, mosaic::OpenMode tile_mode);

// InvalidInput for an empty, inverted or non-finite region or one outside the mosaic, bad policy
// options, and when cancelled; Internal on storage errors. `store` must be writable.
Result<RemapResult> RunRemap(mosaic::TileStore& store, mosaic::PatchStore& patches,
                             VehicleStandingStore& standing, const RemapRequest& request,
                             const std::function<void(const RemapProgress&)>& progress = {},
                             const std::atomic<bool>* cancel = nullptr);

}  // namespace fleetloc::mosaic_upkeep
