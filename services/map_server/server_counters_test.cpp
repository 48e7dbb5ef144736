// Service counters: named, thread-safe, rejected inputs summed, last error kept.
#include "map_server/server_counters.h"

#include <gtest/gtest.h>

#include <thread>

namespace fleetloc::map_server {
namespace {

TEST(ServerCounters, CountsFromManyThreadsAndKeepsTheLastError) {
  ServerCounters counters({"served", "rejected_a", "rejected_b"});
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 1000; ++i) counters.Add("served");
    });
  }
  for (auto& thread : threads) thread.join();
  counters.Reject("rejected_a", "first");
  counters.Reject("rejected_b", "second");
  EXPECT_EQ(counters.Get("served"), 4000u);
  EXPECT_EQ(counters.TotalRejected(), 2u);
  EXPECT_EQ(counters.last_error(), "second");
  const auto snapshot = counters.Snapshot();
  ASSERT_EQ(snapshot.size(), 3u);
  EXPECT_EQ(snapshot[0].first, "served");
}

}  // namespace
}  // namespace fleetloc::map_server
