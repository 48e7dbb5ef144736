// A map_server process on its own DDS domain over a freshly imported mosaic, and a participant
// for the test to talk to it, shared by the map server integration and fault tests.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <functional>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "base/eventually.h"
#include "cli_runner.h"
#include "daemon_process.h"
#include "mosaic/importer.h"
#include "transport/topic_names.h"
#include "transport/typed_io.h"
#include "transport/wire_util.h"

namespace fleetloc::testing {

class MapServerFixture {
 public:
  // Imports `floor` (a gray image) at `resolution_m` with `tile_size_px` tiles and starts
  // map_server on `domain`; `config_members` (JSON members, e.g. `"patch_intake": {...}`) go into
  // a configuration file for it.
  MapServerFixture(const std::string& name, const cv::Mat& floor, uint32_t domain,
                   double resolution_m = 0.0005, int tile_size_px = 256,
                   const std::string& config_members = "")
      : scratch_(name), domain_(domain) {
    mosaic_path_ = (scratch_.path() / "floor.db").string();
    const std::string image = (scratch_.path() / "floor.png").string();
    EXPECT_TRUE(cv::imwrite(image, floor));
    mosaic::ImportOptions options;
    options.resolution_m = resolution_m;
    options.tile_size_px = tile_size_px;
    auto imported = mosaic::ImportImage(image, options, mosaic_path_);
    EXPECT_TRUE(imported.ok()) << imported.status().message();
    if (imported.ok()) layout_ = *imported;
    if (!config_members.empty()) {
      config_path_ = (scratch_.path() / "map_server.json").string();
      std::ofstream(config_path_) << R"({"mosaic": ")" << mosaic_path_ << R"(", )" << config_members
                                  << "}";
    }
    StartServer();
    auto participant = transport::Participant::Create(domain);
    EXPECT_TRUE(participant.ok()) << participant.status().message();
    participant_ = std::make_unique<transport::Participant>(std::move(participant).value());
  }
  ~MapServerFixture() {
    participant_.reset();
    if (server_) {
      EXPECT_EQ(server_->Stop(SIGTERM), 0) << "map_server did not stop cleanly";
    }
  }

  void StartServer() {
    std::vector<std::string> args = {
        "--mosaic", mosaic_path_, "--domain", std::to_string(domain_), "--server-id", "map-t"};
    if (!config_path_.empty()) args.insert(args.end(), {"--config", config_path_});
    server_ = std::make_unique<runtime::ChildProcess>(StartDaemon(
        "map_server", args,
        (scratch_.path() / ("map_server_" + std::to_string(++starts_) + ".log")).string()));
  }
  // Kills the server with `signal` and returns its exit status.
  int StopServer(int signal) {
    const int status = server_->Stop(signal);
    server_.reset();
    return status;
  }

  // The newest value of ServiceHealth counter `name` (waits up to 5 s for a report).
  uint64_t HealthCounter(const std::string& name) {
    auto topic = transport::Topic<fleetloc_ServiceHealth>::Create(
        *participant_, transport::topics::kServiceHealth);
    auto reader = transport::Reader<fleetloc_ServiceHealth>::Create(
        participant_->get(), *topic, transport::PeriodicStateQos(3, 5));
    uint64_t value = 0;
    bool seen = false;
    Eventually(
        [&] {
          (void)reader->TakeAll([&](const fleetloc_ServiceHealth& h, const dds_sample_info_t&) {
            for (uint32_t i = 0; i < h.counters._length; ++i) {
              if (transport::GetBounded(h.counters._buffer[i].name) == name) {
                value = h.counters._buffer[i].value;
                seen = true;
              }
            }
          });
          return seen;
        },
        5.0);
    EXPECT_TRUE(seen) << name;
    return value;
  }

  // "name: message" of the newest health report's issue ("" when it has none; waits up to 5 s
  // for a report).
  std::string HealthIssue() {
    auto topic = transport::Topic<fleetloc_ServiceHealth>::Create(
        *participant_, transport::topics::kServiceHealth);
    auto reader = transport::Reader<fleetloc_ServiceHealth>::Create(
        participant_->get(), *topic, transport::PeriodicStateQos(3, 5));
    std::string issue;
    bool seen = false;
    Eventually(
        [&] {
          (void)reader->TakeAll([&](const fleetloc_ServiceHealth& h, const dds_sample_info_t&) {
            seen = true;
            issue = h.issues._length == 0 ? ""
                                          : transport::GetBounded(h.issues._buffer[0].name) + ": " +
                                                transport::GetBounded(h.issues._buffer[0].message);
          });
          return seen;
        },
        5.0);
    EXPECT_TRUE(seen);
    return issue;
  }

  const std::string& mosaic_path() const { return mosaic_path_; }
  const mosaic::MosaicLayout& layout() const { return layout_; }
  transport::Participant& participant() { return *participant_; }
  uint32_t domain() const { return domain_; }
  const std::filesystem::path& dir() const { return scratch_.path(); }

 private:
  ScratchDir scratch_;
  uint32_t domain_;
  int starts_ = 0;
  std::string mosaic_path_;
  std::string config_path_;
  mosaic::MosaicLayout layout_;
  std::unique_ptr<runtime::ChildProcess> server_;
  std::unique_ptr<transport::Participant> participant_;
};

}  // namespace fleetloc::testing
