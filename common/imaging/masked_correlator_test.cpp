// MaskedCorrelator against cv::matchTemplate's masked TM_CCORR_NORMED on random images, templates
// and rotated-rectangle masks, also for the template turned by π and over an image with a zero
// border (shorter transforms); bad inputs abort.
#include "imaging/masked_correlator.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <vector>

namespace fleetloc::imaging {
namespace {

cv::Mat RandomImage(cv::Size size, int seed) {
  cv::RNG rng(seed);
  cv::Mat image(size, CV_32F);
  rng.fill(image, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(image, image, {5, 5}, 1.0);
  return image;
}

// A template cut from the image at (40 + k, 30), its corners masked out as a rotated frame's
// (`symmetric`: also the mask turned by π, as the dense place search's rotated frames are).
struct Cut {
  cv::Rect rect;
  cv::Mat templ, mask;
};

Cut CutFrom(const cv::Mat& image, int k, bool symmetric) {
  Cut cut;
  cut.rect = cv::Rect(40 + k, 30, 61 - 2 * k, 47 + 3 * k);
  cut.templ = image(cut.rect).clone();
  cut.mask = cv::Mat::zeros(cut.rect.size(), CV_8U);
  const cv::RotatedRect frame({0.5f * cut.rect.width, 0.5f * cut.rect.height},
                              {0.8f * cut.rect.width, 0.7f * cut.rect.height}, 20.0f * k);
  cv::Point2f corners[4];
  frame.points(corners);
  std::vector<cv::Point> polygon(corners, corners + 4);
  cv::fillConvexPoly(cut.mask, polygon, cv::Scalar(255));
  if (symmetric) {
    cv::Mat turned;
    cv::flip(cut.mask, turned, -1);
    cut.mask &= turned;
  }
  return cut;
}

// cv::matchTemplate's masked NCC of the cut's template, and of it turned by π with its mask.
struct Expected {
  cv::Mat scores, turned, turned_mask;
};

Expected ExpectedScores(const cv::Mat& image, const Cut& cut) {
  Expected e;
  cv::Mat turned_templ;
  cv::flip(cut.templ, turned_templ, -1);
  cv::flip(cut.mask, e.turned_mask, -1);
  cv::matchTemplate(image, cut.templ, e.scores, cv::TM_CCORR_NORMED, cut.mask);
  cv::matchTemplate(image, turned_templ, e.turned, cv::TM_CCORR_NORMED, e.turned_mask);
  return e;
}

double WorstDifference(const cv::Mat& a, const cv::Mat& b, const cv::Mat& where = cv::Mat()) {
  double worst = 0;
  cv::minMaxLoc(cv::abs(a - b), nullptr, &worst, nullptr, nullptr, where);
  return worst;
}

// At every placement of the mask, how many of its pixels fall on non-zero image pixels.
cv::Mat CoveredPixels(const cv::Mat& image, const cv::Mat& mask) {
  cv::Mat content, used, covered;
  cv::Mat(image != 0).convertTo(content, CV_32F, 1.0 / 255.0);
  mask.convertTo(used, CV_32F, 1.0 / 255.0);
  cv::matchTemplate(content, used, covered, cv::TM_CCORR);
  return covered;
}

TEST(MaskedCorrelator, EqualsMatchTemplateWithARotatedMask) {
  const cv::Mat image = RandomImage({157, 131}, 1);
  const MaskedCorrelator correlator(image);
  for (int k = 0; k < 3; ++k) {
    const Cut cut = CutFrom(image, k, false);
    cv::Mat expected, scores;
    cv::matchTemplate(image, cut.templ, expected, cv::TM_CCORR_NORMED, cut.mask);
    correlator.Match(cut.templ, cut.mask, &scores);
    ASSERT_EQ(scores.size(), expected.size());
    EXPECT_LT(WorstDifference(scores, expected), 1e-4) << "template " << k;
    cv::Point best;
    cv::minMaxLoc(scores, nullptr, nullptr, nullptr, &best);
    EXPECT_EQ(best, cut.rect.tl());  // the template's own place correlates 1
    EXPECT_NEAR(scores.at<float>(cut.rect.y, cut.rect.x), 1.0, 1e-4);
  }
}

TEST(MaskedCorrelator, EqualsMatchTemplateWithAMaskOfSeveralRunsARow) {
  const cv::Mat image = RandomImage({157, 131}, 5);
  const MaskedCorrelator correlator(image);
  const cv::Rect rect(30, 20, 50, 40);
  cv::Mat mask(rect.size(), CV_8U);
  cv::RNG(6).fill(mask, cv::RNG::UNIFORM, 0, 2);  // about half the pixels, many runs a row
  mask *= 255;
  cv::Mat expected, scores;
  cv::matchTemplate(image, image(rect), expected, cv::TM_CCORR_NORMED, mask);
  correlator.Match(image(rect), mask, &scores);
  EXPECT_LT(WorstDifference(scores, expected), 1e-4);
  EXPECT_NEAR(scores.at<float>(rect.y, rect.x), 1.0, 1e-4);
}

TEST(MaskedCorrelator, TheTurnedTemplateEqualsMatchTemplateWithBothFlipped) {
  const cv::Mat image = RandomImage({157, 131}, 3);
  const MaskedCorrelator correlator(image);
  for (const bool symmetric : {false, true}) {
    for (int k = 0; k < 3; ++k) {
      const Cut cut = CutFrom(image, k, symmetric);
      const Expected expected = ExpectedScores(image, cut);
      cv::Mat scores, turned;
      correlator.MatchWithTurned(cut.templ, cut.mask, &scores, &turned);
      ASSERT_EQ(turned.size(), expected.turned.size());
      EXPECT_LT(WorstDifference(scores, expected.scores), 1e-4) << "template " << k;
      EXPECT_LT(WorstDifference(turned, expected.turned), 1e-4)
          << "template " << k << (symmetric ? ", symmetric mask" : "");
      // The turned template is not the image's own content: nowhere near 1 at the cut.
      EXPECT_LT(turned.at<float>(cut.rect.y, cut.rect.x), 0.9);
    }
  }
}

TEST(MaskedCorrelator, ShorterTransformsOverAZeroBorderGiveTheSameScores) {
  constexpr int kBorder = 40;  // the templates below are 47 to 61 pixels a side
  cv::Mat image;
  cv::copyMakeBorder(RandomImage({157, 131}, 7), image, kBorder, kBorder, kBorder, kBorder,
                     cv::BORDER_CONSTANT, 0);
  const MaskedCorrelator correlator(image, kBorder);
  for (const bool symmetric : {false, true}) {
    for (int k = 0; k < 3; ++k) {
      const Cut cut = CutFrom(image, k, symmetric);
      const Expected expected = ExpectedScores(image, cut);
      cv::Mat scores, turned;
      correlator.MatchWithTurned(cut.templ, cut.mask, &scores, &turned);
      ASSERT_EQ(scores.size(), expected.scores.size());
      // Where the mask covers only the border both are 0 / 0: compared where it covers at least
      // a tenth of the image's own pixels (the turned map's reads that wrap around start well
      // inside that range: at x ≥ 200 − w + 1 of up to 237 − w).
      const cv::Mat covered = CoveredPixels(image, cut.mask) >= 0.1 * cv::countNonZero(cut.mask);
      const cv::Mat turned_covered =
          CoveredPixels(image, expected.turned_mask) >= 0.1 * cv::countNonZero(cut.mask);
      EXPECT_LT(WorstDifference(scores, expected.scores, covered), 1e-4) << "template " << k;
      EXPECT_LT(WorstDifference(turned, expected.turned, turned_covered), 1e-4) << "template " << k;
    }
  }
}

TEST(MaskedCorrelator, AtFewPlacementsEqualsMatchTemplate) {
  const cv::Mat image = RandomImage({157, 131}, 4);
  for (int k = 0; k < 3; ++k) {
    const Cut cut = CutFrom(image, k, false);
    // 9 × 9 placements around the cut, as the dense place search's refinement has.
    const cv::Rect area(cut.rect.tl() - cv::Point(4, 4), cut.rect.size() + cv::Size(8, 8));
    cv::Mat expected, scores;
    cv::matchTemplate(image(area), cut.templ, expected, cv::TM_CCORR_NORMED, cut.mask);
    MatchAtFewPlacements(image(area), cut.templ, cut.mask, &scores);
    ASSERT_EQ(scores.size(), cv::Size(9, 9));
    EXPECT_LT(WorstDifference(scores, expected), 1e-4) << "template " << k;
    EXPECT_NEAR(scores.at<float>(4, 4), 1.0, 1e-4);
  }
}

TEST(MaskedCorrelatorDeathTest, ANonZeroBorderOrATemplateNoLargerThanTheBorderAborts) {
  EXPECT_DEATH(MaskedCorrelator(RandomImage({80, 60}, 8), 10), "");
  cv::Mat image;
  cv::copyMakeBorder(RandomImage({80, 60}, 8), image, 10, 10, 10, 10, cv::BORDER_CONSTANT, 0);
  const MaskedCorrelator correlator(image, 10);
  cv::Mat scores;
  EXPECT_DEATH(
      correlator.Match(cv::Mat::zeros(10, 20, CV_32F), cv::Mat::ones(10, 20, CV_8U), &scores), "");
}

TEST(MaskedCorrelatorDeathTest, ATemplateLargerThanTheImageAborts) {
  const MaskedCorrelator correlator(RandomImage({40, 30}, 2));
  cv::Mat scores;
  EXPECT_DEATH(
      correlator.Match(cv::Mat::zeros(31, 20, CV_32F), cv::Mat::ones(31, 20, CV_8U), &scores), "");
}

}  // namespace
}  // namespace fleetloc::imaging
