// A small network of "hosts" on this machine for multi-host tests: one network namespace per
// host, each with an `eth0` (veth) at its own 10.10.0.x/24 address on a bridge that lives in a
// namespace of its own (the machine's own networking is never touched), programs started inside
// a host, and packet loss and delay between the hosts: `tc netem` on a host's link where the
// kernel has netem, else netns_switch (a userspace switch doing what netem does) in place of the
// bridge. Needs root (CAP_NET_ADMIN);
// Create() answers NotFound when this machine cannot have namespaces (a test skips then) and
// Internal when building the network failed.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "daemon_process.h"

namespace fleetloc::testing {

class NetnsLab {
 public:
  // `hosts`: name → address (10.10.0.x). Names become namespace names `<prefix>-<name>`.
  static Result<std::unique_ptr<NetnsLab>> Create(const std::map<std::string, std::string>& hosts) {
    if (::geteuid() != 0) return NotFound("network namespaces need root");
    std::unique_ptr<NetnsLab> lab(new NetnsLab("fl" + std::to_string(::getpid() % 100000)));
    const std::string net = lab->Namespace("net");
    if (!lab->Run("ip netns add " + net)) return NotFound("'ip netns add' failed here");
    lab->namespaces_.push_back(net);
    bool ok = lab->Run("ip netns exec " + net + " ip link add br0 type bridge") &&
              lab->Run("ip netns exec " + net + " ip link set br0 up");
    for (const auto& [name, address] : hosts) ok = ok && lab->AddHost(name, address);
    if (!ok) return Internal("could not build the namespace network (see the test log)");
    return lab;
  }
  // Programs started in the lab must be stopped before it goes (declare the lab first).
  ~NetnsLab() {
    if (switch_) switch_->Stop(SIGTERM);
    for (const std::string& ns : namespaces_) Run("ip netns del " + ns);
  }

  // Starts build/bin/`program` inside `host`.
  runtime::ChildProcess Start(const std::string& host, const std::string& program,
                              const std::vector<std::string>& args, const std::string& log) {
    std::vector<std::string> all{"netns", "exec", Namespace(host),
                                 std::string(FLEETLOC_BINARY_DIR "/bin/") + program};
    all.insert(all.end(), args.begin(), args.end());
    auto child = runtime::ChildProcess::Start(kIp, all, log);
    if (!child.ok()) {
      ADD_FAILURE() << child.status().message();
      std::abort();
    }
    return std::move(child).value();
  }
  // Runs a shell `command` inside `host`; its standard output (empty on failure).
  std::string Capture(const std::string& host, const std::string& command) const {
    std::string out;
    FILE* pipe =
        ::popen(("ip netns exec " + Namespace(host) + " " + command + " 2>/dev/null").c_str(), "r");
    if (pipe == nullptr) return out;
    std::array<char, 4096> buffer{};
    size_t n = 0;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
      out.append(buffer.data(), n);
    return ::pclose(pipe) == 0 ? out : std::string();
  }
  // The IP counter `name` of `host` (a column of the "Ip:" lines of its /proc/net/snmp, e.g.
  // "FragCreates"); -1 when it cannot be read.
  long long IpCounter(const std::string& host, const std::string& name) const {
    std::istringstream snmp(Capture(host, "cat /proc/net/snmp"));
    std::string header, values;
    for (std::string line; std::getline(snmp, line);) {
      if (line.rfind("Ip: ", 0) != 0) continue;
      (header.empty() ? header : values) = line;
    }
    std::istringstream names(header), numbers(values);
    for (std::string n, v; names >> n && numbers >> v;) {
      if (n == name) return std::stoll(v);
    }
    return -1;
  }
  // Packet loss and delay on everything `host` sends (`spec`: tc netem parameters, e.g.
  // "delay 30ms 10ms loss 3%"); false where the kernel has no netem (see Shape).
  bool Netem(const std::string& host, const std::string& spec) {
    return Shape(host, "netem " + spec);
  }
  // Any root qdisc on `host`'s link (e.g. "tbf rate 20mbit burst 32kb latency 20ms").
  bool Shape(const std::string& host, const std::string& qdisc) {
    return Run("ip netns exec " + Namespace(host) + " tc qdisc replace dev eth0 root " + qdisc);
  }
  // Replaces the bridge with build/bin/netns_switch, which forwards every frame between two hosts
  // `delay_ms` ± `jitter_ms` late and loses it with probability `loss`, as netem on each link
  // would; it writes its counts (netns_switch.cpp) to `stats` every second. For a kernel without
  // netem.
  bool ImpairWithSwitch(double delay_ms, double jitter_ms, double loss, const std::string& stats,
                        const std::string& log) {
    const std::string net = Namespace("net");
    std::vector<std::string> args{"netns",       "exec",
                                  net,           FLEETLOC_BINARY_DIR "/bin/netns_switch",
                                  "--delay-ms",  std::to_string(delay_ms),
                                  "--jitter-ms", std::to_string(jitter_ms),
                                  "--loss",      std::to_string(loss),
                                  "--stats",     stats};
    for (const std::string& peer : peers_) {
      if (!Run("ip netns exec " + net + " ip link set " + peer + " nomaster")) return false;
      args.push_back(peer);
    }
    auto child = runtime::ChildProcess::Start(kIp, args, log);
    if (!child.ok()) return false;
    switch_.emplace(std::move(child).value());
    return true;
  }
  // Whether this kernel has the netem qdisc (some container kernels ship without it).
  bool NetemAvailable() {
    const std::string host = hosts_.front();
    const bool ok = Netem(host, "delay 1ms");
    if (ok) Run("ip netns exec " + Namespace(host) + " tc qdisc del dev eth0 root");
    return ok;
  }

 private:
  static constexpr const char* kIp = "/usr/sbin/ip";
  explicit NetnsLab(std::string prefix) : prefix_(std::move(prefix)) {}

  std::string Namespace(const std::string& host) const { return prefix_ + "-" + host; }
  static bool Run(const std::string& command) {
    const int status = std::system((command + " >/dev/null 2>&1").c_str());
    if (status != 0) std::fprintf(stderr, "netns lab: '%s' failed (%d)\n", command.c_str(), status);
    return status == 0;
  }
  bool AddHost(const std::string& name, const std::string& address) {
    const std::string ns = Namespace(name), net = Namespace("net"),
                      in = "ip netns exec " + ns + " ";
    const std::string peer =
        "v" + std::to_string(namespaces_.size()) + "-" + prefix_;  // <= 15 chars
    if (!Run("ip netns add " + ns)) return false;
    namespaces_.push_back(ns);
    hosts_.push_back(name);
    peers_.push_back(peer);
    return Run("ip link add eth0 netns " + ns + " type veth peer name " + peer + " netns " + net) &&
           Run("ip netns exec " + net + " ip link set " + peer + " master br0 up") &&
           Run(in + "ip addr add " + address + "/24 dev eth0") && Run(in + "ip link set eth0 up") &&
           Run(in + "ip link set lo up");
  }

  std::string prefix_;
  std::vector<std::string> namespaces_;
  std::vector<std::string> hosts_;
  std::vector<std::string> peers_;  // each host link's end in the "net" namespace
  std::optional<runtime::ChildProcess> switch_;
};

}  // namespace fleetloc::testing
