// Patch-grid registration of a built mosaic against the truth and a similarity fit.
#include "mapping/mosaic_distortion.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "imaging/correlation.h"
#include "imaging/fast_patch.h"

namespace fleetloc::mapping {
namespace {

// The patch `rect` of `image`, locally normalized with a margin that is then cropped away.
cv::Mat NormalizedRegion(const cv::Mat& image, const cv::Rect& rect, int window_px) {
  const int m = window_px / 2 + 1;
  const cv::Rect padded(rect.x - m, rect.y - m, rect.width + 2 * m, rect.height + 2 * m);
  return imaging::NormalizePatch(image(padded), window_px)(cv::Rect(m, m, rect.width, rect.height));
}

std::optional<PatchDisplacement> MeasurePatch(const cv::Mat& built, const cv::Mat& truth,
                                              const cv::Rect& patch, const DistortionOptions& o) {
  const cv::Mat templ = NormalizedRegion(built, patch, o.normalize_window_px);
  const int s = o.search_px;
  const cv::Rect window_rect(patch.x - s, patch.y - s, patch.width + 2 * s, patch.height + 2 * s);
  const cv::Mat window = NormalizedRegion(truth, window_rect, o.normalize_window_px);
  const imaging::Match match = imaging::MatchTemplate(window, templ);
  if (!match.found || match.peak < o.min_peak) return std::nullopt;
  return PatchDisplacement{{patch.x + patch.width / 2.0, patch.y + patch.height / 2.0},
                           match.offset_px - Eigen::Vector2d(s, s),
                           match.peak};
}

// Fits q ≈ s·R·p + t (p the patch centres, q = p + displacement) in closed form and fills the
// similarity and residual fields of the report.
void FitSimilarity(DistortionReport* r) {
  Eigen::Vector2d p_mean(0, 0), q_mean(0, 0);
  for (const PatchDisplacement& d : r->patches) {
    p_mean += d.center_px;
    q_mean += d.center_px + d.displacement_px;
  }
  p_mean /= r->patches.size();
  q_mean /= r->patches.size();
  double dot = 0, cross = 0, norm = 0;
  for (const PatchDisplacement& d : r->patches) {
    const Eigen::Vector2d p = d.center_px - p_mean;
    const Eigen::Vector2d q = d.center_px + d.displacement_px - q_mean;
    dot += p.dot(q);
    cross += p.x() * q.y() - p.y() * q.x();
    norm += p.squaredNorm();
  }
  const double a = dot / norm, b = cross / norm;
  r->scale_error = std::hypot(a, b) - 1.0;
  r->rotation_rad = -std::atan2(b, a);  // image v points down: counter-clockwise in map is −θ
  r->translation_px = q_mean - p_mean;
  double sum_sq = 0;
  for (const PatchDisplacement& d : r->patches) {
    const Eigen::Vector2d p = d.center_px - p_mean;
    const Eigen::Vector2d fitted(a * p.x() - b * p.y(), b * p.x() + a * p.y());
    const double residual = (d.center_px + d.displacement_px - q_mean - fitted).norm();
    sum_sq += residual * residual;
    r->residual_max_px = std::max(r->residual_max_px, residual);
  }
  r->residual_rms_px = std::sqrt(sum_sq / r->patches.size());
}

}  // namespace

Result<DistortionReport> MeasureDistortion(const cv::Mat& built, const cv::Mat& truth,
                                           const DistortionOptions& o) {
  if (built.size() != truth.size() || built.type() != CV_8UC1 || truth.type() != CV_8UC1) {
    return InvalidInput("the built mosaic and the truth must be 8-bit gray of the same size");
  }
  DistortionReport report;
  const int margin = o.search_px + o.normalize_window_px / 2 + 1;
  double sum_sq = 0;
  for (int y = margin; y + o.patch_px + margin <= built.rows; y += o.spacing_px) {
    for (int x = margin; x + o.patch_px + margin <= built.cols; x += o.spacing_px) {
      const cv::Rect patch(x, y, o.patch_px, o.patch_px);
      const cv::Rect padded(x - margin, y - margin, o.patch_px + 2 * margin,
                            o.patch_px + 2 * margin);
      if (cv::countNonZero(built(padded)) < padded.area()) continue;  // not fully mapped
      ++report.patches_tried;
      const std::optional<PatchDisplacement> d = MeasurePatch(built, truth, patch, o);
      if (!d) continue;
      report.patches.push_back(*d);
      const double length = d->displacement_px.norm();
      sum_sq += length * length;
      report.max_px = std::max(report.max_px, length);
    }
  }
  if (report.patches.size() < 3) {
    return InvalidInput("only " + std::to_string(report.patches.size()) + " of " +
                        std::to_string(report.patches_tried) +
                        " mapped patches match the truth: cannot measure distortion");
  }
  report.rms_px = std::sqrt(sum_sq / report.patches.size());
  FitSimilarity(&report);
  return report;
}

}  // namespace fleetloc::mapping
