// SpectralNcc gives cv::matchTemplate's TM_CCOEFF_NORMED surface, on a real photograph.
#include "imaging/spectral_ncc.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::imaging {
namespace {

cv::Mat Photo() {
  cv::Mat gray = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  cv::Mat f;
  gray.convertTo(f, CV_32F, 1.0 / 255);
  return f;
}

TEST(SpectralNcc, EqualsOpenCvsMatchTemplateOnEveryView) {
  const cv::Mat photo = Photo();
  ASSERT_FALSE(photo.empty());
  const cv::Mat templ = photo(cv::Rect(100, 80, 152, 112)).clone();
  const cv::Size view_size(152 + 2 * 17, 112 + 2 * 17);
  const SpectralNcc ncc(templ, view_size);
  // The template's own place (peak 1 at the centre), a shifted one, and one with a masked
  // occluder (set to 0, as the dense search masks them).
  cv::Mat occluded = photo(cv::Rect(90, 75, view_size.width, view_size.height)).clone();
  occluded(cv::Rect(30, 20, 60, 50)).setTo(0.0f);
  for (const cv::Mat& view :
       {photo(cv::Rect(83, 63, view_size.width, view_size.height)),
        photo(cv::Rect(90, 75, view_size.width, view_size.height)), occluded}) {
    cv::Mat expected;
    cv::matchTemplate(view, templ, expected, cv::TM_CCOEFF_NORMED);
    const cv::Mat surface = ncc.Surface(view.clone());
    ASSERT_EQ(surface.size(), expected.size());
    EXPECT_LT(cv::norm(surface, expected, cv::NORM_INF), 2e-4);
  }
  double best;
  cv::Point at;
  cv::minMaxLoc(ncc.Surface(photo(cv::Rect(83, 63, view_size.width, view_size.height)).clone()),
                nullptr, &best, nullptr, &at);
  EXPECT_EQ(at, cv::Point(17, 17));
  EXPECT_NEAR(best, 1.0, 1e-4);
}

TEST(SpectralNcc, SurfaceNearEqualsTheSpectralSurfaceOverAPeaksNeighbourhood) {
  const cv::Mat photo = Photo();
  const cv::Mat templ = photo(cv::Rect(100, 80, 152, 112)).clone();
  const SpectralNcc ncc(templ, cv::Size(152 + 2 * 17, 112 + 2 * 17));
  // ±2 px around the template's place, and a 7×5 neighbourhood of another place.
  for (const cv::Rect& near : {cv::Rect(98, 78, 156, 116), cv::Rect(40, 30, 158, 116)}) {
    const cv::Mat view = photo(near);
    cv::Mat expected;
    cv::matchTemplate(view, templ, expected, cv::TM_CCOEFF_NORMED);
    const cv::Mat surface = ncc.SurfaceNear(view);
    ASSERT_EQ(surface.size(), expected.size());
    EXPECT_LT(cv::norm(surface, expected, cv::NORM_INF), 2e-4);
  }
  EXPECT_NEAR(ncc.SurfaceNear(photo(cv::Rect(98, 78, 156, 116))).at<float>(2, 2), 1.0, 1e-4);
}

TEST(SpectralNcc, AFlatViewGivesZeroNotNaN) {
  const cv::Mat templ = Photo()(cv::Rect(100, 80, 64, 48)).clone();
  cv::Mat flat(cv::Size(80, 60), CV_32F, cv::Scalar(0.5));
  cv::randn(flat(cv::Rect(0, 0, 10, 10)), 0.5, 1e-4);  // an almost flat corner
  const cv::Mat surface = SpectralNcc(templ, flat.size()).Surface(flat);
  EXPECT_TRUE(cv::checkRange(surface, true, nullptr, -1.0, 1.0 + 1e-6));
  ASSERT_EQ(surface.size(), cv::Size(17, 13));
  EXPECT_EQ(surface.at<float>(12, 16), 0.0f);  // a window with no spread at all
  const cv::Mat near = SpectralNcc(templ, flat.size()).SurfaceNear(flat(cv::Rect(10, 10, 66, 50)));
  EXPECT_TRUE(cv::checkRange(near, true, nullptr, -1.0, 1.0 + 1e-6));
}

}  // namespace
}  // namespace fleetloc::imaging
