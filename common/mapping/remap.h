// The re-mapping computation (pure): register each stored patch against the current mosaic, fit
// its photometry, blend the registered patches into every level-0 tile they touch, and rebuild
// the pyramid tiles above them. Reads the current mosaic through a RasterSource and a tile fetch
// function; returns the new tiles (nothing is written here).
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "base/status.h"
#include "mapping/patch_blender.h"
#include "mapping/patch_registration.h"
#include "mosaic/tile_key.h"

namespace fleetloc::mapping {

struct RemapOptions {
  BlendMode mode = BlendMode::kBlend;
  double feather_px = 24.0;
  // A patch that does not register (its floor changed too much) is still used when its reported
  // position sigma is at most this (the vehicle was well localized); else it is rejected.
  double max_unregistered_sigma_px = 1.0;
  tracking::TrackerOptions tracker;
};

struct RemapStep {
  std::string phase;  // "register", "blend", "pyramid"
  int done = 0;
  int total = 0;
};

struct RemapTiles {
  std::map<mosaic::TileKey, cv::Mat> tiles;  // every changed tile, all levels
  std::vector<bool> used;                    // per input patch: folded into the tiles
  std::vector<Registration> registrations;   // per input patch
  int rejected = 0;
};

// The current tile (CV_8UC1, tile size; zeros where the mosaic has none).
using TileFetch = std::function<cv::Mat(const mosaic::TileKey&)>;

// Cancelled (InvalidInput "cancelled") when *cancel becomes true between steps.
Result<RemapTiles> ComputeRemap(mosaic::RasterSource* mosaic, const TileFetch& fetch,
                                const std::vector<Patch>& patches, const RemapOptions& options,
                                const std::function<void(const RemapStep&)>& progress,
                                const std::atomic<bool>* cancel);

}  // namespace fleetloc::mapping
