// PatchStore: the floor patches vehicles reported (rectified images with pose, covariance and
// quality), kept in the mosaic file's `patches` table until a re-mapping job folds them into a
// new mosaic version. Idempotent on (vehicle_id, sequence): a retried patch is stored once.
//
// Folding is atomic with the mosaic version without sharing a transaction with the tile store: a
// job first marks its patches folded_in_version = v + 1, then commits tile version v + 1. A patch
// counts as folded only when folded_in_version <= the committed mosaic version, so a job that dies
// between the two steps leaves its patches unfolded and can simply be re-run.
//
// A patch the map server refused (it failed admission: mapping/patch_admission.h) keeps its
// reason and is never selected for folding again. Each patch keeps the (wall-clock) time the
// server stored it, for retention (mosaic_retention.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"
#include "sqlite/sqlite_util.h"

namespace fleetloc::mosaic {

struct PatchRecord {
  std::string vehicle_id;
  int64_t sequence = 0;
  double stamp_s = 0;
  geometry::Pose2 pose;  // camera_ground of the image centre in map (docs/formats.md)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double quality = 0;
  cv::Mat image;  // CV_8UC1 at the mosaic's level-0 resolution
  int64_t folded_in_version = 0;
  // The image as received (PNG): stored as is when set (no re-encoding), else `image` is encoded.
  std::vector<std::uint8_t> png;
};

enum class PutOutcome { kStored, kDuplicate };

// An axis-aligned map rectangle, metres.
struct MapRect {
  double x_min = 0, y_min = 0, x_max = 0, y_max = 0;
};

struct PatchQuery {
  std::vector<PatchRecord> patches;
  int unreadable = 0;  // stored rows whose image did not decode (skipped, counted)
};

// Stored patches and their image bytes (of one vehicle, or of all).
struct StoredUsage {
  long long patches = 0;
  long long bytes = 0;
};

struct PatchCounts {
  long long stored = 0;
  long long folded = 0;  // at or below the given committed version
  long long refused = 0;
};

// A patch a re-mapping job refused, and why.
struct Refusal {
  std::string vehicle_id;
  int64_t sequence = 0;
  std::string reason;
};

class PatchStore {
 public:
  // Opens the mosaic file at `mosaic_path` (which must exist and be a mosaic) and creates the
  // patches table if absent. NotFound / InvalidInput naming the file; Internal on SQLite errors.
  static Result<std::unique_ptr<PatchStore>> Open(const std::string& mosaic_path);

  // Stores one patch in one transaction. kDuplicate (nothing written) if (vehicle_id, sequence)
  // is already stored. InvalidInput naming the field for an empty or non-gray image, a non-finite
  // pose, a covariance that is not finite, symmetric and positive definite, or a quality outside
  // [0, 1]; Internal on SQLite errors.
  Result<PutOutcome> Put(const PatchRecord& patch);

  // The patches whose footprint intersects `region` and that are neither folded at
  // `committed_version` nor refused, images decoded.
  Result<PatchQuery> Unfolded(const MapRect& region, int64_t committed_version);
  // The same patches without their images (pose, covariance, quality, ids), ordered by vehicle
  // and sequence: a re-mapping job reads each image when it needs it (LoadImage), so its memory
  // does not grow with the number of patches.
  Result<std::vector<PatchRecord>> UnfoldedHeaders(const MapRect& region,
                                                   int64_t committed_version);
  // The decoded image of one stored patch. NotFound if it is gone; InvalidInput if it does not
  // decode.
  Result<cv::Mat> LoadImage(const std::string& vehicle_id, int64_t sequence);

  // Every vehicle's stored patches and bytes (any state).
  Result<std::map<std::string, StoredUsage>> UsageByVehicle();

  // Marks the patches folded into `version` (see the note at the top), in one transaction.
  Status MarkFolded(const std::vector<PatchRecord>& patches, int64_t version);

  // Marks patches refused for good, with their reasons, in one transaction.
  Status MarkRefused(const std::vector<Refusal>& refusals);

  // Clears marks above `committed_version` left by a job that died before committing its tiles.
  Status ClearUncommittedMarks(int64_t committed_version);

  Result<PatchCounts> Counts(int64_t committed_version);

  // Footprint of a patch in map coordinates (its image's corners placed by its pose).
  MapRect Footprint(const PatchRecord& patch) const;

 private:
  PatchStore(std::string path, sqlite::Db db, double resolution_m);
  const std::string path_;
  std::mutex mutex_;
  sqlite::Db db_;
  const double resolution_m_;
};

}  // namespace fleetloc::mosaic
