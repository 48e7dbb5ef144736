// EvenDftSize: even, at least the length asked for, and one of OpenCV's optimal lengths.
#include "imaging/dft_size.h"

#include <gtest/gtest.h>

namespace fleetloc::imaging {
namespace {

TEST(EvenDftSize, IsTheSmallestEvenOptimalLengthAtLeastTheOneAskedFor) {
  EXPECT_EQ(EvenDftSize(366), 384);  // getOptimalDFTSize: 375
  EXPECT_EQ(EvenDftSize(622), 640);  // 625
  EXPECT_EQ(EvenDftSize(700), 720);  // 720, even already
  EXPECT_EQ(EvenDftSize(1), 2);
  for (int n = 1; n <= 3000; ++n) {
    const int size = EvenDftSize(n);
    ASSERT_GE(size, n);
    ASSERT_EQ(size % 2, 0) << n;
    ASSERT_EQ(cv::getOptimalDFTSize(size), size) << n;
    for (int smaller = n; smaller < size; ++smaller) {
      ASSERT_TRUE(smaller % 2 != 0 || cv::getOptimalDFTSize(smaller) != smaller) << n;
    }
  }
  EXPECT_EQ(EvenDftSize(cv::Size(622, 366)), cv::Size(640, 384));
}

}  // namespace
}  // namespace fleetloc::imaging
