// fleetctl mosaic vehicles | prune | rollback: the upkeep of a mosaic file — each vehicle's
// standing with the map server (patches admitted and refused, recent verdicts, quarantine and why)
// as JSON and the release of a quarantined vehicle; retention (old tile versions and patches
// deleted, mosaic/mosaic_retention.h); and a rollback to an earlier version
// (mosaic/mosaic_rollback.h). All work on the file, also while the map server runs (it serves and
// announces a version committed by another writer within half a second).
#include <chrono>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.h"
#include "mosaic/mosaic_retention.h"
#include "mosaic/mosaic_rollback.h"
#include "mosaic_upkeep/vehicle_standing_store.h"
#include "transport/wire_util.h"

namespace fleetloc::fleetctl {
namespace {

struct VehiclesArgs {
  std::string mosaic;
  std::string release;
};

nlohmann::json ToJson(const mapping::VehicleStanding& s) {
  return {{"admitted", s.admitted},
          {"refused", s.refused},
          {"recent", s.recent},
          {"quarantined", s.quarantined},
          {"reason", s.reason}};
}

Status RunVehicles(const VehiclesArgs& a) {
  auto store = mosaic_upkeep::VehicleStandingStore::Open(a.mosaic);
  if (!store.ok()) return store.status();
  if (!a.release.empty()) {
    if (!transport::IsValidEntityId(a.release)) {
      return InvalidInput("--release: '" + a.release +
                          "' is not a vehicle id (1-11 of [A-Za-z0-9_-])");
    }
    FLEETLOC_RETURN_IF_ERROR((*store)->Release(a.release));
  }
  auto all = (*store)->All();
  if (!all.ok()) return all.status();
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [vehicle, standing] : *all) out[vehicle] = ToJson(standing);
  std::cout << out.dump(2) << "\n";
  return Status::Ok();
}

struct PruneArgs {
  std::string mosaic;
  int keep_versions = mosaic::RetentionPolicy{}.tile_versions_kept;
  double patch_days = mosaic::RetentionPolicy{}.patch_retention_s / 86400;
  double unfolded_days = mosaic::RetentionPolicy{}.unfolded_patch_retention_s / 86400;
  bool vacuum = false;
};

Status RunPrune(const PruneArgs& a) {
  const double now =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  Result<mosaic::PruneResult> r = mosaic::PruneMosaic(
      a.mosaic, {a.keep_versions, a.patch_days * 86400, a.unfolded_days * 86400}, now, a.vacuum);
  if (!r.ok()) return r.status();
  const nlohmann::json out = {{"mosaic_version", r->mosaic_version},
                              {"oldest_version_kept", r->oldest_version_kept},
                              {"tile_rows_deleted", r->tile_rows_deleted},
                              {"place_indexes_deleted", r->place_indexes_deleted},
                              {"patches_deleted", r->patches_deleted},
                              {"patch_bytes_deleted", r->patch_bytes_deleted},
                              {"file_bytes_before", r->file_bytes_before},
                              {"file_bytes_after", r->file_bytes_after}};
  std::cout << out.dump(2) << "\n";
  return Status::Ok();
}

void RegisterMosaicPruneCommand(CLI::App& mosaic, Status* result) {
  auto a = std::make_shared<PruneArgs>();
  CLI::App* cmd = mosaic.add_subcommand("prune",
                                        "Delete tile versions older than the last kept ones, and "
                                        "old folded, refused or stale patches");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("MOSAIC", a->mosaic, "Mosaic file")->required();
  cmd->add_option("--keep-versions", a->keep_versions,
                  "Mosaic versions whose tiles stay (the current one included)")
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--patch-retention-days", a->patch_days,
                  "Folded and refused patches older than this go")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--unfolded-retention-days", a->unfolded_days,
                  "Patches never folded older than this go")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--vacuum", a->vacuum,
                "Also give the freed space back to the file system (rewrites the file)");
  cmd->callback([a, result] { *result = RunPrune(*a); });
}

struct RollbackArgs {
  std::string mosaic;
  long long to_version = 0;
  bool dry_run = false;
};

Status RunRollback(const RollbackArgs& a) {
  auto store = mosaic::TileStore::Open(
      a.mosaic, a.dry_run ? mosaic::OpenMode::kReadOnly : mosaic::OpenMode::kReadWrite);
  if (!store.ok()) return store.status();
  Result<mosaic::RollbackResult> r = mosaic::RollBackMosaic(**store, a.to_version, a.dry_run);
  if (!r.ok()) return r.status();
  nlohmann::json tiles = nlohmann::json::array();
  for (const mosaic::TileKey& key : r->tiles) tiles.push_back(mosaic::ToString(key));
  const nlohmann::json out = {{"from_version", r->from_version},  {"to_version", r->to_version},
                              {"new_version", r->new_version},    {"dry_run", a.dry_run},
                              {"tiles_changed", r->tiles.size()}, {"tiles", tiles}};
  std::cout << out.dump(2) << "\n";
  return Status::Ok();
}

void RegisterMosaicRollbackCommand(CLI::App& mosaic, Status* result) {
  auto a = std::make_shared<RollbackArgs>();
  CLI::App* cmd = mosaic.add_subcommand(
      "rollback",
      "Write a new mosaic version whose tiles are those of an earlier version (--dry-run: list "
      "the tiles only)");
  cmd->add_option("MOSAIC", a->mosaic, "Mosaic file")->required();
  cmd->add_option("--to-version", a->to_version, "The earlier version to restore")->required();
  cmd->add_flag("--dry-run", a->dry_run, "List the tiles that would change, write nothing");
  cmd->callback([a, result] { *result = RunRollback(*a); });
}

}  // namespace

void RegisterMosaicUpkeepCommands(CLI::App& mosaic, Status* result) {
  RegisterMosaicPruneCommand(mosaic, result);
  RegisterMosaicRollbackCommand(mosaic, result);
  auto args = std::make_shared<VehiclesArgs>();
  CLI::App* cmd = mosaic.add_subcommand(
      "vehicles",
      "Print each vehicle's standing with the map server (patches admitted, refused, "
      "quarantine) as JSON; --release lifts a quarantine");
  cmd->add_option("MOSAIC", args->mosaic, "Mosaic file")->required();
  cmd->add_option("--release", args->release, "Vehicle id whose quarantine to lift");
  cmd->callback([args, result] { *result = RunVehicles(*args); });
}

}  // namespace fleetloc::fleetctl
