// The supervisor's history in SQLite: sampled poses and every health report per vehicle, and
// every alert raised and cleared, with a retention limit. The supervisor restores the fleet's last
// known state and its open alerts from it after a restart. Thread-safe (one mutex, one
// connection; WAL so a reader such as the sqlite3 shell never blocks it).
#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "base/status.h"
#include "fleet/fleet_state.h"
#include "sqlite/sqlite_util.h"

namespace fleetloc::fleet_supervisor {

struct StoredPose {
  std::string vehicle_id;
  double received = 0.0;  // supervisor clock
  fleet::PoseSample pose;
};

struct StoredHealth {
  std::string vehicle_id;
  double received = 0.0;
  fleet::HealthSample health;
};

struct AlertQuery {
  std::string vehicle_id;  // empty: every vehicle
  bool active_only = false;
  int limit = 200;
};

class HistoryStore {
 public:
  // Opens (creating if needed) the history at `path`. Internal naming the file on failure, or
  // InvalidInput if the file is not a fleetloc history.
  static Result<std::unique_ptr<HistoryStore>> Open(const std::string& path);

  // Appends the rows in one transaction.
  Status Append(const std::vector<StoredPose>& poses, const std::vector<StoredHealth>& health);
  // Stores a raised alert and returns its id; Close sets the cleared time of a stored one.
  Result<long long> InsertAlert(const fleet::Alert& alert);
  Status CloseAlert(long long id, double cleared_t);
  // Deletes pose and health rows received before `before` and alerts cleared before it; returns
  // the number of rows deleted. (History is indexed by the supervisor's receive time: a vehicle's
  // stamps may be on another clock, e.g. a replayed run's.)
  Result<long long> Prune(double before);

  // Rows of one vehicle received in [from, to], oldest first, at most `limit` (the newest kept).
  Result<std::vector<StoredPose>> Poses(const std::string& vehicle_id, double from, double to,
                                        int limit);
  Result<std::vector<StoredHealth>> Health(const std::string& vehicle_id, double from, double to,
                                           int limit);
  // Alerts, newest raised first.
  Result<std::vector<fleet::Alert>> Alerts(const AlertQuery& query);
  // Every vehicle with its newest stored pose and health (trail empty); last_seen is the
  // received time of the newer one.
  Result<std::vector<fleet::VehicleState>> LatestVehicles();
  // Whether the history has any row of this vehicle.
  Result<bool> KnowsVehicle(const std::string& vehicle_id);

 private:
  explicit HistoryStore(sqlite::Db db) : db_(std::move(db)) {}
  Status CreateSchema();

  std::mutex mutex_;
  sqlite::Db db_;
};

}  // namespace fleetloc::fleet_supervisor
