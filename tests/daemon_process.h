// Starts a fleetloc daemon (build/bin/<name>) as a child process for integration and fault tests,
// with its stderr in a log file, and stops it with a signal, returning its exit status.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fcntl.h>
#include <string>
#include <thread>
#include <vector>

namespace fleetloc::testing {

class DaemonProcess {
 public:
  // Runs FLEETLOC_BINARY_DIR/bin/<program> with `args`; stdout and stderr go to `log_path`.
  DaemonProcess(const std::string& program, const std::vector<std::string>& args,
                const std::string& log_path) {
    const std::string path = std::string(FLEETLOC_BINARY_DIR "/bin/") + program;
    pid_ = ::fork();
    if (pid_ == 0) {
      const int log = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(log, 1), ::dup2(log, 2);
      std::vector<char*> argv{const_cast<char*>(path.c_str())};
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(path.c_str(), argv.data());
      ::_exit(127);
    }
  }
  ~DaemonProcess() {
    if (running()) Stop(SIGKILL);
  }
  DaemonProcess(const DaemonProcess&) = delete;
  DaemonProcess& operator=(const DaemonProcess&) = delete;

  bool running() {
    if (pid_ <= 0) return false;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      pid_ = -1;
      return false;
    }
    return true;
  }

  // Sends `signal` and waits up to `limit` for the exit; returns the exit status (128 + signal
  // if killed by one), or -1 if it did not exit in time (it is then killed).
  int Stop(int signal = SIGTERM, std::chrono::seconds limit = std::chrono::seconds(15)) {
    if (!running()) return exit_status_;
    ::kill(pid_, signal);
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      if (!running()) return exit_status_;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
    return -1;
  }

 private:
  pid_t pid_ = -1;
  int exit_status_ = -1;
};

}  // namespace fleetloc::testing
