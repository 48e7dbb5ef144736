// Patch admission: the server's own registration, block evidence, photometry and change checks.
#include "mapping/patch_admission.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <utility>

#include "geometry/covariance_check.h"
#include "mapping/patch_blender.h"

namespace fleetloc::mapping {
namespace {

std::string Format(const char* what, double value, const char* op, double limit) {
  std::ostringstream out;
  out.precision(3);
  out << what << " " << value << " " << op << " " << limit;
  return out.str();
}

// `a` refused with `verdict` for `reason`: Evaluate's early answers.
Admission Refused(Admission a, Verdict verdict, std::string reason) {
  a.verdict = verdict;
  a.reason = std::move(reason);
  return a;
}

double MaxEigenvalue(const Eigen::Matrix2d& m) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(m).eigenvalues().maxCoeff();
}

// RMS of mosaic − (gain · patch + bias) over the anchor blocks' pixels the mosaic covers.
double PhotometricRms(const cv::Mat& patch, const cv::Mat& view,
                      const std::vector<cv::Rect>& anchors, double gain, double bias) {
  double sum = 0;
  long n = 0;
  for (const cv::Rect& r : anchors) {
    for (int y = r.y; y < r.br().y; ++y) {
      const uchar* p = patch.ptr<uchar>(y);
      const uchar* m = view.ptr<uchar>(y);
      for (int x = r.x; x < r.br().x; ++x) {
        if (m[x] == 0) continue;
        const double d = m[x] - (gain * p[x] + bias);
        sum += d * d;
        ++n;
      }
    }
  }
  return n > 0 ? std::sqrt(sum / n) : 0.0;
}

}  // namespace

const char* VerdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kAdmitted:
      return "admitted";
    case Verdict::kMalformed:
      return "malformed";
    case Verdict::kUnregistered:
      return "unregistered";
    case Verdict::kPoseDisagrees:
      return "pose_disagrees";
    case Verdict::kNoAnchor:
      return "no_anchor";
    case Verdict::kPhotometry:
      return "photometry";
    case Verdict::kImplausibleChange:
      return "implausible_change";
    case Verdict::kTextureDestroyed:
      return "texture_destroyed";
  }
  return "unknown";
}

std::string OptionsProblem(const AdmissionOptions& o) {
  if (!(o.min_search_sigma_px > 0 && o.min_search_sigma_px <= o.max_search_sigma_px)) {
    return "min_search_sigma_px must be > 0 and <= max_search_sigma_px";
  }
  if (!(o.min_search_sigma_rad > 0 && o.min_search_sigma_rad <= o.max_search_sigma_rad)) {
    return "min_search_sigma_rad must be > 0 and <= max_search_sigma_rad";
  }
  if (o.min_inliers < 3) return "min_inliers must be >= 3";
  if (!(o.max_rms_residual_px > 0)) return "max_rms_residual_px must be > 0";
  if (!(o.max_disagreement_sigmas > 0 && o.min_disagreement_px > 0 && o.min_disagreement_rad > 0)) {
    return "the disagreement limits must be > 0";
  }
  if (o.blocks.block_px < 8) return "block_px must be >= 8";
  if (!(o.anchor_ncc > o.blocks.min_block_ncc && o.anchor_ncc <= 1)) {
    return "anchor_ncc must be in (changed_ncc, 1]";
  }
  if (o.min_anchor_blocks < 1) return "min_anchor_blocks must be >= 1";
  if (!(o.min_anchor_fraction > 0 && o.min_anchor_fraction <= 1))
    return "min_anchor_fraction must be in (0, 1]";
  if (!(o.min_gain > 0 && o.min_gain < o.max_gain)) return "min_gain must be > 0 and < max_gain";
  if (!(o.max_abs_bias >= 0 && o.max_photometric_rms > 0))
    return "photometric limits must be positive";
  if (!(o.max_changed_fraction >= 0 && o.max_changed_fraction < 1))
    return "max_changed_fraction must be in [0, 1)";
  if (!(o.min_texture_ratio >= 0 && o.min_texture_ratio <= 1))
    return "min_texture_ratio must be in [0, 1]";
  if (!(o.max_flattened_fraction >= 0 && o.max_flattened_fraction <= 1)) {
    return "max_flattened_fraction must be in [0, 1]";
  }
  if (o.texture_window_px < 3) return "texture_window_px must be >= 3";
  return "";
}

double ClaimedRank(const Patch& patch, double resolution_m) {
  const double sigma_px =
      std::sqrt(std::max(0.0, MaxEigenvalue(patch.covariance.topLeftCorner<2, 2>()))) /
      resolution_m;
  const double quality = std::isfinite(patch.quality) ? std::clamp(patch.quality, 0.0, 1.0) : 0.0;
  return quality / (1.0 + (std::isfinite(sigma_px) ? sigma_px : 1e9));
}

double MeanLocalStdDev(const cv::Mat& image, const cv::Rect& rect, int window_px) {
  // Local windows reach past the block by half a window; clip them to the image.
  const int r = window_px / 2;
  const cv::Rect grown = cv::Rect(rect.x - r, rect.y - r, rect.width + 2 * r, rect.height + 2 * r) &
                         cv::Rect(0, 0, image.cols, image.rows);
  cv::Mat f, mean, mean_sq;
  image(grown).convertTo(f, CV_32F);
  cv::boxFilter(f, mean, CV_32F, {window_px, window_px}, {-1, -1}, true, cv::BORDER_REFLECT);
  cv::boxFilter(f.mul(f), mean_sq, CV_32F, {window_px, window_px}, {-1, -1}, true,
                cv::BORDER_REFLECT);
  cv::Mat variance = cv::max(mean_sq - mean.mul(mean), 0.0f);
  cv::Mat stddev;
  cv::sqrt(variance, stddev);
  return cv::mean(stddev(rect - grown.tl()))[0];
}

PatchAdmission::PatchAdmission(mosaic::RasterSource* mosaic, AdmissionOptions options,
                               tracking::TrackerOptions tracker)
    : mosaic_(mosaic), options_(options), registrar_(mosaic, tracker) {}

Eigen::Matrix3d PatchAdmission::SearchPrior(const Eigen::Matrix3d& claimed) const {
  const double res = mosaic_->layout().geo.resolution;
  const double position_px =
      std::sqrt(std::max(0.0, MaxEigenvalue(claimed.topLeftCorner<2, 2>()))) / res;
  const double heading = std::sqrt(std::max(0.0, claimed(2, 2)));
  const double s_px = std::clamp(std::isfinite(position_px) ? position_px : 0.0,
                                 options_.min_search_sigma_px, options_.max_search_sigma_px);
  const double s_rad = std::clamp(std::isfinite(heading) ? heading : 0.0,
                                  options_.min_search_sigma_rad, options_.max_search_sigma_rad);
  return Eigen::Vector3d(std::pow(s_px * res, 2), std::pow(s_px * res, 2), s_rad * s_rad)
      .asDiagonal();
}

Admission PatchAdmission::Evaluate(const Patch& patch) {
  Admission a;
  a.pose = patch.pose;
  if (const std::string problem = geometry::CovarianceProblem(patch.covariance); !problem.empty())
    return Refused(a, Verdict::kMalformed, problem);
  if (patch.image.empty() || patch.image.type() != CV_8UC1 ||
      patch.image.cols < 2 * options_.blocks.block_px ||
      patch.image.rows < 2 * options_.blocks.block_px)
    return Refused(a, Verdict::kMalformed, "image is not 8-bit gray of at least 2 × 2 blocks");
  const double res = mosaic_->layout().geo.resolution;
  const Registration r = registrar_.Register(patch, SearchPrior(patch.covariance));
  a.evidence.registered = r.registered;
  a.evidence.inliers = r.inliers;
  a.evidence.rms_residual_px = r.rms_residual_px;
  if (!r.registered)
    return Refused(a, Verdict::kUnregistered, "does not register against the mosaic");
  a.pose = r.pose;
  if (r.inliers < options_.min_inliers)
    return Refused(a, Verdict::kUnregistered,
                   Format("registration inliers", r.inliers, "<", options_.min_inliers));
  if (r.rms_residual_px > options_.max_rms_residual_px)
    return Refused(
        a, Verdict::kUnregistered,
        Format("registration residual (px)", r.rms_residual_px, ">", options_.max_rms_residual_px));
  const geometry::Pose2 offset = geometry::Between(patch.pose, r.pose);
  a.evidence.disagreement_px = std::hypot(offset.x, offset.y) / res;
  a.evidence.disagreement_rad = std::abs(geometry::WrapAngle(offset.theta));
  const double claimed_px =
      std::sqrt(std::max(0.0, MaxEigenvalue(patch.covariance.topLeftCorner<2, 2>()))) / res;
  const double allowed_px =
      std::max(options_.max_disagreement_sigmas * claimed_px, options_.min_disagreement_px);
  const double allowed_rad =
      std::max(options_.max_disagreement_sigmas * std::sqrt(patch.covariance(2, 2)),
               options_.min_disagreement_rad);
  if (a.evidence.disagreement_px > allowed_px)
    return Refused(a, Verdict::kPoseDisagrees,
                   Format("reported position off the registration by (px)",
                          a.evidence.disagreement_px, ">", allowed_px));
  if (a.evidence.disagreement_rad > allowed_rad)
    return Refused(a, Verdict::kPoseDisagrees,
                   Format("reported heading off the registration by (rad)",
                          a.evidence.disagreement_rad, ">", allowed_rad));
  Judge(patch, &a);
  if (a.admitted()) a.rank = ClaimedRank(patch, res);
  return a;
}

void PatchAdmission::Judge(const Patch& patch, Admission* a) {
  const AdmissionOptions& o = options_;
  const cv::Mat view = MosaicUnderPatch(mosaic_, patch.image.size(), a->pose);
  std::vector<cv::Rect> anchors, changed;
  double anchor_ncc_sum = 0, patch_texture = 0, mosaic_texture = 0;
  AdmissionEvidence& e = a->evidence;
  for (const BlockComparison& b : CompareBlocks(patch.image, view, o.blocks)) {
    if (!b.mapped || !b.textured(o.blocks.min_block_stddev)) continue;
    ++e.textured_blocks;
    if (b.ncc >= o.anchor_ncc) {
      anchors.push_back(b.rect);
      anchor_ncc_sum += b.ncc;
    } else if (b.ncc < o.blocks.min_block_ncc) {
      changed.push_back(b.rect);
      const double patch_std = MeanLocalStdDev(patch.image, b.rect, o.texture_window_px);
      const double mosaic_std = MeanLocalStdDev(view, b.rect, o.texture_window_px);
      if (patch_std < o.min_texture_ratio * mosaic_std) ++e.flattened_blocks;
      patch_texture += patch_std;
      mosaic_texture += mosaic_std;
    }
  }
  e.anchor_blocks = static_cast<int>(anchors.size());
  e.changed_blocks = static_cast<int>(changed.size());
  e.anchor_ncc_mean = anchors.empty() ? 0 : anchor_ncc_sum / anchors.size();
  e.texture_ratio = mosaic_texture > 0 ? patch_texture / mosaic_texture : 1.0;
  if (e.anchor_blocks < o.min_anchor_blocks || e.anchor_fraction() < o.min_anchor_fraction) {
    a->verdict = Verdict::kNoAnchor;
    a->reason = "only " + std::to_string(e.anchor_blocks) + " of " +
                std::to_string(e.textured_blocks) + " textured blocks agree with the mosaic";
    return;
  }
  // The fit over the blocks that agree with the mosaic (PhotometricFit ignores the pixels where
  // its mosaic side is 0), so changed floor does not pull it.
  cv::Mat anchor_view = cv::Mat::zeros(view.size(), CV_8UC1);
  for (const cv::Rect& r : anchors) view(r).copyTo(anchor_view(r));
  std::tie(a->gain, a->bias) = PhotometricFit(patch.image, anchor_view);
  e.photometric_rms = PhotometricRms(patch.image, view, anchors, a->gain, a->bias);
  if (a->gain < o.min_gain || a->gain > o.max_gain || std::abs(a->bias) > o.max_abs_bias ||
      e.photometric_rms > o.max_photometric_rms) {
    a->verdict = Verdict::kPhotometry;
    std::ostringstream out;
    out.precision(3);
    out << "photometry out of bounds: gain " << a->gain << ", bias " << a->bias << ", residual "
        << e.photometric_rms << " grey levels";
    a->reason = out.str();
    return;
  }
  if (e.changed_fraction() > o.max_changed_fraction) {
    a->verdict = Verdict::kImplausibleChange;
    a->reason = Format("changed fraction", e.changed_fraction(), ">", o.max_changed_fraction);
    return;
  }
  if (e.flattened_fraction() > o.max_flattened_fraction) {
    a->verdict = Verdict::kTextureDestroyed;
    a->reason = Format("flattened fraction", e.flattened_fraction(), ">", o.max_flattened_fraction);
    return;
  }
  a->verdict = Verdict::kAdmitted;
  a->changed_blocks = std::move(changed);
}

}  // namespace fleetloc::mapping
