// netns_switch: the multi-host tests' Ethernet switch with netem's impairments, for kernels built
// without the netem qdisc (sch_netem; container kernels often lack it, this machine's among them,
// and no library or tool here can delay packets in its place). It runs inside the lab's network
// namespace (NetnsLab::ImpairWithSwitch), opens a raw packet socket on each host link's peer end,
// and forwards every frame between them as a learning switch does — dropping each frame it would
// send on a link with probability --loss, delivering the rest --delay-ms ± --jitter-ms later
// (uniform jitter, so frames may be reordered, as with netem's default) — with netem's default
// queue limit of 1000 frames per link. Every second, and on SIGTERM, it writes its counts as JSON
// to --stats.
//   netns_switch --delay-ms 20 --jitter-ms 5 --loss 0.02 --stats FILE [--seed N] IFACE...
// Exit status: 0 after SIGINT/SIGTERM, 2 on bad arguments, 1 when a link cannot be opened.
#include <arpa/inet.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <queue>
#include <random>
#include <string>
#include <vector>

#include "runtime/stop_signal.h"

namespace {

using Clock = std::chrono::steady_clock;
using Mac = std::array<uint8_t, 6>;

struct Impairment {
  double delay_ms = 0;
  double jitter_ms = 0;
  double loss = 0;
};

struct Counts {
  long long received = 0;     // frames the hosts sent into the switch
  long long forwarded = 0;    // copies delivered to a link
  long long lost = 0;         // copies dropped by --loss
  long long overflowed = 0;   // copies dropped because a link's queue was full
  long long send_errors = 0;  // copies the kernel refused (e.g. larger than the link MTU)
  double delay_ms_total = 0;  // time forwarded copies spent in the switch, for the mean

  nlohmann::json ToJson() const {
    return {
        {"received", received},
        {"forwarded", forwarded},
        {"lost", lost},
        {"overflowed", overflowed},
        {"send_errors", send_errors},
        {"mean_delay_ms", forwarded > 0 ? delay_ms_total / forwarded : 0.0},
        {"loss_fraction", forwarded + lost > 0 ? double(lost) / double(forwarded + lost) : 0.0}};
  }
};

struct Pending {
  Clock::time_point due;
  uint64_t order;  // ties keep arrival order
  size_t link;
  Clock::time_point received;
  std::vector<uint8_t> frame;
  bool operator>(const Pending& other) const {
    return due != other.due ? due > other.due : order > other.order;
  }
};

// Each frame read or written on a link starts with a virtio_net_hdr (PACKET_VNET_HDR) that is
// passed on as it came: a host's UDP checksums are left for the receiver to trust (veth offload,
// CHECKSUM_PARTIAL), and a frame forwarded without its header would arrive with a checksum never
// filled in and be dropped.
// sizeof(struct virtio_net_hdr); <linux/virtio_net.h> itself does not compile as C++.
constexpr size_t kVnetHeader = 10;

// A raw socket on one link, bound to it, seeing only frames arriving from its host.
int OpenLink(const std::string& name) {
  const unsigned index = if_nametoindex(name.c_str());
  if (index == 0) return -1;
  const int fd = socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK, htons(ETH_P_ALL));
  if (fd < 0) return -1;
  sockaddr_ll address{};
  address.sll_family = AF_PACKET;
  address.sll_protocol = htons(ETH_P_ALL);
  address.sll_ifindex = static_cast<int>(index);
  const int one = 1, buffer = 4 << 20;
  packet_mreq promiscuous{};
  promiscuous.mr_ifindex = static_cast<int>(index);
  promiscuous.mr_type = PACKET_MR_PROMISC;
  if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      setsockopt(fd, SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof one) != 0 ||
      setsockopt(fd, SOL_PACKET, PACKET_VNET_HDR, &one, sizeof one) != 0 ||
      setsockopt(fd, SOL_PACKET, PACKET_ADD_MEMBERSHIP, &promiscuous, sizeof promiscuous) != 0) {
    close(fd);
    return -1;
  }
  setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
  setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &buffer, sizeof buffer);
  return fd;
}

class Switch {
 public:
  Switch(std::vector<int> links, Impairment impairment, uint64_t seed)
      : links_(std::move(links)),
        impairment_(impairment),
        queued_(links_.size(), 0),
        random_(seed) {}

  void Run(const std::atomic<bool>& stop, const std::string& stats_path) {
    std::vector<pollfd> polls;
    for (int fd : links_) polls.push_back({fd, POLLIN, 0});
    auto next_stats = Clock::now();
    while (!stop) {
      const int wait_ms = WaitMs();
      if (poll(polls.data(), polls.size(), wait_ms) < 0 && errno != EINTR) break;
      for (size_t link = 0; link < polls.size(); ++link) {
        if (polls[link].revents & POLLIN) Receive(link);
      }
      Deliver();
      if (Clock::now() >= next_stats) {
        WriteStats(stats_path);
        next_stats += std::chrono::seconds(1);
      }
    }
    WriteStats(stats_path);
  }

 private:
  static constexpr size_t kQueueLimit = 1000;  // frames per link, netem's default limit

  int WaitMs() const {
    if (pending_.empty()) return 200;
    const auto left = pending_.top().due - Clock::now();
    return std::max(0,
                    static_cast<int>(std::chrono::ceil<std::chrono::milliseconds>(left).count()));
  }

  void Receive(size_t from) {
    std::array<uint8_t, 65536> buffer{};
    for (;;) {
      const ssize_t n = recv(links_[from], buffer.data(), buffer.size(), 0);
      if (n < static_cast<ssize_t>(kVnetHeader + ETH_HLEN)) return;  // EAGAIN (drained), or a runt
      ++counts_.received;
      Mac source, destination;
      std::memcpy(destination.data(), buffer.data() + kVnetHeader, 6);
      std::memcpy(source.data(), buffer.data() + kVnetHeader + 6, 6);
      where_[source] = from;
      const auto known = where_.find(destination);
      const bool flood = (destination[0] & 1) != 0 || known == where_.end();
      for (size_t to = 0; to < links_.size(); ++to) {
        if (to == from || (!flood && known->second != to)) continue;
        Enqueue(to, std::vector<uint8_t>(buffer.begin(), buffer.begin() + n));
      }
    }
  }

  void Enqueue(size_t link, std::vector<uint8_t> frame) {
    if (uniform_(random_) < impairment_.loss) {
      ++counts_.lost;
      return;
    }
    if (queued_[link] >= kQueueLimit) {
      ++counts_.overflowed;
      return;
    }
    const double delay_ms =
        std::max(0.0, impairment_.delay_ms + impairment_.jitter_ms * (2 * uniform_(random_) - 1));
    ++queued_[link];
    const auto now = Clock::now();
    pending_.push({now + std::chrono::duration_cast<Clock::duration>(
                             std::chrono::duration<double, std::milli>(delay_ms)),
                   next_order_++, link, now, std::move(frame)});
  }

  void Deliver() {
    const auto now = Clock::now();
    while (!pending_.empty() && pending_.top().due <= now) {
      const Pending& next = pending_.top();
      --queued_[next.link];
      if (send(links_[next.link], next.frame.data(), next.frame.size(), 0) < 0) {
        ++counts_.send_errors;
      } else {
        ++counts_.forwarded;
        counts_.delay_ms_total +=
            std::chrono::duration<double, std::milli>(now - next.received).count();
      }
      pending_.pop();
    }
  }

  void WriteStats(const std::string& path) const {
    const std::string partial = path + ".part";
    std::ofstream(partial) << counts_.ToJson().dump() << "\n";
    std::error_code ignored;
    std::filesystem::rename(partial, path, ignored);
  }

  std::vector<int> links_;
  Impairment impairment_;
  std::vector<size_t> queued_;  // per link
  std::mt19937_64 random_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::map<Mac, size_t> where_;  // learned: which link a MAC address is behind
  std::priority_queue<Pending, std::vector<Pending>, std::greater<>> pending_;
  uint64_t next_order_ = 0;
  Counts counts_;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"userspace Ethernet switch with netem-style loss and delay"};
  Impairment impairment;
  std::string stats_path;
  uint64_t seed = 1;
  std::vector<std::string> names;
  app.add_option("--delay-ms", impairment.delay_ms)->check(CLI::Range(0.0, 10000.0));
  app.add_option("--jitter-ms", impairment.jitter_ms)->check(CLI::Range(0.0, 10000.0));
  app.add_option("--loss", impairment.loss)->check(CLI::Range(0.0, 1.0));
  app.add_option("--stats", stats_path)->required();
  app.add_option("--seed", seed);
  app.add_option("links", names)->required()->expected(2, 64);
  CLI11_PARSE(app, argc, argv);

  std::vector<int> links;
  for (const std::string& name : names) {
    const int fd = OpenLink(name);
    if (fd < 0) {
      std::fprintf(stderr, "netns_switch: cannot open link %s: %s\n", name.c_str(),
                   std::strerror(errno));
      return 1;
    }
    links.push_back(fd);
  }
  const std::atomic<bool>& stop = fleetloc::runtime::InstallStopSignals();
  std::printf("netns_switch: %zu links, %.1f +- %.1f ms delay, %.1f %% loss\n", links.size(),
              impairment.delay_ms, impairment.jitter_ms, 100 * impairment.loss);
  std::fflush(stdout);
  Switch(links, impairment, seed).Run(stop, stats_path);
  for (int fd : links) close(fd);
  return 0;
}
