// No silent port sharing (issue 22): a second supervisor started on the HTTP port of a running one
// fails at start with exit status 1 and an error naming the address, instead of listening too
// (httplib's default SO_REUSEPORT let both accept and split the requests between them).
// clang-format off: Eigen before httplib (<resolv.h> defines `_res`, a name Eigen's headers use)
#include <Eigen/Core>
// clang-format on
#include <gtest/gtest.h>
#include <httplib.h>

#include "cli_runner.h"
#include "supervisor_fixture.h"

namespace fleetloc {
namespace {

constexpr uint32_t kDomain = 125;

TEST(SupervisorPort, ASecondSupervisorOnTheSamePortFailsAtStartAndTheFirstServesOn) {
  testing::ScratchDir dir("supervisor_port");
  testing::SupervisorProcess first(dir.path(), kDomain, "tok-3333-3333-3333");
  const std::string port = std::to_string(first.port());
  // `timeout`: before the fix the second one listened too and ran until killed (exit 124).
  const testing::CommandResult second =
      testing::RunCommand("timeout 20 " FLEETLOC_BINARY_DIR "/bin/fleet_supervisor --domain " +
                          std::to_string(kDomain) + " --history " +
                          testing::Quote((dir.path() / "second.db").string()) + " --http-port " +
                          port + " --metrics-port 0");
  EXPECT_EQ(second.exit_code, 1) << second.err;
  EXPECT_NE(second.err.find("cannot listen on 127.0.0.1:" + port + ": the port is in use"),
            std::string::npos)
      << second.err;
  httplib::Client http("127.0.0.1", first.port());
  for (int i = 0; i < 10; ++i) {
    auto r = http.Get("/healthz");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  }
}

}  // namespace
}  // namespace fleetloc
