// Child processes: exit status, stop by signal, environment and log file, missing program.
#include "runtime/child_process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fleetloc::runtime {
namespace {

std::string LogPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("child_process_" + name + ".log")).string();
}

TEST(ChildProcess, ReportsTheExitStatusAndWritesTheLogWithTheExtraEnvironment) {
  auto child = ChildProcess::Start("/bin/sh", {"-c", "echo \"$FLEETLOC_TEST_VALUE\"; exit 3"},
                                   LogPath("exit"), {"FLEETLOC_TEST_VALUE=forty-two"});
  ASSERT_TRUE(child.ok()) << child.status().message();
  EXPECT_EQ(child->Wait(std::chrono::seconds(10)), 3);
  std::stringstream log;
  log << std::ifstream(LogPath("exit")).rdbuf();
  EXPECT_EQ(log.str(), "forty-two\n");
}

TEST(ChildProcess, StopsARunningChildWithTheSignal) {
  auto child = ChildProcess::Start("/bin/sleep", {"30"}, LogPath("sleep"));
  ASSERT_TRUE(child.ok());
  EXPECT_TRUE(child->Running());
  EXPECT_EQ(child->Stop(SIGTERM), 128 + SIGTERM);
  EXPECT_FALSE(child->Running());
}

TEST(ChildProcess, UsageOfAProcessIsReadFromProc) {
  const ProcessUsage self = UsageOf(::getpid());
  EXPECT_GT(self.rss_mb, 1.0);
  EXPECT_GE(self.peak_rss_mb, self.rss_mb);
  EXPECT_GE(self.cpu_s, 0.0);
  EXPECT_EQ(UsageOf(-1).rss_mb, 0.0);
}

TEST(ChildProcess, MissingProgramIsNotFound) {
  auto child = ChildProcess::Start("/nonexistent/daemon", {}, LogPath("missing"));
  ASSERT_FALSE(child.ok());
  EXPECT_EQ(child.status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetloc::runtime
