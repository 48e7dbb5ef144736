// A fleet_supervisor process for integration tests: own DDS domain, history in a scratch
// directory, any free HTTP port on loopback (read back from --port-file), a maintainer token.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "daemon_process.h"
#include "map_server_fixture.h"

namespace fleetloc::testing {

class SupervisorProcess {
 public:
  // `extra_args` go to fleet_supervisor after the fixture's own (e.g. --dds-config FILE).
  SupervisorProcess(const std::filesystem::path& dir, uint32_t domain, const std::string& token,
                    const std::vector<std::string>& extra_args = {})
      : dir_(dir), token_(token) {
    const std::string token_file = (dir / "token").string();
    std::ofstream(token_file) << token << "\n";
    // The supervisor refuses a token file group or others may read.
    std::filesystem::permissions(
        token_file, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
    const std::string port_file = (dir / "port").string();
    std::filesystem::remove(port_file);
    std::vector<std::string> args = {"--domain",     std::to_string(domain),
                                     "--history",    (dir / "history.db").string(),
                                     "--http-port",  "0",
                                     "--port-file",  port_file,
                                     "--token-file", token_file};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    process_ = std::make_unique<runtime::ChildProcess>(
        StartDaemon("fleet_supervisor", args, (dir / "fleet_supervisor.log").string()));
    EXPECT_TRUE(Eventually([&] {
      std::ifstream in(port_file);
      return static_cast<bool>(in >> port_) && port_ > 0;
    })) << "the supervisor never wrote its port; log: "
        << ReadWhole(dir / "fleet_supervisor.log");
  }
  ~SupervisorProcess() {
    if (process_) {
      EXPECT_EQ(process_->Stop(SIGTERM), 0) << "fleet_supervisor did not stop cleanly";
    }
  }

  // Kills the supervisor without letting it clean up (SIGKILL); the destructor then has nothing to
  // stop.
  void Crash() {
    process_->Stop(SIGKILL);
    process_.reset();
  }

  int port() const { return port_; }
  pid_t pid() const { return process_->pid(); }
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  const std::string& token() const { return token_; }
  std::string log() const { return ReadWhole(dir_ / "fleet_supervisor.log"); }

 private:
  std::filesystem::path dir_;
  std::string token_;
  int port_ = 0;
  std::unique_ptr<runtime::ChildProcess> process_;
};

}  // namespace fleetloc::testing
