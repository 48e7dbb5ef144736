// A waitset over readers' data-available conditions, so a service thread sleeps until there is
// work or a timeout (used for periodic jobs and to notice a stop request).
#pragma once

#include <vector>

#include "transport/dds_entity.h"
#include "transport/participant.h"

namespace fleetloc::transport {

class WaitSet {
 public:
  static Result<WaitSet> Create(const Participant& participant);

  // Wakes Wait() when `reader` has samples not yet taken; Wait() then returns `tag`.
  Status AttachReader(dds_entity_t reader, dds_attach_t tag);
  // Blocks until an attached reader has data or `timeout_s` passes; returns the tags that
  // triggered (empty on timeout). Internal on a DDS error.
  Result<std::vector<dds_attach_t>> Wait(double timeout_s);
  // Makes a concurrent or the next Wait() return at once (from another thread, not a signal
  // handler).
  Status Wake();

 private:
  WaitSet(Entity waitset, Entity guard) : waitset_(std::move(waitset)), guard_(std::move(guard)) {}
  Entity waitset_;
  Entity guard_;
  std::vector<Entity> conditions_;
};

}  // namespace fleetloc::transport
