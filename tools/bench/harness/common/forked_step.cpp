// fork + pipe + wait4.
#include "harness/common/forked_step.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace fleetloc::bench {
namespace {

// Writes all of `text` to `fd`, retrying short writes; false on error.
bool WriteAll(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

std::string ReadAll(int fd) {
  std::string text;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return text;
    text.append(buffer, static_cast<std::size_t>(n));
  }
}

// In the child: runs the work, sends "<status code byte><output or message>", exits.
[[noreturn]] void RunChild(int fd, const std::function<Result<std::string>()>& work) {
  Result<std::string> result = work();
  const Status status = result.ok() ? Status::Ok() : result.status();
  const std::string payload = result.ok() ? *result : status.message();
  const bool sent = WriteAll(fd, std::string(1, static_cast<char>(status.code())) + payload);
  std::fflush(nullptr);
  ::_exit(sent ? status.ExitCode() : 1);
}

double Seconds(const timeval& t) { return t.tv_sec + t.tv_usec * 1e-6; }

}  // namespace

Result<ChildRun> RunInChild(const std::function<Result<std::string>()>& work) {
  int fds[2];
  if (::pipe(fds) != 0) return Internal(std::string("pipe: ") + std::strerror(errno));
  std::fflush(nullptr);  // nothing buffered may be written twice
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return Internal(std::string("fork: ") + std::strerror(errno));
  }
  if (pid == 0) {
    ::close(fds[0]);
    RunChild(fds[1], work);
  }
  ::close(fds[1]);
  const std::string reply = ReadAll(fds[0]);  // until the child exits: the pipe never fills
  ::close(fds[0]);
  int wait_status = 0;
  rusage usage{};
  while (::wait4(pid, &wait_status, 0, &usage) < 0 && errno == EINTR) {
  }
  ChildRun run;
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (reply.empty() || !WIFEXITED(wait_status)) {
    return Internal("benchmark child process died without a result (status " +
                    std::to_string(wait_status) + ")");
  }
  const auto code = static_cast<StatusCode>(reply[0]);
  if (code != StatusCode::kOk) return Status(code, reply.substr(1));
  run.output = reply.substr(1);
  run.user_s = Seconds(usage.ru_utime);
  run.system_s = Seconds(usage.ru_stime);
  run.peak_rss_bytes = static_cast<long long>(usage.ru_maxrss) * 1024;  // Linux reports KiB
  return run;
}

long long ResidentBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    long long kib = 0;
    if (std::sscanf(line.c_str(), "VmRSS: %lld kB", &kib) == 1) return kib * 1024;
  }
  return 0;
}

}  // namespace fleetloc::bench
