// Waitset with data-available read conditions and a guard condition for wake-ups.
#include "transport/waitset.h"

#include <array>

namespace fleetloc::transport {

namespace {
constexpr dds_attach_t kGuardTag = -1;
}

Result<WaitSet> WaitSet::Create(const Participant& participant) {
  Result<Entity> waitset = Adopt(dds_create_waitset(participant.get()), "DDS waitset");
  if (!waitset.ok()) return waitset.status();
  Result<Entity> guard = Adopt(dds_create_guardcondition(participant.get()), "DDS guard");
  if (!guard.ok()) return guard.status();
  FLEETLOC_RETURN_IF_ERROR(DdsStatus(dds_waitset_attach(waitset->get(), guard->get(), kGuardTag),
                                     "attach guard condition"));
  return WaitSet(std::move(waitset).value(), std::move(guard).value());
}

Status WaitSet::AttachReader(dds_entity_t reader, dds_attach_t tag) {
  Result<Entity> condition =
      Adopt(dds_create_readcondition(
                reader, DDS_NOT_READ_SAMPLE_STATE | DDS_ANY_VIEW_STATE | DDS_ANY_INSTANCE_STATE),
            "DDS read condition");
  if (!condition.ok()) return condition.status();
  FLEETLOC_RETURN_IF_ERROR(
      DdsStatus(dds_waitset_attach(waitset_.get(), condition->get(), tag), "attach reader"));
  conditions_.push_back(std::move(condition).value());
  return Status::Ok();
}

Result<std::vector<dds_attach_t>> WaitSet::Wait(double timeout_s) {
  std::array<dds_attach_t, 32> triggered{};
  const dds_return_t n = dds_waitset_wait(waitset_.get(), triggered.data(), triggered.size(),
                                          static_cast<dds_duration_t>(timeout_s * 1e9));
  if (n < 0) return DdsStatus(n, "waitset wait");
  std::vector<dds_attach_t> tags;
  for (int i = 0; i < n && i < static_cast<int>(triggered.size()); ++i) {
    if (triggered[i] == kGuardTag) {
      dds_set_guardcondition(guard_.get(), false);
      continue;
    }
    tags.push_back(triggered[i]);
  }
  return tags;
}

Status WaitSet::Wake() {
  return DdsStatus(dds_set_guardcondition(guard_.get(), true), "set guard condition");
}

}  // namespace fleetloc::transport
