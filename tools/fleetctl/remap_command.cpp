// fleetctl remap: asks the running map server (over DDS) to fold the stored patches of a map
// region into a new mosaic version, follows the job's RemapStatus and prints the outcome as JSON.
#include <spdlog/spdlog.h>

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "commands.h"
#include "transport/topic_names.h"
#include "transport/typed_io.h"
#include "transport/wire_util.h"

namespace fleetloc::fleetctl {
namespace {

struct RemapArgs {
  std::vector<double> region;  // x_min, y_min, x_max, y_max (map metres)
  std::string mode = "blend";
  std::string mosaic_id;
  int domain = 0;
  std::string dds_config;
  double timeout_s = 600;
};

const char* StateName(fleetloc_RemapState state) {
  switch (state) {
    case fleetloc_REMAP_QUEUED: return "queued";
    case fleetloc_REMAP_RUNNING: return "running";
    case fleetloc_REMAP_DONE: return "done";
    case fleetloc_REMAP_FAILED: return "failed";
    case fleetloc_REMAP_REJECTED: return "rejected";
  }
  return "unknown";
}

nlohmann::json StatusJson(const fleetloc_RemapStatus& s) {
  return {{"command_id", s.command_id},
          {"server_id", transport::GetBounded(s.server_id)},
          {"state", StateName(s.state)},
          {"new_version", s.new_version},
          {"tiles_changed", s.tiles_changed},
          {"patches_folded", s.patches_folded},
          {"patches_rejected", s.patches_rejected},
          {"message", transport::GetBounded(s.message)}};
}

fleetloc_RemapCommand MakeCommand(const RemapArgs& a, uint64_t command_id) {
  fleetloc_RemapCommand command{};
  command.wire_version = fleetloc_WIRE_VERSION;
  command.command_id = command_id;
  transport::SetBounded(command.requester, "fleetctl");
  transport::SetBounded(command.mosaic_id, a.mosaic_id);
  command.region = {a.region[0], a.region[1], a.region[2], a.region[3]};
  command.mode = a.mode == "replace" ? fleetloc_REMAP_REPLACE : fleetloc_REMAP_BLEND;
  command.stamp = transport::NowStamp();
  return command;
}

// Sends the command once a map server listens, then follows its status until done, failed,
// rejected or the time-out.
Status RunRemap(const RemapArgs& a) {
  if (a.region.size() != 4) return InvalidInput("--region: give x_min,y_min,x_max,y_max");
  using namespace transport;
  auto participant = Participant::Create(a.domain, {"", a.dds_config});
  if (!participant.ok()) return participant.status();
  auto command_topic = Topic<fleetloc_RemapCommand>::Create(*participant, topics::kRemapCommand);
  auto status_topic = Topic<fleetloc_RemapStatus>::Create(*participant, topics::kRemapStatus);
  if (!command_topic.ok()) return command_topic.status();
  if (!status_topic.ok()) return status_topic.status();
  auto writer = Writer<fleetloc_RemapCommand>::Create(participant->get(), *command_topic, CommandQos());
  auto reader = Reader<fleetloc_RemapStatus>::Create(participant->get(), *status_topic, DurableStateQos());
  if (!writer.ok()) return writer.status();
  if (!reader.ok()) return reader.status();
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(a.timeout_s);
  while (writer->MatchedReaders() == 0) {
    if (Clock::now() > deadline) return Internal("no map server on domain " + std::to_string(a.domain));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const uint64_t id = std::random_device{}() * 4294967296ull + std::random_device{}();
  FLEETLOC_RETURN_IF_ERROR(writer->Write(MakeCommand(a, id)));
  spdlog::info("remap: command {} sent", id);
  std::optional<fleetloc_RemapStatus> final;
  while (!final && Clock::now() < deadline) {
    (void)reader->TakeAll([&](const fleetloc_RemapStatus& s, const dds_sample_info_t&) {
      if (s.command_id != id) return;
      spdlog::info("remap: {} {} {:.0f}%", StateName(s.state), GetBounded(s.phase), 100 * s.progress);
      if (s.state >= fleetloc_REMAP_DONE) final = s;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!final) return Internal("remap: no final status within " + std::to_string(a.timeout_s) + " s");
  std::cout << StatusJson(*final).dump(2) << "\n";
  const std::string message = GetBounded(final->message);
  if (final->state == fleetloc_REMAP_REJECTED) return InvalidInput("remap rejected: " + message);
  if (final->state == fleetloc_REMAP_FAILED) return Internal("remap failed: " + message);
  return Status::Ok();
}

}  // namespace

void RegisterRemapCommand(CLI::App& app, Status* result) {
  auto a = std::make_shared<RemapArgs>();
  CLI::App* remap = app.add_subcommand(
      "remap", "Fold the stored patches of a map region into a new mosaic version (over DDS)");
  remap->option_defaults()->always_capture_default();
  remap->add_option("--region", a->region, "X_MIN,Y_MIN,X_MAX,Y_MAX in map metres")
      ->required()
      ->delimiter(',')
      ->expected(4);
  remap->add_option("--mode", a->mode, "blend (average with the mosaic) or replace (changed floor)")
      ->check(CLI::IsMember({"blend", "replace"}));
  remap->add_option("--mosaic-id", a->mosaic_id, "Mosaic id (default: the one the server serves)");
  remap->add_option("--domain", a->domain, "DDS domain")->check(CLI::Range(0, 232));
  remap->add_option("--dds-config", a->dds_config, "Cyclone DDS XML (default: built-in loopback)");
  remap->add_option("--timeout", a->timeout_s, "Seconds to wait for the job")->check(CLI::PositiveNumber);
  remap->callback([a, result] { *result = RunRemap(*a); });
}

}  // namespace fleetloc::fleetctl
