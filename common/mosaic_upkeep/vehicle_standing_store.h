// The vehicles' standing with the map server (mapping/vehicle_reputation.h), kept in the mosaic
// file's `vehicle_standing` table: how many of each vehicle's patches were admitted and refused,
// its recent verdicts, and whether it is quarantined (its patches then refused on arrival) and why.
// The map server updates it after each re-mapping job; `fleetctl mosaic vehicles` reads it and
// releases a quarantined vehicle.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "base/status.h"
#include "mapping/vehicle_reputation.h"
#include "sqlite/sqlite_util.h"

namespace fleetloc::mosaic_upkeep {

class VehicleStandingStore {
 public:
  // Opens the mosaic file at `mosaic_path` (which must exist) and creates the table if absent.
  // NotFound naming the file; Internal on SQLite errors.
  static Result<std::unique_ptr<VehicleStandingStore>> Open(const std::string& mosaic_path);

  // Every vehicle with a standing, by id.
  Result<std::map<std::string, mapping::VehicleStanding>> All();
  // A vehicle's standing (a fresh one if it has none yet).
  Result<mapping::VehicleStanding> Get(const std::string& vehicle_id);
  Result<bool> IsQuarantined(const std::string& vehicle_id);
  // Writes the given standings in one transaction.
  Status PutAll(const std::map<std::string, mapping::VehicleStanding>& standings);
  // Lifts a vehicle's quarantine (mapping::Release). NotFound if the vehicle has no standing.
  Status Release(const std::string& vehicle_id);

 private:
  VehicleStandingStore(std::string path, sqlite::Db db)
      : path_(std::move(path)), db_(std::move(db)) {}
  Result<std::map<std::string, mapping::VehicleStanding>> Select(const std::string* vehicle_id);
  Status PutAllLocked(const std::map<std::string, mapping::VehicleStanding>& standings);
  const std::string path_;
  std::mutex mutex_;
  sqlite::Db db_;
};

}  // namespace fleetloc::mosaic_upkeep
