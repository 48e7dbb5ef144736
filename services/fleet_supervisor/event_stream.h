// The live stream's hub: the DDS thread publishes the newest fleet snapshot (serialized once);
// each Server-Sent-Events connection waits for a snapshot newer than the one it sent last.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

namespace fleetloc::fleet_supervisor {

class EventStream {
 public:
  // Replaces the current snapshot and wakes the waiting connections.
  void Publish(std::string data);
  // Waits up to `timeout` for a snapshot with a sequence number above *seq; on success stores it
  // in *data, updates *seq and returns true. False on time-out or once closed.
  bool WaitNewer(uint64_t* seq, std::shared_ptr<const std::string>* data, std::chrono::milliseconds timeout);
  // Wakes everyone for good (shutdown).
  void Close();
  bool closed() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::shared_ptr<const std::string> data_;
  uint64_t seq_ = 0;
  bool closed_ = false;
};

}  // namespace fleetloc::fleet_supervisor
