// DecideAck: which PatchAck answers end, count for, or leave alone a queued patch.
#include "tracker_agent/patch_acks.h"

#include <gtest/gtest.h>

namespace fleetloc::tracker_agent {
namespace {

transport::ReceivedAck Ack(const std::string& server, fleetloc_PatchAckStatus status) {
  transport::ReceivedAck ack;
  ack.sequence = 7;
  ack.server_id = server;
  ack.status = status;
  return ack;
}

const std::vector<std::string> kSplit = {"ms-east", "ms-west"};

TEST(DecideAck, AStoredOrDuplicateAnswerCountsForItsReplica) {
  for (fleetloc_PatchAckStatus status : {fleetloc_PATCH_STORED, fleetloc_PATCH_DUPLICATE}) {
    const AckDecision d = DecideAck(Ack("ms-west", status), kSplit);
    EXPECT_EQ(d.action, AckAction::kCount);
    EXPECT_EQ(d.server, "ms-west");
  }
}

TEST(DecideAck, ARejectionByAReplicaDropsThePatch) {
  const AckDecision d = DecideAck(Ack("ms-east", fleetloc_PATCH_REJECTED), kSplit);
  EXPECT_EQ(d.action, AckAction::kDrop);
  EXPECT_EQ(d.server, "ms-east");
}

TEST(DecideAck, AnswersFromServersOfAnotherMosaicAreIgnored) {
  EXPECT_EQ(DecideAck(Ack("ms-other", fleetloc_PATCH_REJECTED), kSplit).action, AckAction::kIgnore);
  EXPECT_EQ(DecideAck(Ack("ms-other", fleetloc_PATCH_STORED), kSplit).action, AckAction::kIgnore);
  EXPECT_EQ(DecideAck(Ack("ms-west", fleetloc_PATCH_STORED), {}).action, AckAction::kIgnore);
}

TEST(DecideAck, AnUnnamedServerIsTheOnlyReplicaOrIgnored) {
  const AckDecision single = DecideAck(Ack("", fleetloc_PATCH_STORED), {"ms-1"});
  EXPECT_EQ(single.action, AckAction::kCount);
  EXPECT_EQ(single.server, "ms-1");
  EXPECT_EQ(DecideAck(Ack("", fleetloc_PATCH_STORED), kSplit).action, AckAction::kIgnore);
  EXPECT_EQ(DecideAck(Ack("", fleetloc_PATCH_REJECTED), kSplit).action, AckAction::kIgnore);
}

}  // namespace
}  // namespace fleetloc::tracker_agent
