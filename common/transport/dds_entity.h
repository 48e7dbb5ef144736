// RAII ownership of one Cyclone DDS entity handle, and the check that turns a negative dds_*
// return code into a Status naming the call and the entity.
#pragma once

#include <dds/dds.h>

#include <string>
#include <utility>

#include "base/status.h"

namespace fleetloc::transport {

// Owns a dds_entity_t (participant, topic, reader, writer, waitset, ...): dds_delete runs when it
// goes out of scope, which also deletes the entity's children. Move-only.
class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  ~Entity() { Reset(); }
  Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      Reset();
      handle_ = std::exchange(other.handle_, 0);
    }
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;

  dds_entity_t get() const { return handle_; }
  bool valid() const { return handle_ > 0; }
  void Reset();

 private:
  dds_entity_t handle_ = 0;
};

// Status for a dds_return_t: ok when rc >= 0, else Internal("<what>: <dds_strretcode>").
Status DdsStatus(dds_return_t rc, const std::string& what);

// Wraps a freshly created handle: the Entity when handle > 0, else the Status naming `what`.
Result<Entity> Adopt(dds_entity_t handle, const std::string& what);

}  // namespace fleetloc::transport
