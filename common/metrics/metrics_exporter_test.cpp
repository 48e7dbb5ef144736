// MetricsExporter over real sockets: a scrape returns the published snapshot in the text format;
// clients that connect and send nothing cannot keep a scrape out for longer than the request
// timeout; a port in use is an error naming the address.
#include "metrics/metrics_exporter.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "io/loopback_socket.h"
#include "metrics/exposition.h"
#include "metrics/metric_families.h"

namespace fleetloc::metrics {
namespace {

int Connect(int port) { return io::ConnectLoopback(port); }

// GET `path`; the whole answer ("" if none within `timeout_s`).
std::string Get(int port, const std::string& path, double timeout_s = 10) {
  const int fd = Connect(port);
  if (fd < 0) return "";
  const std::string request =
      "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  (void)::write(fd, request.data(), request.size());
  std::string answer;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  char buffer[4096];
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) break;
    answer.append(buffer, static_cast<size_t>(n));
  }
  ::close(fd);
  return answer;
}

std::string Body(const std::string& answer) {
  const size_t split = answer.find("\r\n\r\n");
  return split == std::string::npos ? "" : answer.substr(split + 4);
}

std::vector<prometheus::MetricFamily> SomeFamilies(double value) {
  FamilyBuilder b("fleetloc_test_", {{"service_id", "t-1"}});
  b.Counter("frames", "frames seen", value);
  b.Gauge("outbox_patches", "patches waiting", 3);
  return b.Take();
}

MetricsOptions Loopback() {
  MetricsOptions o;
  o.enabled = true;
  o.request_timeout_s = 1.0;
  return o;
}

TEST(MetricsExporter, ServesThePublishedSnapshotInTheTextFormat) {
  const std::string port_file = ::testing::TempDir() + "/metrics_port";
  MetricsOptions o = Loopback();
  o.port_file = port_file;
  Result<std::unique_ptr<MetricsExporter>> exporter = MetricsExporter::Start(o);
  ASSERT_TRUE(exporter.ok()) << exporter.status().message();
  const int port = (*exporter)->port();
  ASSERT_GT(port, 0);
  int written = 0;
  std::ifstream(port_file) >> written;
  EXPECT_EQ(written, port);
  (*exporter)->Publish(SomeFamilies(5));
  std::string answer = Get(port, "/metrics");
  ASSERT_NE(answer.find("200 OK"), std::string::npos) << answer;
  Result<Exposition> e = ParseExposition(Body(answer));
  ASSERT_TRUE(e.ok()) << e.status().message() << "\n" << answer;
  EXPECT_EQ(*e->Value("fleetloc_test_frames_total", {{"service_id", "t-1"}}), 5);
  (*exporter)->Publish(SomeFamilies(6));
  e = ParseExposition(Body(Get(port, "/metrics")));
  ASSERT_TRUE(e.ok());
  EXPECT_EQ(*e->Value("fleetloc_test_frames_total"), 6);
  EXPECT_EQ(Get(port, "/other").find("200 OK"), std::string::npos);
}

TEST(MetricsExporter, SilentClientsDelayAScrapeAtMostTheRequestTimeout) {
  MetricsOptions o = Loopback();
  o.threads = 1;
  Result<std::unique_ptr<MetricsExporter>> exporter = MetricsExporter::Start(o);
  ASSERT_TRUE(exporter.ok()) << exporter.status().message();
  (*exporter)->Publish(SomeFamilies(1));
  std::vector<int> silent;
  for (int i = 0; i < 4; ++i) silent.push_back(Connect((*exporter)->port()));
  // The service keeps publishing meanwhile without waiting.
  const auto publish_start = std::chrono::steady_clock::now();
  for (int i = 0; i < 100; ++i) (*exporter)->Publish(SomeFamilies(i));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - publish_start).count(),
            0.5);
  const auto start = std::chrono::steady_clock::now();
  const std::string answer = Get((*exporter)->port(), "/metrics", 15);
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (int fd : silent) ::close(fd);
  ASSERT_NE(answer.find("200 OK"), std::string::npos);
  EXPECT_TRUE(ParseExposition(Body(answer)).ok());
  // Four silent clients before it on one thread, each cut off after 1 s.
  EXPECT_LT(took, 4 * o.request_timeout_s + 2.0);
}

TEST(MetricsExporter, APortInUseIsAnErrorNamingTheAddress) {
  Result<std::unique_ptr<MetricsExporter>> first = MetricsExporter::Start(Loopback());
  ASSERT_TRUE(first.ok());
  MetricsOptions o = Loopback();
  o.port = (*first)->port();
  Result<std::unique_ptr<MetricsExporter>> second = MetricsExporter::Start(o);
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.status().message().find("127.0.0.1:" + std::to_string(o.port)),
            std::string::npos)
      << second.status().message();
}

}  // namespace
}  // namespace fleetloc::metrics
