// Patch outbox: sequence numbers never reused across restarts, retries after the delay, removal
// on acknowledgement.
#include "tracker_agent/patch_outbox.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace fleetloc::tracker_agent {
namespace {

transport::PatchToSend Patch(double x) {
  transport::PatchToSend p;
  p.pose = {x, 2.0, 0.5};
  p.covariance[0] = 1e-6;
  p.quality = 0.7f;
  p.resolution_m = 0.0005;
  p.mosaic_id = "abc";
  p.png = {0x89, 'P', 'N', 'G', 1, 2, 3};
  return p;
}

TEST(PatchOutbox, SurvivesRestartWithoutReusingSequenceNumbersAndRetries) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("outbox_test_" + std::to_string(::getpid()) + ".db")).string();
  std::filesystem::remove(path);
  {
    auto outbox = std::move(PatchOutbox::Open(path)).value();
    transport::PatchToSend a = Patch(1), b = Patch(2);
    EXPECT_EQ(*outbox->Add(&a), 1u);
    EXPECT_EQ(*outbox->Add(&b), 2u);
    ASSERT_TRUE(outbox->Remove(2).ok());  // acknowledged
    ASSERT_TRUE(outbox->MarkSent(1, 100.0).ok());
  }
  auto outbox = std::move(PatchOutbox::Open(path)).value();  // the agent restarted
  EXPECT_EQ(*outbox->Size(), 1);
  transport::PatchToSend c = Patch(3);
  EXPECT_EQ(*outbox->Add(&c), 3u);  // 2 was used before the restart
  auto due = outbox->Due(101.0, 2.0, 10);  // 1 was sent 1 s ago: not yet due
  ASSERT_EQ(due->size(), 1u);
  EXPECT_EQ((*due)[0].sequence, 3u);
  due = outbox->Due(103.0, 2.0, 10);
  ASSERT_EQ(due->size(), 2u);
  EXPECT_EQ((*due)[0].sequence, 1u);
  EXPECT_EQ((*due)[0].pose.x, 1.0);
  EXPECT_EQ((*due)[0].png, Patch(1).png);
  EXPECT_EQ((*due)[0].covariance[0], 1e-6);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace fleetloc::tracker_agent
