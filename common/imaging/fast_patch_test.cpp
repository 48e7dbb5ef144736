// The hand-written patch kernels agree with the OpenCV functions they stand in for.
#include "imaging/fast_patch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "imaging/normalize.h"
#include "imaging/texture.h"

namespace fleetloc::imaging {
namespace {

cv::Mat Gravel() {
  return cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
}

TEST(NormalizePatch, MatchesOpenCvNormalizationAwayFromTheBorder) {
  const cv::Mat patch = Gravel()(cv::Rect(100, 120, 60, 50));
  const cv::Mat fast = NormalizePatch(patch, 11);
  const cv::Mat reference = LocalNormalize(patch, 11);
  const cv::Rect interior(5, 5, 50, 40);
  EXPECT_LT(cv::norm(fast(interior), reference(interior), cv::NORM_INF), 1e-3);
}

TEST(NormalizePatch, GivesTheLocalVarianceOfOpenCvsBoxFilterAwayFromTheBorder) {
  const cv::Mat patch = Gravel()(cv::Rect(100, 120, 60, 50));
  cv::Mat variance;
  const cv::Mat normalized = NormalizePatch(patch, 11, 2.0f, &variance);
  EXPECT_LT(cv::norm(normalized, NormalizePatch(patch, 11), cv::NORM_INF), 1e-6);
  cv::Mat f, mean, mean_sq;
  patch.convertTo(f, CV_32F);
  cv::boxFilter(f, mean, CV_32F, {11, 11});
  cv::boxFilter(f.mul(f), mean_sq, CV_32F, {11, 11});
  const cv::Mat reference = mean_sq - mean.mul(mean);
  const cv::Rect interior(5, 5, 50, 40);
  ASSERT_GT(cv::mean(reference(interior))[0], 10.0);  // a textured patch
  EXPECT_LT(cv::norm(variance(interior), reference(interior), cv::NORM_INF), 0.05);
}

// (I − μ_w) / (σ_w + ε) and σ_w² in double precision, the window clipped at the patch border.
void ClippedWindowReference(const cv::Mat& patch, int window_px, cv::Mat* normalized,
                            cv::Mat* variance) {
  const int half = window_px / 2;
  normalized->create(patch.size(), CV_64F);
  variance->create(patch.size(), CV_64F);
  for (int y = 0; y < patch.rows; ++y) {
    for (int x = 0; x < patch.cols; ++x) {
      double sum = 0.0, sum_sq = 0.0, n = 0.0;
      for (int v = std::max(0, y - half); v <= std::min(patch.rows - 1, y + half); ++v) {
        for (int u = std::max(0, x - half); u <= std::min(patch.cols - 1, x + half); ++u) {
          const double value = patch.at<float>(v, u);
          sum += value;
          sum_sq += value * value;
          n += 1.0;
        }
      }
      const double mean = sum / n, var = std::max(0.0, sum_sq / n - mean * mean);
      variance->at<double>(y, x) = var;
      normalized->at<double>(y, x) = (patch.at<float>(y, x) - mean) / (std::sqrt(var) + 2.0);
    }
  }
}

TEST(NormalizePatch, EqualsADoublePrecisionReferenceAtEveryPixelOfABrightPlainTileRow) {
  // A bright, nearly plain floor (grey 200–225, mean local variance 6.4 grey levels²), as wide as
  // a mosaic tile with its margins: Σ I² over a 7×7 window is ~2·10⁶, of which ~300 is variance.
  // Running float prefix sums of I and I² along the rows were off by up to 1.2 grey levels² and
  // 0.087 in the normalized value here.
  cv::Mat patch;
  Gravel()(cv::Rect(0, 0, 270, 40)).convertTo(patch, CV_32F, 0.1, 200.0);
  for (const int window_px : {5, 7, 11}) {
    cv::Mat variance, reference_normalized, reference_variance;
    const cv::Mat normalized = NormalizePatch(patch, window_px, 2.0f, &variance);
    ClippedWindowReference(patch, window_px, &reference_normalized, &reference_variance);
    cv::Mat variance_64, normalized_64;
    variance.convertTo(variance_64, CV_64F);
    normalized.convertTo(normalized_64, CV_64F);
    ASSERT_GT(cv::mean(reference_variance)[0], 4.0) << window_px;
    EXPECT_LT(cv::norm(variance_64, reference_variance, cv::NORM_INF), 1e-3) << window_px;
    EXPECT_LT(cv::norm(normalized_64, reference_normalized, cv::NORM_INF), 1e-5) << window_px;
  }
}

TEST(NccSurface, MatchesMatchTemplateCoeffNormed) {
  cv::Mat f;
  Gravel().convertTo(f, CV_32F);
  const cv::Mat window = f(cv::Rect(200, 200, 44, 40)).clone();
  const cv::Mat templ = f(cv::Rect(205, 203, 32, 32)).clone();
  cv::Mat reference;
  cv::matchTemplate(window, templ, reference, cv::TM_CCOEFF_NORMED);
  const cv::Mat fast = NccSurface(window, templ);
  ASSERT_EQ(fast.size(), reference.size());
  EXPECT_LT(cv::norm(fast, reference, cv::NORM_INF), 1e-4);
  double best;
  cv::Point at;
  cv::minMaxLoc(fast, nullptr, &best, nullptr, &at);
  EXPECT_EQ(at, cv::Point(5, 3));
  EXPECT_NEAR(best, 1.0, 1e-5);
}

TEST(NccSurface, MatchesMatchTemplateForEveryPlacementCountOfTheTrackersSearches) {
  // Few placements a row (each one a dot product along the template) and many (8-wide blocks of
  // placements, the last one partial): widths around the blocks' edges, templates of 12 px (level
  // 2), 13 and 24 px, and windows that are views into a larger image.
  cv::Mat f;
  Gravel().convertTo(f, CV_32F);
  for (const int template_px : {12, 13, 24}) {
    for (const int placements : {3, 9, 15, 16, 17, 24, 31, 32, 33, 40, 65}) {
      const cv::Mat window = f(cv::Rect(150, 160, template_px + placements - 1, template_px + 6));
      const cv::Mat templ = f(cv::Rect(150 + placements / 2, 163, template_px, template_px));
      cv::Mat reference;
      cv::matchTemplate(window, templ, reference, cv::TM_CCOEFF_NORMED);
      const cv::Mat fast = NccSurface(window, templ);
      ASSERT_EQ(fast.size(), reference.size());
      EXPECT_LT(cv::norm(fast, reference, cv::NORM_INF), 1e-4) << template_px << " " << placements;
    }
  }
}

// TM_CCOEFF_NORMED at every placement, summed in double.
cv::Mat NccReference(const cv::Mat& window, const cv::Mat& templ) {
  cv::Mat w, t;
  window.convertTo(w, CV_64F);
  templ.convertTo(t, CV_64F);
  t -= cv::mean(t)[0];
  cv::Mat out(window.rows - templ.rows + 1, window.cols - templ.cols + 1, CV_64F);
  for (int y = 0; y < out.rows; ++y) {
    for (int x = 0; x < out.cols; ++x) {
      cv::Mat v = w(cv::Rect({x, y}, templ.size())).clone();
      v -= cv::mean(v)[0];
      out.at<double>(y, x) = t.dot(v) / std::sqrt(t.dot(t) * v.dot(v));
    }
  }
  return out;
}

TEST(NccSurface, EqualsADoublePrecisionReferenceOnABrightPlainWindow) {
  // Grey 200–225 with a local variance of a few grey levels²: Σ v² under a 24² template is
  // ~3·10⁷, of which ~4·10³ is spread. Running float sums along the window's rows were off by
  // 1·10⁻⁴ to 1·10⁻³ in the NCC here; what remains (≤ 2·10⁻⁵) is the float sum Σ t'·v.
  cv::Mat bright;
  Gravel().convertTo(bright, CV_32F, 0.1, 200.0);
  for (const int template_px : {12, 24}) {
    for (const int placements : {5, 9, 40, 65}) {
      const cv::Mat window =
          bright(cv::Rect(30, 20, template_px + placements - 1, template_px + 8));
      const cv::Mat templ = bright(cv::Rect(30 + placements / 3, 24, template_px, template_px));
      cv::Mat fast;
      NccSurface(window, templ).convertTo(fast, CV_64F);
      EXPECT_LT(cv::norm(fast, NccReference(window, templ), cv::NORM_INF), 4e-5)
          << template_px << " " << placements;
    }
  }
}

// A placement whose Σ t'·v reaches the window's spread: rounding (kept at 1 within 1.125 of it,
// as TM_CCOEFF_NORMED) or a transform's noise over a flat window (0), or the plain ratio.
TEST(NormalizeBySpread, TreatsSumsBeyondTheSpreadByItsRule) {
  cv::Mat window = cv::Mat::zeros(1, 4, CV_32F);
  window.at<float>(0, 0) = 1.0f;  // one placement of a 1×4 template: spread² = Σ(v − v̄)² = 0.75
  const double spread = std::sqrt(0.75) * 2.0;  // times the template's norm, 2
  for (const auto& [ratio, opencv, zero_when_flat] :
       {std::tuple{0.5, 0.5, 0.5}, {-1.05, -1.0, -1.05}, {1.2, 0.0, 1.2}}) {
    cv::Mat cross(1, 1, CV_32F, cv::Scalar(ratio * spread)), plain = cross.clone();
    NormalizeBySpread(window, {4, 1}, 0.25f, 2.0, SpreadRule::kLikeOpenCv, cross);
    NormalizeBySpread(window, {4, 1}, 0.25f, 2.0, SpreadRule::kZeroWhenFlat, plain);
    EXPECT_NEAR(cross.at<float>(0, 0), opencv, 1e-6) << ratio;
    EXPECT_NEAR(plain.at<float>(0, 0), zero_when_flat, 1e-6) << ratio;
  }
  // A flat window: 0 either way.
  cv::Mat flat(1, 4, CV_32F, cv::Scalar(3.0f)), cross(1, 1, CV_32F, cv::Scalar(1e-3f));
  NormalizeBySpread(flat, {4, 1}, 3.0f, 2.0, SpreadRule::kLikeOpenCv, cross);
  EXPECT_EQ(cross.at<float>(0, 0), 0.0f);
}

TEST(TextureScoreGrid, AgreesWithTheDenseScoreInRankAndScale) {
  const cv::Mat gray = Gravel();
  const cv::Mat grid = TextureScoreGrid(gray, 8, 5);
  const cv::Mat dense = TextureScore(gray, 5);
  // Central differences versus Sobel: same structure, similar magnitude at each grid point.
  double dot = 0, nd = 0, ng = 0;
  for (int r = 1; r < grid.rows - 1; ++r) {
    for (int c = 1; c < grid.cols - 1; ++c) {
      const double g = grid.at<float>(r, c), d = dense.at<float>((r + 1) * 8, (c + 1) * 8);
      dot += g * d;
      nd += d * d;
      ng += g * g;
    }
  }
  EXPECT_GT(dot / std::sqrt(nd * ng), 0.9);  // strongly correlated
  EXPECT_GT(std::sqrt(ng / nd), 0.5);
  EXPECT_LT(std::sqrt(ng / nd), 2.0);
}

}  // namespace
}  // namespace fleetloc::imaging
