// The stress bench's verdict on one cell: issue 15's targets, and the comparison with ECC only
// where ECC measured something.
#include "harness/stress/run_stress_bench.h"

#include <gtest/gtest.h>

namespace fleetloc::bench {
namespace {

// `median_locked_ms` < 0: the median over the locked frames is the median over all.
BenchRow Row(const std::string& label, double lock_rate, double camera_rms_px, double median_ms,
             double median_locked_ms = -1.0) {
  BenchRow row;
  row.replay.label = label;
  row.summary = {{"lock_rate", lock_rate},
                 {"error", {{"false_locks", 0}, {"camera_position_rms_px", camera_rms_px}}},
                 {"ms_per_frame",
                  {{"median", median_ms},
                   {"median_locked", median_locked_ms < 0 ? median_ms : median_locked_ms}}}};
  return row;
}

TEST(JudgeStressCell, PassesWithinTheTargetsAndBelowEcc) {
  const FrameSize vga{640, 480};
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.05, 1.5), Row("ecc", 1.0, 0.06, 40)},
                            "worn_asphalt", vga),
            "PASS");
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.12, 3.5)}, "plain_concrete", vga), "PASS");
  EXPECT_EQ(JudgeStressCell({Row("ecc", 1.0, 0.06, 40)}, "epoxy", vga), "n/a");
}

TEST(JudgeStressCell, NamesEveryMissedTarget) {
  const FrameSize vga{640, 480};
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 0.99, 0.12, 2.5), Row("ecc", 1.0, 0.03, 40)},
                            "worn_asphalt", vga),
            "MISS: lock, rms, rms vs ecc, time");
  // At 640×480 at most a tenth of ECC's median time where ECC locked frames.
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.05, 1.5), Row("ecc", 1.0, 0.06, 12)},
                            "worn_asphalt", vga),
            "MISS: time vs ecc");
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.05, 1.5), Row("ecc", 0.0, 0.0, 2)},
                            "worn_asphalt", vga),
            "PASS");
  // Against ECC's time on the frames it registered, not on those it gave up on within
  // milliseconds.
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.05, 1.5), Row("ecc", 0.25, 0.06, 2.5, 90)},
                            "worn_asphalt", vga),
            "PASS");
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.05, 1.5), Row("ecc", 0.25, 0.06, 90, 12)},
                            "worn_asphalt", vga),
            "MISS: time vs ecc");
  // Only 640×480 frames are timed.
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.05, 9.0)}, "worn_asphalt", {320, 240}), "PASS");
}

// An ECC that locked no frame reports an RMS of 0 over none: no measurement, no comparison. One
// that locked some is compared, on fleetloc's first N frames when ECC replayed only N.
TEST(JudgeStressCell, ComparesWithEccOnlyWhereEccLockedFrames) {
  const FrameSize small{320, 240};
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.14, 5.4), Row("ecc", 0.0, 0.0, 1.4)},
                            "polished_concrete", small),
            "PASS");
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.14, 5.4), Row("fleetloc@20", 1.0, 0.13, 5.4),
                             Row("ecc", 0.5, 0.12, 1.4)},
                            "polished_concrete", small),
            "MISS: rms vs ecc");
  EXPECT_EQ(JudgeStressCell({Row("fleetloc", 1.0, 0.14, 5.4), Row("fleetloc@20", 1.0, 0.11, 5.4),
                             Row("ecc", 0.5, 0.12, 1.4)},
                            "polished_concrete", small),
            "PASS");
}

}  // namespace
}  // namespace fleetloc::bench
