// The interior Gaussian blur equals OpenCV's away from the border, for the kernels the tracker
// uses.
#include "imaging/gaussian_blur.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::imaging {
namespace {

cv::Mat GravelFloat() {
  cv::Mat f;
  cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE)
      .convertTo(f, CV_32F, 1.0 / 255);
  return f;
}

TEST(GaussianBlurInterior, EqualsOpenCvsBlurCroppedByTheRadius) {
  const cv::Mat gravel = GravelFloat();
  ASSERT_FALSE(gravel.empty());
  struct Case {
    cv::Rect rect;
    double sigma;
    int radius;
  };
  // Widths that leave 16-, 8- and 1-pixel remainders for the vector loops; every kernel size with
  // its own unrolled loop (3–17 taps) and one without (19); radius 0 is a copy.
  for (const Case& c : {Case{{10, 20, 200, 150}, 1.55, 5}, Case{{0, 0, 37, 29}, 0.5, 2},
                        Case{{50, 40, 33, 64}, 2.5, 8}, Case{{5, 5, 20, 20}, 1.0, 0},
                        Case{{3, 7, 45, 31}, 0.4, 1}, Case{{60, 60, 58, 40}, 1.0, 3},
                        Case{{80, 30, 41, 50}, 1.4, 4}, Case{{20, 90, 63, 44}, 2.0, 6},
                        Case{{70, 10, 50, 52}, 2.3, 7}, Case{{40, 40, 70, 60}, 3.0, 9}}) {
    const cv::Mat src = gravel(c.rect);
    cv::Mat reference;
    const int k = 2 * c.radius + 1;
    cv::GaussianBlur(src, reference, {k, k}, c.sigma, c.sigma, cv::BORDER_REPLICATE);
    const cv::Rect interior(c.radius, c.radius, src.cols - 2 * c.radius, src.rows - 2 * c.radius);
    const cv::Mat blurred = GaussianBlurInterior(src, c.sigma, c.radius);
    ASSERT_EQ(blurred.size(), interior.size());
    EXPECT_LT(cv::norm(blurred, reference(interior), cv::NORM_INF), 2e-6)
        << "sigma " << c.sigma << " radius " << c.radius;
  }
}

TEST(GaussianBlurInterior, RefusesAnImageNoLargerThanTheKernel) {
  const cv::Mat small(10, 30, CV_32F, cv::Scalar(1.0f));
  EXPECT_THROW(GaussianBlurInterior(small, 1.5, 5), cv::Exception);
  EXPECT_THROW(GaussianBlurInterior(cv::Mat(30, 30, CV_8U), 1.5, 5), cv::Exception);
}

}  // namespace
}  // namespace fleetloc::imaging
