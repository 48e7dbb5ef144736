// Whether a kind of service (e.g. "map_server") is alive, judged by its periodic ServiceHealth:
// DDS discovery alone keeps a killed process "matched" until its participant lease (10 s by
// default) expires; a health report seen within a timeout is what the agent calls reachable.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <string>

#include "transport/typed_io.h"

namespace fleetloc::transport {

class ServiceWatch {
 public:
  using Clock = std::chrono::steady_clock;

  static Result<std::unique_ptr<ServiceWatch>> Create(const Participant& participant,
                                                      std::string kind);

  // Takes the health reports received since the last call; remembers when one of `kind` came.
  void Poll();
  // True when a report of `kind` arrived within `timeout` before `now` (Poll first). Before the
  // first report, the watch's creation counts as one: a service is not called unreachable
  // before it has had `timeout` to report.
  bool SeenWithin(Clock::duration timeout, Clock::time_point now = Clock::now()) const;
  // The same for the one service `service_id` of this kind (e.g. one of several map servers).
  bool SeenWithin(const std::string& service_id, Clock::duration timeout,
                  Clock::time_point now = Clock::now()) const;
  long long reports() const { return reports_; }

 private:
  ServiceWatch(std::string kind, Topic<fleetloc_ServiceHealth> topic,
               Reader<fleetloc_ServiceHealth> reader)
      : kind_(std::move(kind)), topic_(std::move(topic)), reader_(std::move(reader)) {}

  std::string kind_;
  Topic<fleetloc_ServiceHealth> topic_;
  Reader<fleetloc_ServiceHealth> reader_;
  const Clock::time_point created_ = Clock::now();
  Clock::time_point last_seen_ = created_;
  std::map<std::string, Clock::time_point> last_seen_by_id_;
  long long reports_ = 0;
};

}  // namespace fleetloc::transport
