// Re-mapping jobs: a RemapCommand is checked (wire version, mosaic, region) and queued; one worker
// thread runs the jobs in order with the re-mapping engine, reporting RemapStatus (queued, running
// with phase and progress, done with the per-vehicle summary as its message, failed, rejected).
// Finished jobs are handed back to the DDS loop (TakeFinished) to announce the new version.
// Stopping cancels the running job, which then leaves the mosaic as it was. Between jobs the same
// thread runs the periodic maintenance (pruning old tile versions and patches), so it never races a
// job for the mosaic file.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "map_server/server_counters.h"
#include "mosaic/raster_source.h"
#include "mosaic/tile_key.h"
#include "transport/typed_io.h"

namespace fleetloc::map_server {

struct RemapJob {
  uint64_t command_id = 0;
  double x_min = 0, y_min = 0, x_max = 0, y_max = 0;  // map metres
  bool replace = false;                               // else blend
};

struct RemapOutcome {
  long long new_version = 0;
  std::vector<mosaic::TileKey> changed_tiles;
  int patches_folded = 0;
  int patches_rejected = 0;
  int patches_held = 0;                        // awaiting another vehicle's confirmation
  std::string summary;                         // per vehicle: folded, refused (why), held
  std::vector<std::string> newly_quarantined;  // vehicles this job quarantined
};

using RemapProgressFn = std::function<void(const std::string& phase, double fraction)>;
// Runs one job to completion, or returns an error (the mosaic then unchanged).
using RemapRunner = std::function<Result<RemapOutcome>(const RemapJob&, const RemapProgressFn&,
                                                       const std::atomic<bool>& cancel)>;

// Work run every `period_s` between jobs (period 0: never).
struct Maintenance {
  double period_s = 0;
  std::function<void()> run;
};

class RemapService {
 public:
  static std::vector<std::string> CounterNames();

  RemapService(std::string server_id, RemapRunner runner,
               const transport::Writer<fleetloc_RemapStatus>* status_writer,
               ServerCounters* counters, Maintenance maintenance = {});
  ~RemapService();  // cancels the running job and joins the worker

  // `layout`: the mosaic served now (its id and extent bound the region).
  void Receive(const fleetloc_RemapCommand& command, const mosaic::MosaicLayout& layout);
  // Outcomes of the jobs finished since the last call.
  std::vector<RemapOutcome> TakeFinished();

 private:
  void Work();
  // Waits for a job (true) or until maintenance is due (false, after running it) or stop.
  bool WaitForJob(RemapJob* job);
  void Publish(uint64_t id, fleetloc_RemapState state, const std::string& phase, double progress,
               const std::string& message, const RemapOutcome* outcome = nullptr);

  const std::string server_id_;
  RemapRunner runner_;
  Maintenance maintenance_;
  const transport::Writer<fleetloc_RemapStatus>* status_writer_;
  ServerCounters* counters_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<RemapJob> queue_;
  std::vector<RemapOutcome> finished_;
  std::atomic<bool> stopping_{false};
  std::chrono::steady_clock::time_point next_maintenance_{};  // worker thread only (due at start)
  std::thread worker_;
};

}  // namespace fleetloc::map_server
