// Change detection on a real floor: the same floor (with camera noise) is unchanged, a pasted
// marking and an unmapped area are found, in the right proportion.
#include "mapping/change_detection.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "mapping/changed_floor_scene.h"

namespace fleetloc::mapping {
namespace {

TEST(ChangeDetection, FindsTheChangedAndTheUnmappedBlocks) {
  testing::ChangedFloorScene scene;
  const cv::Rect frame_rect(384, 320, 256, 192);  // 4 × 3 blocks of 64 px; the change is inside
  cv::Mat noisy = scene.new_floor(frame_rect).clone();
  cv::Mat noise(noisy.size(), CV_8SC1);
  cv::randn(noise, 0, 3);
  cv::add(noisy, noise, noisy, cv::noArray(), CV_8U);
  const ChangeReport same = CompareWithMosaic(noisy, scene.new_floor(frame_rect));
  EXPECT_EQ(same.blocks, 12);
  EXPECT_EQ(same.changed, 0);
  const ChangeReport changed = CompareWithMosaic(noisy, scene.old_floor(frame_rect));
  // The 120 × 90 px change at (430, 380) fully covers block (1, 1) and part of its neighbours.
  EXPECT_GE(changed.changed, 1);
  EXPECT_LE(changed.changed, 6);
  cv::Mat half_mapped = scene.new_floor(frame_rect).clone();
  half_mapped(cv::Rect(0, 0, 128, 192)).setTo(0);
  const ChangeReport unmapped = CompareWithMosaic(noisy, half_mapped);
  EXPECT_EQ(unmapped.unmapped, 6);
  EXPECT_NEAR(unmapped.changed_fraction(), 0.5, 1e-9);
}

}  // namespace
}  // namespace fleetloc::mapping
