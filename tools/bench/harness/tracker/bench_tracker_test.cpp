// The tracker benchmarks' timing of repeated replays: each frame's time the least of the replays,
// and only when every replay gave the same poses.
#include "harness/tracker/bench_tracker.h"

#include <gtest/gtest.h>

#include <limits>

namespace fleetloc::bench {
namespace {

replay::ReplayResult Replay(std::vector<double> ms, double last_x) {
  replay::ReplayResult r;
  for (size_t i = 0; i < ms.size(); ++i) {
    run_io::PoseRecord p;
    p.t = 0.2 * static_cast<double>(i);
    p.pose = {0.01 * static_cast<double>(i), 0.0, 0.1};
    p.status = "tracking";
    r.poses.push_back(p);
  }
  r.poses.back().pose.x = last_x;
  r.poses.back().status = "lost";
  r.cycle_ms = std::move(ms);
  return r;
}

TEST(TakeLeastTimes, KeepsEachFramesLeastTime) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  replay::ReplayResult first = Replay({2.0, 5.0, 1.5}, nan);
  ASSERT_TRUE(TakeLeastTimes(Replay({2.5, 1.8, 1.5}, nan), &first).ok());
  ASSERT_TRUE(TakeLeastTimes(Replay({1.9, 3.0, 4.0}, nan), &first).ok());
  EXPECT_EQ(first.cycle_ms, (std::vector<double>{1.9, 1.8, 1.5}));
}

TEST(TakeLeastTimes, RefusesAReplayWithOtherPosesOrFrames) {
  replay::ReplayResult first = Replay({2.0, 5.0, 1.5}, 0.5);
  const Status moved = TakeLeastTimes(Replay({1.0, 1.0, 1.0}, 0.5 + 1e-12), &first);
  EXPECT_EQ(moved.code(), StatusCode::kInternal);
  EXPECT_NE(moved.message().find("not deterministic"), std::string::npos);
  replay::ReplayResult other_status = Replay({1.0, 1.0, 1.0}, 0.5);
  other_status.poses[1].status = "coasting";
  EXPECT_FALSE(TakeLeastTimes(other_status, &first).ok());
  EXPECT_FALSE(TakeLeastTimes(Replay({1.0, 1.0}, 0.5), &first).ok());
  EXPECT_EQ(first.cycle_ms, (std::vector<double>{2.0, 5.0, 1.5}));  // untouched
}

}  // namespace
}  // namespace fleetloc::bench
