// Replies held back until the vehicle's reader is matched: a volatile writer's samples written
// before matching are lost, so each service queues its work per vehicle here and flushes it once
// the vehicle's channel is ready, expiring what waited too long.
#pragma once

#include <chrono>
#include <deque>
#include <string>
#include <utility>

namespace fleetloc::map_server {

template <typename Item>
class PendingReplies {
 public:
  using Clock = std::chrono::steady_clock;

  void Push(std::string vehicle_id, Item item) {
    entries_.push_back({std::move(vehicle_id), std::move(item), Clock::now()});
  }

  // For each queued item, in order: send(vehicle, item) if ready(vehicle); else expire(vehicle,
  // item) if it waited longer than `timeout`; else it stays queued.
  template <typename Ready, typename Send, typename Expire>
  void Flush(Ready&& ready, Send&& send, Expire&& expire, Clock::duration timeout) {
    const auto now = Clock::now();
    std::deque<Entry> waiting;
    for (Entry& entry : entries_) {
      if (ready(entry.vehicle_id)) {
        send(entry.vehicle_id, entry.item);
      } else if (now - entry.queued > timeout) {
        expire(entry.vehicle_id, entry.item);
      } else {
        waiting.push_back(std::move(entry));
      }
    }
    entries_ = std::move(waiting);
  }

  size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    std::string vehicle_id;
    Item item;
    Clock::time_point queued;
  };
  std::deque<Entry> entries_;
};

}  // namespace fleetloc::map_server
