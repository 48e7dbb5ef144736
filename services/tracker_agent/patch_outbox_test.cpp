// Patch outbox: sequence numbers never reused across restarts, retries after the delay, resent at
// once after a reboot (a simulated clock jump), removal once every map server keeping a replica
// acknowledged (acknowledgements survive a restart), and a size cap dropping the oldest,
// lowest-quality patches first, counted.
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
  std::string path =
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
    EXPECT_EQ(outbox->Due({"boot-a", 0}, 1, 10)->size(), 2u);  // still sent, for ms-east
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
                            ("outbox_test_" + std::to_string(::getpid()) + ".db"))
                               .string();
  std::filesystem::remove(path);
  {
    auto outbox = std::move(PatchOutbox::Open(path)).value();
    transport::PatchToSend a = Patch(1), b = Patch(2);
    EXPECT_EQ(*outbox->Add(&a), 1u);
    EXPECT_EQ(*outbox->Add(&b), 2u);
    ASSERT_TRUE(*outbox->Acknowledge(2, "ms-1", {"ms-1"}));
    ASSERT_TRUE(outbox->MarkSent(1, {"boot-a", 100.0}).ok());
  }
  auto outbox = std::move(PatchOutbox::Open(path)).value();  // the agent restarted
  EXPECT_EQ(*outbox->Size(), 1);
  transport::PatchToSend c = Patch(3);
  EXPECT_EQ(*outbox->Add(&c), 3u);                     // 2 was used before the restart
  auto due = outbox->Due({"boot-a", 101.0}, 2.0, 10);  // 1 was sent 1 s ago: not yet due
  ASSERT_EQ(due->size(), 1u);
  EXPECT_EQ((*due)[0].sequence, 3u);
  due = outbox->Due({"boot-a", 103.0}, 2.0, 10);
  ASSERT_EQ(due->size(), 2u);
  EXPECT_EQ((*due)[0].sequence, 1u);
  EXPECT_EQ((*due)[0].pose.x, 1.0);
  EXPECT_EQ((*due)[0].png, Patch(1).png);
  EXPECT_EQ((*due)[0].covariance[0], 1e-6);
  std::filesystem::remove(path);
}

TEST(PatchOutbox, AnOutboxWrittenBeforeARebootIsResentRightAfterIt) {
  const std::string path = ScratchOutbox("outbox_reboot");
  {
    auto outbox = std::move(PatchOutbox::Open(path)).value();
    transport::PatchToSend a = Patch(1), b = Patch(2);
    ASSERT_TRUE(outbox->Add(&a).ok());
    ASSERT_TRUE(outbox->Add(&b).ok());
    // Sent after 30 days of uptime, never acknowledged; then the vehicle loses power.
    ASSERT_TRUE(outbox->MarkSent(1, {"boot-a", 30 * 86400.0}).ok());
    ASSERT_TRUE(outbox->MarkSent(2, {"boot-a", 30 * 86400.0}).ok());
    EXPECT_TRUE(outbox->Due({"boot-a", 30 * 86400.0 + 1}, 2.0, 10)->empty());
  }
  // 5 s into the next boot the monotonic clock reads 5 s: both are due at once, not in 30 days.
  auto outbox = std::move(PatchOutbox::Open(path)).value();
  auto due = outbox->Due({"boot-b", 5.0}, 2.0, 10);
  ASSERT_TRUE(due.ok());
  EXPECT_EQ(due->size(), 2u);
  ASSERT_TRUE(outbox->MarkSent(1, {"boot-b", 5.0}).ok());
  due = outbox->Due({"boot-b", 6.0}, 2.0, 10);
  ASSERT_EQ(due->size(), 1u);  // 1 was just sent in this boot; 2 still waits from the last one
  EXPECT_EQ((*due)[0].sequence, 2u);
  // This machine's own clock names a boot.
  EXPECT_FALSE(OutboxNow().boot_id.empty());
  std::filesystem::remove(path);
}

TEST(PatchOutbox, AFullOutboxDropsTheOldestLowestQualityPatchesAndCountsThem) {
  const std::string path = ScratchOutbox("outbox_cap");
  auto outbox = std::move(PatchOutbox::Open(path, {20, 1 << 20})).value();
  for (int i = 1; i <= 20; ++i) {
    transport::PatchToSend p = Patch(i);
    p.quality = i == 1 ? 0.9f : i == 2 ? 0.1f : 0.5f;
    ASSERT_TRUE(outbox->Add(&p).ok());
  }
  EXPECT_EQ(*outbox->Dropped(), 0);
  // Each add beyond 20 drops one of the oldest tenth (the two oldest): the lower quality one.
  for (int i = 21; i <= 23; ++i) {
    transport::PatchToSend p = Patch(i);
    ASSERT_TRUE(outbox->Add(&p).ok());
  }
  EXPECT_EQ(*outbox->Size(), 20);
  EXPECT_EQ(*outbox->Dropped(), 3);
  std::vector<uint64_t> kept;
  const auto due = outbox->Due({"boot-a", 0}, 1, 100);  // kept alive: the loop ranges over it
  for (const auto& p : *due) kept.push_back(p.sequence);
  EXPECT_EQ(kept.front(), 1u);  // the oldest, but of high quality: kept over 2, 3 and 4
  EXPECT_EQ(kept[1], 5u);
  EXPECT_EQ(kept.back(), 23u);
  // A byte cap works alike: 3 patches of 400 KiB in 1 MiB keep 2.
  const std::string bytes_path = ScratchOutbox("outbox_cap_bytes");
  auto small = std::move(PatchOutbox::Open(bytes_path, {100, 1 << 20})).value();
  for (int i = 0; i < 3; ++i) {
    transport::PatchToSend p = Patch(i);
    p.png.assign(400 * 1024, 7);
    ASSERT_TRUE(small->Add(&p).ok());
  }
  EXPECT_EQ(*small->Size(), 2);
  EXPECT_EQ(*small->Dropped(), 1);
  std::filesystem::remove(path);
  std::filesystem::remove(bytes_path);
}

}  // namespace
}  // namespace fleetloc::tracker_agent
