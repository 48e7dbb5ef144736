// The live stream's source: the DDS thread publishes the newest fleet snapshot (serialized once);
// the stream hub (stream_hub.h) is told of each and sends it to every Server-Sent-Events client;
// a reader can also wait for a snapshot newer than the one it saw last.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
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
  bool WaitNewer(uint64_t* seq, std::shared_ptr<const std::string>* data,
                 std::chrono::milliseconds timeout);
  // The newest snapshot and its sequence number (0 and null before the first).
  std::pair<uint64_t, std::shared_ptr<const std::string>> Latest() const;
  // Called (on the publishing thread, after each Publish and on Close) to tell a listener there is
  // news; it must not block, and must stay callable after it is replaced (a call may be under way).
  void SetListener(std::function<void()> listener);
  // Wakes everyone for good (shutdown).
  void Close();
  bool closed() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::shared_ptr<const std::string> data_;
  uint64_t seq_ = 0;
  bool closed_ = false;
  std::function<void()> listener_;
};

}  // namespace fleetloc::fleet_supervisor
