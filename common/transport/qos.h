// QoS as values: a RAII dds_qos_t with chainable setters, and the few named profiles every
// fleetloc topic uses (docs/topics.md says which topic takes which, and why).
#pragma once

#include <dds/dds.h>

#include <string>
#include <vector>

namespace fleetloc::transport {

class Qos {
 public:
  Qos();
  ~Qos();
  Qos(const Qos& other);
  Qos& operator=(const Qos& other);

  Qos& Reliable(double max_blocking_s = 1.0);
  Qos& BestEffort();
  Qos& KeepLast(int depth);
  Qos& KeepAll();
  Qos& Volatile();
  Qos& TransientLocal();
  // A writer promises (a reader expects) a sample of each instance at least this often.
  Qos& Deadline(double period_s);
  // Automatic liveliness: the participant asserts it; lost after `lease_s` of silence.
  Qos& Liveliness(double lease_s);
  Qos& Partitions(const std::vector<std::string>& names);
  // Bounds a KEEP_ALL history (samples in total and per instance); -1 = unlimited.
  Qos& Limits(int max_samples, int max_instances, int max_samples_per_instance);
  // USER_DATA: bytes every matched reader can see (MatchedWriters), e.g. which server writes.
  Qos& UserData(const std::string& bytes);

  const dds_qos_t* get() const { return qos_; }

 private:
  dds_qos_t* qos_;
};

// Profiles (see docs/topics.md):
// Commands and requests: reliable, every sample delivered in order, nothing kept for late joiners.
Qos CommandQos();
// Latest-state announcements late joiners must get (MosaicInfo, TileUpdate, RemapStatus,
// PlaceIndexChunk): reliable, transient-local, the last `depth` samples of each instance.
Qos DurableStateQos(int depth = 1);
// Bulk payloads (PatchObservation; tiles take TileQos): reliable so lost fragments are resent,
// KEEP_ALL with a bound so a slow reader throttles the writer instead of losing samples. A write
// waits at most `max_blocking_s` for room before it fails with a time-out.
Qos BulkQos(int max_samples = 256, double max_blocking_s = 5.0);
// A vehicle's pose stream (VehiclePose): like PeriodicStateQos but the writer keeps the last 16
// samples of each vehicle, so a burst (a frame's pose right after the odometry-rate ones) reaches
// a reader that keeps them all; a keep-last-1 reader (the supervisor) still gets only the newest.
Qos PoseStreamQos(double deadline_s = 1.0, double lease_s = 3.0);
// Tiles: reliable, the newest sample of each tile (keyed by level, col, row) kept until
// acknowledged — an older version of a tile still unsent is superseded, never queued behind.
Qos TileQos();
// Periodic state (VehicleHealth, ServiceHealth; poses take PoseStreamQos): the newest sample per
// instance matters; reliable keep-last 1 with a deadline and liveliness so silence is detected.
Qos PeriodicStateQos(double deadline_s, double lease_s);

}  // namespace fleetloc::transport
