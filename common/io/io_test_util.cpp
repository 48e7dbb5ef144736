// Test helpers for the io tests.
#include "io/io_test_util.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <sstream>

namespace fleetloc::io::testing {

namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = fs::temp_directory_path() /
          ("fleetloc_io_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void WriteText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

::testing::AssertionResult HasError(const Status& status, StatusCode code, const fs::path& file,
                                    int line, const std::string& field) {
  std::string prefix = file.string();
  if (line > 0) prefix.append(":").append(std::to_string(line));
  prefix += ": ";
  if (!field.empty()) prefix += "field '" + field + "': ";
  const std::string& message = status.message();
  if (status.code() != code) {
    return ::testing::AssertionFailure()
           << "status code " << static_cast<int>(status.code()) << ", expected "
           << static_cast<int>(code) << ": " << message;
  }
  if (message.rfind(prefix, 0) != 0) {
    return ::testing::AssertionFailure()
           << "message '" << message << "' does not start with '" << prefix << "'";
  }
  if (message.find('\n') != std::string::npos || message.size() <= prefix.size()) {
    return ::testing::AssertionFailure() << "not a one-line explanation: '" << message << "'";
  }
  return ::testing::AssertionSuccess() << message;
}

}  // namespace fleetloc::io::testing
