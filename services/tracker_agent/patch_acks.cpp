// PatchAck decisions for a mosaic replicated on every owning map server.
#include "tracker_agent/patch_acks.h"

#include <algorithm>

namespace fleetloc::tracker_agent {

AckDecision DecideAck(const transport::ReceivedAck& ack, const std::vector<std::string>& replicas) {
  std::string server = ack.server_id;
  if (server.empty() && replicas.size() == 1) server = replicas.front();
  if (std::find(replicas.begin(), replicas.end(), server) == replicas.end()) return {};
  const AckAction action =
      ack.status == fleetloc_PATCH_REJECTED ? AckAction::kDrop : AckAction::kCount;
  return {action, std::move(server)};
}

}  // namespace fleetloc::tracker_agent
