// ServiceWatch: last-seen time of a kind of service from its ServiceHealth reports.
#include "transport/service_watch.h"

#include "transport/qos.h"
#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::transport {

Result<std::unique_ptr<ServiceWatch>> ServiceWatch::Create(const Participant& participant,
                                                           std::string kind) {
  auto topic = Topic<fleetloc_ServiceHealth>::Create(participant, topics::kServiceHealth);
  if (!topic.ok()) return topic.status();
  // Volatile, keep-last: only fresh reports matter. No deadline of our own, so every server's
  // writer (whatever its period) is compatible.
  auto reader = Reader<fleetloc_ServiceHealth>::Create(participant.get(), *topic,
                                                       Qos().Reliable().Volatile().KeepLast(1));
  if (!reader.ok()) return reader.status();
  return std::unique_ptr<ServiceWatch>(
      new ServiceWatch(std::move(kind), std::move(topic).value(), std::move(reader).value()));
}

void ServiceWatch::Poll() {
  (void)reader_.TakeAll([&](const fleetloc_ServiceHealth& h, const dds_sample_info_t&) {
    if (GetBounded(h.kind) != kind_) return;
    last_seen_ = Clock::now();
    last_seen_by_id_[GetBounded(h.service_id)] = last_seen_;
    ++reports_;
  });
}

bool ServiceWatch::SeenWithin(Clock::duration timeout, Clock::time_point now) const {
  return now - last_seen_ <= timeout;
}

bool ServiceWatch::SeenWithin(const std::string& service_id, Clock::duration timeout,
                              Clock::time_point now) const {
  auto it = last_seen_by_id_.find(service_id);
  return now - (it == last_seen_by_id_.end() ? created_ : it->second) <= timeout;
}

}  // namespace fleetloc::transport
