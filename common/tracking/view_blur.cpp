// The frame's blur, found as the view's blur that correlates best (see view_blur.h).
#include "tracking/view_blur.h"

#include <algorithm>
#include <cmath>

#include "imaging/gaussian_blur.h"
#include "tracking/dense_linearization.h"

namespace fleetloc::tracking {

int BlurMarginPx(double max_sigma_px) {
  return max_sigma_px > 0 ? static_cast<int>(std::ceil(3.0 * max_sigma_px)) : 0;
}

cv::Mat BlurredView(const cv::Mat& view, double sigma_px, int margin_px) {
  const cv::Rect kept(margin_px, margin_px, view.cols - 2 * margin_px, view.rows - 2 * margin_px);
  if (sigma_px <= 0) return view(kept);  // shares view's pixels: read, never written
  const int r = BlurMarginPx(sigma_px);
  CV_Assert(r <= margin_px);
  return imaging::GaussianBlurInterior(
      view(cv::Rect(kept.x - r, kept.y - r, kept.width + 2 * r, kept.height + 2 * r)), sigma_px, r);
}

double BestViewBlur(const cv::Mat& frame, const cv::Mat& view, int margin_px, const cv::Rect& inner,
                    const std::vector<cv::Range>& spans, double max_sigma_px, double step_px,
                    double tukey_c) {
  const int steps = std::max(0, static_cast<int>(std::floor(max_sigma_px / step_px + 1e-9)));
  std::vector<double> correlation(steps + 1);
  // Only the correlation is needed: the principal point does not enter it.
  for (int i = 0; i <= steps; ++i) {
    correlation[i] = LinearizeWholeFrame(frame, BlurredView(view, i * step_px, margin_px), inner,
                                         spans, Eigen::Vector2d::Zero(), tukey_c, 0.0, 0.0)
                         .correlation;
  }
  const int best = static_cast<int>(std::max_element(correlation.begin(), correlation.end()) -
                                    correlation.begin());
  if (best == 0 || best == steps) return best * step_px;
  // Vertex of the parabola through the best step and its neighbours.
  const double left = correlation[best - 1], mid = correlation[best], right = correlation[best + 1];
  const double curvature = left - 2 * mid + right;
  const double offset = curvature < 0 ? 0.5 * (left - right) / curvature : 0.0;
  return (best + std::clamp(offset, -0.5, 0.5)) * step_px;
}

}  // namespace fleetloc::tracking
