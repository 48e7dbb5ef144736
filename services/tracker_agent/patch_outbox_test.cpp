// Patch outbox: sequence numbers never reused across restarts, retries after the delay, removal
// once every map server keeping a replica acknowledged (acknowledgements survive a restart).
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

std::string ScratchOutbox(const std::string& name) {
  const std::string path =
      (std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".db"))
          .string();
  std::filesystem::remove(path);
  return path;
}

TEST(PatchOutbox, APatchLeavesOnlyWhenEveryReplicaAcknowledgedIt) {
  const std::string path = ScratchOutbox("outbox_replicas");
  const std::vector<std::string> servers = {"ms-east", "ms-west"};
  {
    auto outbox = std::move(PatchOutbox::Open(path)).value();
    transport::PatchToSend a = Patch(1), b = Patch(2);
    ASSERT_TRUE(outbox->Add(&a).ok());
    ASSERT_TRUE(outbox->Add(&b).ok());
    EXPECT_FALSE(*outbox->Acknowledge(1, "ms-west", servers));
    EXPECT_FALSE(*outbox->Acknowledge(1, "ms-west", servers));  // a duplicate answer
    EXPECT_EQ(*outbox->Size(), 2);
    EXPECT_EQ(outbox->Due(0, 1, 10)->size(), 2u);  // still sent, for ms-east
  }
  auto outbox = std::move(PatchOutbox::Open(path)).value();  // the agent restarted
  EXPECT_TRUE(*outbox->Acknowledge(1, "ms-east", servers));  // ms-west's ack was kept
  EXPECT_EQ(*outbox->Size(), 1);
  EXPECT_FALSE(*outbox->Acknowledge(1, "ms-east", servers));  // gone: a late duplicate is harmless
  // A server not (yet) known to the directory still counts for the patch it acknowledged.
  EXPECT_TRUE(*outbox->Acknowledge(2, "ms-solo", {}));
  EXPECT_EQ(*outbox->Size(), 0);
  std::filesystem::remove(path);
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
    ASSERT_TRUE(*outbox->Acknowledge(2, "ms-1", {"ms-1"}));
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
