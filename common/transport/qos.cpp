// QoS setters and fleetloc's named QoS profiles.
#include "transport/qos.h"

#include "base/status.h"

namespace fleetloc::transport {

namespace {
dds_duration_t Seconds(double s) { return static_cast<dds_duration_t>(s * 1e9); }
}  // namespace

Qos::Qos() : qos_(dds_create_qos()) { FLEETLOC_CHECK(qos_ != nullptr); }
Qos::~Qos() { dds_delete_qos(qos_); }
Qos::Qos(const Qos& other) : qos_(dds_create_qos()) { dds_copy_qos(qos_, other.qos_); }
Qos& Qos::operator=(const Qos& other) {
  if (this != &other) dds_copy_qos(qos_, other.qos_);
  return *this;
}

Qos& Qos::Reliable(double max_blocking_s) {
  dds_qset_reliability(qos_, DDS_RELIABILITY_RELIABLE, Seconds(max_blocking_s));
  return *this;
}
Qos& Qos::BestEffort() {
  dds_qset_reliability(qos_, DDS_RELIABILITY_BEST_EFFORT, 0);
  return *this;
}
Qos& Qos::KeepLast(int depth) {
  dds_qset_history(qos_, DDS_HISTORY_KEEP_LAST, depth);
  return *this;
}
Qos& Qos::KeepAll() {
  dds_qset_history(qos_, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
  return *this;
}
Qos& Qos::Volatile() {
  dds_qset_durability(qos_, DDS_DURABILITY_VOLATILE);
  return *this;
}
Qos& Qos::TransientLocal() {
  dds_qset_durability(qos_, DDS_DURABILITY_TRANSIENT_LOCAL);
  return *this;
}
Qos& Qos::Deadline(double period_s) {
  dds_qset_deadline(qos_, Seconds(period_s));
  return *this;
}
Qos& Qos::Liveliness(double lease_s) {
  dds_qset_liveliness(qos_, DDS_LIVELINESS_AUTOMATIC, Seconds(lease_s));
  return *this;
}
Qos& Qos::Partitions(const std::vector<std::string>& names) {
  std::vector<const char*> raw;
  for (const std::string& name : names) raw.push_back(name.c_str());
  dds_qset_partition(qos_, static_cast<uint32_t>(raw.size()), raw.data());
  return *this;
}
Qos& Qos::Limits(int max_samples, int max_instances, int max_samples_per_instance) {
  dds_qset_resource_limits(qos_, max_samples, max_instances, max_samples_per_instance);
  return *this;
}

Qos& Qos::UserData(const std::string& bytes) {
  dds_qset_userdata(qos_, bytes.data(), bytes.size());
  return *this;
}

Qos CommandQos() { return Qos().Reliable().KeepAll().Volatile(); }

Qos DurableStateQos(int depth) { return Qos().Reliable().TransientLocal().KeepLast(depth); }

Qos BulkQos(int max_samples, double max_blocking_s) {
  return Qos().Reliable(max_blocking_s).Volatile().KeepAll().Limits(max_samples, -1, -1);
}

Qos PoseStreamQos(double deadline_s, double lease_s) {
  return Qos().Reliable().Volatile().KeepLast(16).Deadline(deadline_s).Liveliness(lease_s);
}

Qos TileQos() { return Qos().Reliable(5.0).Volatile().KeepLast(1); }

Qos PeriodicStateQos(double deadline_s, double lease_s) {
  return Qos().Reliable().Volatile().KeepLast(1).Deadline(deadline_s).Liveliness(lease_s);
}

}  // namespace fleetloc::transport
