// Publishes VDA 5050 visualization messages of every vehicle and the supervisor's own connection
// state to an MQTT broker (libmosquitto, its network thread started here). The broker being down,
// refusing the credentials or dropping the connection is counted, logged and reported by
// problem(); libmosquitto reconnects with backoff; nothing blocks the supervisor's loop: messages
// are QoS 0, published only while connected (otherwise counted as dropped), at the configured rate.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "base/status.h"
#include "fleet/vehicle_samples.h"
#include "fleet_supervisor/shared_fleet.h"
#include "fleet_supervisor/vda5050_options.h"

struct mosquitto;

namespace fleetloc::fleet_supervisor {

class Vda5050Publisher {
 public:
  // Sets up the client (credentials, TLS, the last will: the connection topic's CONNECTIONBROKEN,
  // retained) and starts connecting in the background. InvalidInput/NotFound for unusable
  // options (a TLS or password file that cannot be read); a broker that is down is no error.
  static Result<std::unique_ptr<Vda5050Publisher>> Start(const Vda5050Options& options,
                                                         const std::string& supervisor_id);
  // Publishes OFFLINE (retained), disconnects and stops the network thread.
  ~Vda5050Publisher();

  // True once per 1/rate_hz (the caller then gathers the poses and calls Publish).
  bool Due(double now);
  // One visualization message per vehicle heard from within max_pose_age_s before `now` (the
  // supervisor's clock).
  void Publish(const std::vector<LatestPose>& vehicles, const std::string& mosaic_id, double now);

  bool connected() const { return connected_.load(); }
  // "" while connected; else why not (never connected yet, refused, connection lost).
  std::string problem() const;
  // published, dropped (not connected), publish_errors, connects, connection_losses, refused.
  std::vector<std::pair<std::string, std::uint64_t>> Counters() const;

 private:
  explicit Vda5050Publisher(const Vda5050Options& options, std::string connection_serial);
  void OnConnect(int rc);
  void OnDisconnect(int rc);
  void SetProblem(std::string problem);
  void PublishConnection(const char* state, int qos);
  std::string SerialOf(const std::string& vehicle_id) const;

  Vda5050Options options_;
  std::string connection_serial_;
  mosquitto* client_ = nullptr;
  std::atomic<bool> connected_{false};
  std::atomic<std::uint64_t> published_{0}, dropped_{0}, publish_errors_{0}, connects_{0},
      losses_{0}, refused_{0};
  std::atomic<std::uint32_t> connection_header_id_{0};
  mutable std::mutex mutex_;
  std::string problem_ = "not connected to the MQTT broker yet";
  double next_publish_ = 0;
  std::map<std::string, std::uint32_t> header_ids_;    // per vehicle's visualization topic
  std::map<std::string, fleet::PoseSample> previous_;  // per vehicle: the pose last published
};

}  // namespace fleetloc::fleet_supervisor
