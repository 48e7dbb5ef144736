// The frame's blur against a sharp view, found on a real photograph (tests/data/gravel.png):
// frames blurred by known Gaussians, with sensor noise and an occluder, normalized like the
// tracker's; the estimate must land on the blur that made them.
#include "tracking/view_blur.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "imaging/normalize.h"

namespace fleetloc::tracking {
namespace {

constexpr int kMargin = 8;  // BlurMarginPx(2.5)

struct Scene {
  cv::Mat photo;  // grey levels as floats
  cv::Rect inner{120, 110, 240, 180};

  Scene() {
    cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE)
        .convertTo(photo, CV_32F);
  }
  // The sharp view over `inner` grown by kMargin + 1, normalized.
  cv::Mat View() const {
    return Normalized(photo, {inner.x - kMargin - 1, inner.y - kMargin - 1,
                              inner.width + 2 * kMargin + 2, inner.height + 2 * kMargin + 2});
  }
  // The frame: the photo blurred by `sigma`, dimmed, noisy, partly covered, normalized.
  cv::Mat Frame(double sigma, cv::RNG& rng) const {
    cv::Mat blurred = photo.clone();
    if (sigma > 0) cv::GaussianBlur(photo, blurred, {0, 0}, sigma);
    cv::Mat noise(blurred.size(), CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 3.0);
    blurred = 0.7 * blurred + 10.0 + noise;
    blurred(cv::Rect(inner.x + 20, inner.y + 30, 60, 40)).setTo(250.0f);
    return Normalized(blurred, {0, 0, blurred.cols, blurred.rows});
  }
  static cv::Mat Normalized(const cv::Mat& image, const cv::Rect& rect) {
    cv::Mat bytes;
    image(rect).convertTo(bytes, CV_8U);
    return imaging::LocalNormalize(bytes, 7);
  }
};

TEST(ViewBlur, FindsTheBlurThatMadeTheFrame) {
  const Scene scene;
  ASSERT_FALSE(scene.photo.empty());
  cv::RNG rng(11);
  for (const double sigma : {0.0, 1.0, 1.5, 2.0}) {
    const double found = BestViewBlur(scene.Frame(sigma, rng), scene.View(), kMargin, scene.inner,
                                      {}, 2.5, 0.5, 4.685);
    EXPECT_NEAR(found, sigma, 0.3) << "blur " << sigma;
  }
}

TEST(ViewBlur, BlurredViewKeepsTheCentreAndCutsTheMargin) {
  cv::Mat view(20, 30, CV_32F, cv::Scalar(0));
  view.at<float>(10, 15) = 1.0f;
  const cv::Mat sharp = BlurredView(view, 0.0, 4);
  const cv::Mat soft = BlurredView(view, 1.0, 4);
  ASSERT_EQ(sharp.size(), cv::Size(22, 12));
  ASSERT_EQ(soft.size(), cv::Size(22, 12));
  EXPECT_FLOAT_EQ(sharp.at<float>(6, 11), 1.0f);
  EXPECT_NEAR(cv::sum(soft)[0], 1.0, 1e-3);  // nothing of the blurred point lost
  EXPECT_NEAR(soft.at<float>(6, 11), 1.0 / (2 * CV_PI), 0.01);
}

}  // namespace
}  // namespace fleetloc::tracking
