// ClosestName: typical typos find their command; unrelated words find none.
#include "cli/closest_name.h"

#include <gtest/gtest.h>

namespace fleetloc::cli {
namespace {

const std::vector<std::string> kCommands = {"mosaic", "sim",    "track", "mapmatch",
                                            "reloc",  "status", "remap", "calibrate"};

TEST(ClosestName, TyposFindTheirCommand) {
  EXPECT_EQ(ClosestName("stauts", kCommands), "status");    // transposition
  EXPECT_EQ(ClosestName("trak", kCommands), "track");       // deletion
  EXPECT_EQ(ClosestName("mosaik", kCommands), "mosaic");    // substitution
  EXPECT_EQ(ClosestName("calib", kCommands), "calibrate");  // prefix
  EXPECT_EQ(ClosestName("mapmach", kCommands), "mapmatch");
}

TEST(ClosestName, UnrelatedWordsFindNone) {
  EXPECT_EQ(ClosestName("frobnicate", kCommands), std::nullopt);
  EXPECT_EQ(ClosestName("", kCommands), std::nullopt);
  EXPECT_EQ(ClosestName("xyz", {}), std::nullopt);
}

TEST(EditDistance, CountsEachKindOfEditOnce) {
  EXPECT_EQ(EditDistance("status", "status"), 0);
  EXPECT_EQ(EditDistance("status", "stauts"), 1);
  EXPECT_EQ(EditDistance("remap", "reloc"), 3);
  EXPECT_EQ(EditDistance("", "abc"), 3);
}

}  // namespace
}  // namespace fleetloc::cli
