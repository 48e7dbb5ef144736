// MosaicInfo announcements → JSON on stdout.
#include "served_mosaics.h"

#include <chrono>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "transport/topic_names.h"
#include "transport/typed_io.h"
#include "transport/wire_util.h"

namespace fleetloc::fleetctl {

nlohmann::json MosaicInfoJson(const fleetloc_MosaicInfo& i) {
  using transport::GetBounded;
  return {{"server_id", GetBounded(i.server_id)},
          {"mosaic_id", GetBounded(i.mosaic_id)},
          {"version", i.version},
          {"width", i.width_px},
          {"height", i.height_px},
          {"tile_size", i.tile_size_px},
          {"levels", i.levels},
          {"resolution", i.resolution},
          {"origin_x", i.origin_x},
          {"origin_y", i.origin_y},
          {"tile_encoding", GetBounded(i.tile_encoding)},
          {"owned_tiles",
           {{"col_begin", i.owned_col_begin},
            {"col_end", i.owned_col_end},
            {"row_begin", i.owned_row_begin},
            {"row_end", i.owned_row_end}}},
          {"wire_version", i.wire_version},
          {"stamp", transport::ToSeconds(i.stamp)}};
}

Status PrintServedMosaics(int domain, double wait_s, const std::string& dds_config) {
  using namespace transport;
  auto participant = Participant::Create(domain, {"", dds_config});
  if (!participant.ok()) return participant.status();
  auto topic = Topic<fleetloc_MosaicInfo>::Create(*participant, topics::kMosaicInfo);
  if (!topic.ok()) return topic.status();
  auto reader = Reader<fleetloc_MosaicInfo>::Create(participant->get(), *topic, DurableStateQos());
  if (!reader.ok()) return reader.status();
  std::map<std::string, nlohmann::json> servers;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_s);
  while (std::chrono::steady_clock::now() < end) {
    (void)reader->TakeAll([&](const fleetloc_MosaicInfo& info, const dds_sample_info_t&) {
      servers[GetBounded(info.server_id)] = MosaicInfoJson(info);
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (servers.empty()) {
    return NotFound("no map server announced a mosaic on domain " + std::to_string(domain) +
                    " within " + std::to_string(wait_s) + " s");
  }
  nlohmann::json out{{"domain", domain}, {"servers", nlohmann::json::array()}};
  for (auto& [id, json] : servers) out["servers"].push_back(json);
  std::cout << out.dump(2) << "\n";
  return Status::Ok();
}

}  // namespace fleetloc::fleetctl
