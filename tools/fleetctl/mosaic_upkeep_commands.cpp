// fleetctl mosaic vehicles: the upkeep of a mosaic file's patch intake — each vehicle's standing
// with the map server (patches admitted and refused, recent verdicts, quarantine and why) as JSON,
// and the release of a quarantined vehicle. Works on the file, also while the map server runs
// (the server reads the standing on every patch and health report).
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.h"
#include "mosaic/vehicle_standing_store.h"
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
  auto store = mosaic::VehicleStandingStore::Open(a.mosaic);
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

}  // namespace

void AddMosaicUpkeepCommands(CLI::App& mosaic, Status* result) {
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
