// Local normalization (paper 000 §2.4.2): each pixel becomes its deviation from the local mean
// divided by the local standard deviation, (I − μ_w) / (σ_w + ε), removing gain, bias and slow
// lighting changes between a camera frame and the mosaic.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

// Returns CV_32F. window_px odd ≥ 3; epsilon in grey levels keeps flat areas from exploding.
cv::Mat LocalNormalize(const cv::Mat& gray, int window_px, float epsilon = 2.0f);

}  // namespace fleetloc::imaging
