// MaskedCorrelator against cv::matchTemplate's masked TM_CCORR_NORMED on random images, templates
// and rotated-rectangle masks; bad inputs abort.
#include "imaging/masked_correlator.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace fleetloc::imaging {
namespace {

cv::Mat RandomImage(cv::Size size, int seed) {
  cv::RNG rng(seed);
  cv::Mat image(size, CV_32F);
  rng.fill(image, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(image, image, {5, 5}, 1.0);
  return image;
}

TEST(MaskedCorrelator, EqualsMatchTemplateWithARotatedMask) {
  const cv::Mat image = RandomImage({157, 131}, 1);
  const MaskedCorrelator correlator(image);
  for (int k = 0; k < 3; ++k) {
    // A template cut from the image at (40 + k, 30), its corners masked out as a rotated frame's.
    const cv::Rect cut(40 + k, 30, 61 - 2 * k, 47 + 3 * k);
    const cv::Mat templ = image(cut).clone();
    cv::Mat mask = cv::Mat::zeros(cut.size(), CV_8U);
    const cv::RotatedRect frame({0.5f * cut.width, 0.5f * cut.height},
                                {0.8f * cut.width, 0.7f * cut.height}, 20.0f * k);
    cv::Point2f corners[4];
    frame.points(corners);
    std::vector<cv::Point> polygon(corners, corners + 4);
    cv::fillConvexPoly(mask, polygon, cv::Scalar(255));
    cv::Mat expected, scores;
    cv::matchTemplate(image, templ, expected, cv::TM_CCORR_NORMED, mask);
    correlator.Match(templ, mask, &scores);
    ASSERT_EQ(scores.size(), expected.size());
    double worst = 0;
    cv::minMaxLoc(cv::abs(scores - expected), nullptr, &worst);
    EXPECT_LT(worst, 1e-4) << "template " << k;
    cv::Point best;
    cv::minMaxLoc(scores, nullptr, nullptr, nullptr, &best);
    EXPECT_EQ(best, cut.tl());  // the template's own place correlates 1
    EXPECT_NEAR(scores.at<float>(cut.y, cut.x), 1.0, 1e-4);
  }
}

TEST(MaskedCorrelatorDeathTest, ATemplateLargerThanTheImageAborts) {
  const MaskedCorrelator correlator(RandomImage({40, 30}, 2));
  cv::Mat scores;
  EXPECT_DEATH(
      correlator.Match(cv::Mat::zeros(31, 20, CV_32F), cv::Mat::ones(31, 20, CV_8U), &scores), "");
}

}  // namespace
}  // namespace fleetloc::imaging
