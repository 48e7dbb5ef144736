// The maintainer side of re-mapping: sends RemapCommand to the map server and follows the jobs'
// RemapStatus (their conversions: remap_messages.h). Shared by `fleetctl remap` and the fleet
// supervisor's dashboard.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "transport/remap_messages.h"
#include "transport/typed_io.h"

namespace fleetloc::transport {

class RemapClient {
 public:
  static Result<std::unique_ptr<RemapClient>> Create(const Participant& participant);

  // True when a map server reads our commands.
  bool ServerMatched() const { return commands_.MatchedReaders() > 0; }
  // How many map servers read our commands (each runs every command on its own replica).
  int MatchedServers() const { return commands_.MatchedReaders(); }
  // Sends the command with a fresh random id, which it returns. InvalidInput for an empty or
  // inverted region or non-finite numbers; Internal on a DDS failure.
  Result<uint64_t> Send(const RemapRequest& request);
  // Sends an already filled wire sample as is, unchecked (tests use it to forge bad ones).
  Status SendRaw(const fleetloc_RemapCommand& command);
  // The statuses received since the last call (of every job, also other requesters').
  Result<std::vector<RemapProgress>> TakeStatuses();
  // Ids of the live map servers announcing (MosaicInfo) mosaic `mosaic_id`, or any mosaic when
  // empty: those a command for it runs on, each on its own replica. Sorted.
  std::vector<std::string> ServersOf(const std::string& mosaic_id);

 private:
  RemapClient(Topic<fleetloc_RemapCommand> command_topic, Topic<fleetloc_RemapStatus> status_topic,
              Writer<fleetloc_RemapCommand> commands, Reader<fleetloc_RemapStatus> statuses,
              Topic<fleetloc_MosaicInfo> info_topic, Reader<fleetloc_MosaicInfo> infos)
      : command_topic_(std::move(command_topic)),
        status_topic_(std::move(status_topic)),
        commands_(std::move(commands)),
        statuses_(std::move(statuses)),
        info_topic_(std::move(info_topic)),
        infos_(std::move(infos)) {}

  Topic<fleetloc_RemapCommand> command_topic_;
  Topic<fleetloc_RemapStatus> status_topic_;
  Writer<fleetloc_RemapCommand> commands_;
  Reader<fleetloc_RemapStatus> statuses_;
  Topic<fleetloc_MosaicInfo> info_topic_;
  Reader<fleetloc_MosaicInfo> infos_;
  std::map<std::string, std::string> mosaic_of_server_;  // announced: server id -> mosaic id
};

}  // namespace fleetloc::transport
