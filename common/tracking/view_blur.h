// Matching the mosaic view's blur to the frame's (issue 15). A camera frame is the floor seen
// through the lens's blur and the motion during the exposure; the mosaic is a sharper photograph.
// Aligned at full resolution, the two differ most in their finest detail, and that difference
// moves each frame's fit by a texture-dependent amount (measured at 320×240 under `all`: per-frame
// errors 0.1–0.7 px). The view is blurred to the frame's blur, found per frame as the Gaussian
// that makes the view correlate best with the frame: for Gaussian blurs the correlation of two
// blurred copies of one texture peaks where the blurs are equal (Cauchy–Schwarz on their spectra),
// and noise or occluders in the frame only lower it evenly.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace fleetloc::tracking {

// Margin (px) a view needs around the pixels it keeps to be blurred by up to `max_sigma_px`.
int BlurMarginPx(double max_sigma_px);

// `view` (CV_32F) blurred by a Gaussian of `sigma_px` (0: unchanged, a header on view's own
// pixels) with `margin_px` cut from every side; the margin must be ≥ BlurMarginPx(sigma_px).
cv::Mat BlurredView(const cv::Mat& view, double sigma_px, int margin_px);

// The Gaussian blur (px, 0 to max_sigma_px) under which `view` correlates best with `frame`
// (robust weighted correlation, LinearizeWholeFrame's, over `inner` and `spans`), searched at
// steps of `step_px` and refined by a parabola through the best step and its neighbours.
// `view` covers `inner` grown by margin_px + 1 on each side; margin_px ≥ BlurMarginPx(max).
double BestViewBlur(const cv::Mat& frame, const cv::Mat& view, int margin_px, const cv::Rect& inner,
                    const std::vector<cv::Range>& spans, double max_sigma_px, double step_px,
                    double tukey_c);

}  // namespace fleetloc::tracking
