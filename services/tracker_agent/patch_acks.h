// What the agent does with one PatchAck when every map server owning part of the mosaic keeps a
// replica of every patch: an answer counts only for a replica of the vehicle's mosaic (a server
// of another mosaic on the same domain rejects every patch as "unknown mosaic"; that must not end
// a patch the replicas still need), and a patch leaves the outbox once each replica stored it.
#pragma once

#include <string>
#include <vector>

#include "transport/patch_client.h"

namespace fleetloc::tracker_agent {

enum class AckAction {
  kIgnore,  // not from a replica of our mosaic, or from an unnamed server among several
  kDrop,    // a replica rejected the patch: resending cannot help
  kCount,   // a replica stored it (or already had it): counts for `server`
};

struct AckDecision {
  AckAction action = AckAction::kIgnore;
  std::string server;  // the replica the answer is from (kDrop, kCount)
};

// `replicas`: the ids of the map servers owning part of the vehicle's mosaic. An ack whose writer
// names no server (a map server from before acks named theirs) is taken as the only replica's
// when there is just one, and ignored among several (the patch is sent again later).
AckDecision DecideAck(const transport::ReceivedAck& ack, const std::vector<std::string>& replicas);

}  // namespace fleetloc::tracker_agent
