// Runs build/bin/fleetctl as a child process for integration tests and captures its exit status,
// stdout and stderr.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>

namespace fleetloc::testing {

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// `text` quoted for the shell (single quotes; embedded ones escaped).
inline std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

inline std::string ReadWhole(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs the shell command line `command_line` (already quoted by the caller) with its streams
// captured in a fresh temp directory.
inline CommandResult RunCommand(const std::string& command_line) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("fleetctl_" + std::to_string(::getpid()) + "_" + std::to_string(std::rand()));
  std::filesystem::create_directories(dir);
  const std::string command =
      command_line + " >" + (dir / "out").string() + " 2>" + (dir / "err").string();
  const int status = std::system(command.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadWhole(dir / "out");
  r.err = ReadWhole(dir / "err");
  std::filesystem::remove_all(dir);
  return r;
}

// Runs `fleetctl <args>` (args already shell-quoted by the caller).
inline CommandResult RunFleetctl(const std::string& args) {
  return RunCommand(std::string(FLEETLOC_BINARY_DIR "/bin/fleetctl ") + args);
}

// Exit status 2 and exactly one non-empty line on stderr that contains every one of `parts`.
inline ::testing::AssertionResult IsBadInput(const CommandResult& r,
                                             std::initializer_list<std::string> parts) {
  if (r.exit_code != 2) {
    return ::testing::AssertionFailure() << "exit status " << r.exit_code << ", stderr: " << r.err;
  }
  if (r.err.empty() || r.err.back() != '\n' || r.err.find('\n') != r.err.size() - 1) {
    return ::testing::AssertionFailure() << "stderr is not one line: [" << r.err << "]";
  }
  for (const std::string& part : parts) {
    if (r.err.find(part) == std::string::npos) {
      return ::testing::AssertionFailure() << "stderr lacks '" << part << "': " << r.err;
    }
  }
  return ::testing::AssertionSuccess();
}

// A scratch directory removed at the end of the test.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              (name + "_" + std::to_string(::getpid()) + "_" + std::to_string(std::rand()))) {
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  const std::filesystem::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace fleetloc::testing
