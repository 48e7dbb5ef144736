// RAII entity handle and return-code checks.
#include "transport/dds_entity.h"

namespace fleetloc::transport {

void Entity::Reset() {
  if (handle_ > 0) dds_delete(handle_);
  handle_ = 0;
}

Status DdsStatus(dds_return_t rc, const std::string& what) {
  if (rc >= 0) return Status::Ok();
  return Internal(what + ": " + dds_strretcode(-rc));
}

Result<Entity> Adopt(dds_entity_t handle, const std::string& what) {
  if (handle < 0) return DdsStatus(handle, what);
  return Entity(handle);
}

}  // namespace fleetloc::transport
