// Robust coarse-to-fine inverse-compositional alignment of the whole frame (see direct_aligner.h):
// the cycle (pyramid, search, levels, a rival peak when refused, the full-resolution refinement),
// the image term's fusion with the prediction and the verdict. The levels' Gauss–Newton is in
// direct_levels.cpp, the search in direct_search.cpp, the polish in direct_polish.cpp.
#include "tracking/direct_aligner.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "tracking/direct_aligner_parts.h"

namespace fleetloc::tracking {

using direct_detail::ApplyStep;
using direct_detail::CornerSigmaPx;
using direct_detail::RotationBlock;
using geometry::Difference;
using geometry::Pose2;
using geometry::PoseWithCovariance;

namespace direct_detail {

cv::Rect GrownBy(const cv::Rect& rect, int margin) {
  return {rect.x - margin, rect.y - margin, rect.width + 2 * margin, rect.height + 2 * margin};
}

double Median(std::vector<float> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

Eigen::Matrix3d RotationBlock(const Pose2& pose) { return geometry::ComposeJacobianB(pose); }

Pose2 ApplyStep(const Pose2& pose, const Eigen::Vector3d& q_px, double resolution_m) {
  const Pose2 q{q_px.x() * resolution_m, q_px.y() * resolution_m, q_px.z()};
  return pose * q.Inverse();
}

double CornerSigmaPx(const geometry::CameraModel& camera, const PoseWithCovariance& pose) {
  double worst = 0.0;
  for (int corner = 0; corner < 4; ++corner) {
    const Eigen::Vector2d px((corner & 1) * camera.width_px, (corner >> 1) * camera.height_px);
    const Eigen::Matrix<double, 2, 3> j =
        geometry::PointJacobian(pose.pose, camera.PixelToGround(px));
    const Eigen::Matrix2d cov = j * pose.covariance * j.transpose();
    worst = std::max(worst,
                     Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues().maxCoeff());
  }
  return std::sqrt(worst) / camera.resolution_m;
}

}  // namespace direct_detail

// The level's pixels whose normalization window lies wholly in the frame.
cv::Rect DirectAligner::InnerRect(const Level& level) {
  const int b = level.border;
  return {b, b, level.normalized.cols - 2 * b, level.normalized.rows - 2 * b};
}

DirectAligner::DirectAligner(const DirectAlignOptions& options, const geometry::CameraModel& camera,
                             NormalizedMosaic* mosaic)
    : options_(options), camera_(camera), mosaic_(mosaic) {
  const int shorter = std::min(camera.width_px, camera.height_px);
  while (levels_ < mosaic->layout().levels && (shorter >> levels_) >= options.coarsest_side_px) {
    ++levels_;
  }
  const long long pixels = static_cast<long long>(camera.width_px) * camera.height_px;
  finest_level_ = std::min(options.min_finest_level, levels_ - 1);
  while (finest_level_ + 1 < levels_ &&
         (pixels >> (2 * (finest_level_ + 1))) >= options.finest_level_pixels) {
    ++finest_level_;
  }
}

DirectAlignment DirectAligner::Align(const cv::Mat& frame, const PoseWithCovariance& prior,
                                     const Pose2& start, bool prediction_confirms,
                                     bool refine_only) const {
  DirectAlignment out;
  // A refinement starts inside the finest level's basin: no search, no coarser level.
  const int search_level = refine_only ? finest_level_ : SearchLevel(CornerSigmaPx(camera_, prior));
  const bool full_resolution =
      finest_level_ > 0 && static_cast<long long>(camera_.width_px) * camera_.height_px <=
                               options_.full_resolution_below_pixels;
  const std::vector<Level> levels =
      BuildLevels(frame, full_resolution ? 0 : finest_level_, search_level);
  SearchHit hit;
  hit.pose = hit.rival_pose = start;
  if (!refine_only) hit = CoarseSearch(levels[search_level], prior, start, &out);
  Linearization final_fit;
  Pose2 pose = AlignLevels(levels, search_level, prior, hit.pose, &out, &final_fit);
  const auto judge = [&] {
    out.reason = "";
    Combine(final_fit, prior, pose, &out);
    const char* strict = Verdict(out, prediction_confirms, options_.min_significant_correlation);
    out.needs_polish =
        strict[0] != '\0' &&
        Verdict(out, prediction_confirms, options_.min_polished_significant_correlation)[0] == '\0';
    out.reason = out.needs_polish ? "" : strict;
  };
  judge();
  // Refused, or valid only once polished, with a second peak in the running: align that rival
  // too and judge again.
  if ((out.reason[0] != '\0' || out.needs_polish) && options_.verify_rival_peak && out.searched &&
      out.peak_ratio > options_.max_distinct_peak_ratio) {
    CompareWithRival(levels, search_level, prior, hit, &pose, &out, &final_fit);
    judge();
  }
  out.valid = out.reason[0] == '\0';
  if (out.valid && full_resolution && levels[0].points.size() >= 3) {
    RefineAtFullResolution(levels[0], prior, pose, &out);
  }
  return out;
}

// Aligns from `pose` at level `coarsest` down to the finest level, each level starting from the
// last one's pose; the finest level's fit in `final_fit` and its figures in `out`.
Pose2 DirectAligner::AlignLevels(const std::vector<Level>& levels, int coarsest,
                                 const PoseWithCovariance& prior, Pose2 pose, DirectAlignment* out,
                                 Linearization* final_fit) const {
  for (int l = coarsest; l >= finest_level_; --l) {
    const Level& level = levels[l];
    if (level.points.size() < 3) continue;
    // Coarser levels only need to hand the next level a start well inside its basin.
    const double tolerance = options_.converged_px * (l == finest_level_ ? 1.0 : 5.0);
    // Only the two finest levels' fits are judged: the others need no linearization at the end.
    if (l > finest_level_ + 1) {
      pose = AlignLevel(level, prior, pose, tolerance, &out->iterations, nullptr);
      continue;
    }
    pose = AlignLevel(level, prior, pose, tolerance, &out->iterations, final_fit);
    out->points = final_fit->points;
    out->inlier_fraction = final_fit->inlier_fraction;
    out->correlation = final_fit->correlation;
    // The verdict's coarse correlation is the level above the finest, where its thresholds were
    // measured, also when a wide prediction moved the search coarser (where a weak floor keeps
    // less texture: painted pavement at 640×480 under `all`, right fits correlating 0.23 at the
    // 80×60 search level and 0.38–0.40 at 160×120).
    if (l == finest_level_ + 1 || l == coarsest) out->coarse_correlation = final_fit->correlation;
  }
  return pose;
}

// The search's second peak aligned like the best one: the search level's surface cannot tell a
// look-alike from the floor's own place under a wide prediction (painted lines, at 320×240, peak
// ratios 0.5–0.9 where the aligned fits correlated 0.37–0.60 and their rivals 0.08–0.16). The
// peak ratio becomes the aligned rivals' correlation ratio when that is lower; a rival that aligns
// better takes the best one's place. A rival that converges onto the best fit is the same place,
// one peak split in two at the search level (a mark or a shadow across it): the search's next
// peak outside both is then the alternative (measured at 320×240 on painted pavement 001 under
// `marks`: a fit correlating 0.41, 0.02 px from the truth once polished, was refused at peak ratio
// 0.39 although its rival converged onto it; the next peak was at 0.22).
void DirectAligner::CompareWithRival(const std::vector<Level>& levels, int search_level,
                                     const PoseWithCovariance& prior, const SearchHit& hit,
                                     Pose2* pose, DirectAlignment* out,
                                     Linearization* final_fit) const {
  DirectAlignment rival = *out;
  Linearization rival_fit;
  const Pose2 rival_pose =
      AlignLevels(levels, search_level, prior, hit.rival_pose, &rival, &rival_fit);
  out->iterations = rival.iterations;
  const double apart_px = Difference(rival_pose, *pose).head<2>().norm() / camera_.resolution_m;
  if (apart_px <= options_.rival_same_place_px) {
    out->peak_ratio = std::min(out->peak_ratio, hit.third_ratio);
    return;
  }
  if (rival.correlation > out->correlation) {
    std::swap(rival, *out);
    std::swap(rival_fit, *final_fit);
    *pose = rival_pose;
  }
  if (out->correlation <= 0.0) return;
  out->peak_ratio = std::min(out->peak_ratio, std::max(0.0, rival.correlation) / out->correlation);
}

// A validated fit of a small frame, refined at full resolution: kept when it converges within half
// a pixel of the validated pose and its own correlation holds (the validation stays the coarser
// level's, where lens blur and noise differ less from the mosaic).
void DirectAligner::RefineAtFullResolution(const Level& level, const PoseWithCovariance& prior,
                                           const Pose2& pose, DirectAlignment* out) const {
  Linearization fit;
  int iterations = 0;
  const Pose2 refined = AlignLevel(level, prior, pose, options_.converged_px, &iterations, &fit,
                                   options_.fit_contrast);
  DirectAlignment candidate = *out;
  Combine(fit, prior, refined, &candidate);
  const Eigen::Vector3d moved = Difference(candidate.posterior.pose, out->posterior.pose);
  const double moved_px = moved.head<2>().norm() / camera_.resolution_m;
  out->iterations += iterations;
  if (candidate.reason[0] != '\0' || moved_px > 0.5 || fit.correlation < options_.min_correlation) {
    return;
  }
  out->posterior = candidate.posterior;
  out->measurement = candidate.measurement;
  out->sigma_px = candidate.sigma_px;
  out->prior_chi2 = candidate.prior_chi2;
}

// Why a fit cannot be trusted, or "" (see DirectAlignOptions' validation).
// `min_significant_correlation`: the correlation a significant peak's fit needs.
const char* DirectAligner::Verdict(const DirectAlignment& fit, bool prediction_confirms,
                                   double min_significant_correlation) const {
  const DirectAlignOptions& o = options_;
  if (fit.reason[0] != '\0') return fit.reason;
  if (fit.sigma_px > o.max_sigma_px) return "weakly constrained";
  if (fit.correlation < o.min_correlation) return "no correlation at the finest level";
  const double ratio = fit.searched ? fit.peak_ratio : 0.0;
  const bool clear_peak = fit.searched && fit.coarse_correlation >= o.min_strong_correlation &&
                          fit.peak_ratio <= o.max_clear_peak_ratio;
  // A significant peak locates the frame; the aligned frame must also correlate clearly, or the
  // fit may sit in the right basin but off by a pixel (measured: plain polished concrete at
  // 320×240 under `all`, peaks at 9–15 standard deviations, fits correlating 0.16–0.27, 0.1–1.3 px
  // off with a claimed sigma of 0.03–0.15 px). Align asks for the polish's confirmation instead
  // down to min_polished_significant_correlation.
  const bool significant = fit.searched && fit.peak_z >= o.min_significant_peak_z &&
                           fit.correlation >= min_significant_correlation;
  const bool distinct =
      clear_peak || significant ||
      (fit.coarse_correlation >= o.min_distinct_correlation && ratio <= o.max_distinct_peak_ratio);
  const double max_chi2 = distinct ? o.max_distinct_prior_chi2 : o.max_prior_chi2;
  // Strong at the search level, or at the finest level where a weak floor's texture lives (a
  // coarse search peak that is not ambiguous, then a high correlation once aligned).
  const bool strong = (significant && fit.prior_chi2 <= max_chi2) ||
                      (fit.coarse_correlation >= o.min_strong_correlation &&
                       ratio <= o.max_strong_peak_ratio && fit.prior_chi2 <= max_chi2) ||
                      (fit.correlation >= o.min_fine_strong_correlation &&
                       ratio <= o.max_weak_peak_ratio && fit.prior_chi2 <= o.max_prior_chi2);
  const bool weak = prediction_confirms && fit.coarse_correlation >= o.min_weak_correlation &&
                    ratio <= o.max_weak_peak_ratio && fit.prior_chi2 <= o.max_weak_prior_chi2;
  if (strong || weak) return "";
  if (fit.prior_chi2 > max_chi2) return "inconsistent with the prediction";
  if (ratio > o.max_weak_peak_ratio) return "ambiguous coarse peak";
  return fit.coarse_correlation < o.min_weak_correlation
             ? "low correlation"
             : "weak fit the prediction does not confirm";
}

namespace {

// The worst-direction position sigma of a covariance of q.
double WorstPositionSigma(const Eigen::Matrix3d& cov_q) {
  return std::sqrt(
      std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov_q.topLeftCorner<2, 2>())
                        .eigenvalues()
                        .maxCoeff()));
}

}  // namespace

// The image's own estimate and covariance from the finest level's linearization (see
// ImageCovariance in tracking/dense_linearization.h), fused with the prediction.
void DirectAligner::Combine(const Linearization& fit, const PoseWithCovariance& prior,
                            const Pose2& pose, DirectAlignment* out) const {
  const double res = camera_.resolution_m;
  const Eigen::Matrix3d to_px = Eigen::Vector3d(res, res, 1.0).asDiagonal();
  Eigen::LDLT<Eigen::Matrix3d> h(fit.h);
  if (fit.points < 3 || h.info() != Eigen::Success || !(h.vectorD().array() > 0).all()) {
    out->reason = "no image information";
    out->posterior = prior;
    out->sigma_px = 1e9;
    return;
  }
  const Eigen::Matrix3d h_inv = h.solve(Eigen::Matrix3d::Identity());
  const Eigen::Vector3d q_image = -h_inv * fit.g;  // image-only optimum, from `pose`
  const Eigen::Matrix3d cov_q = ImageCovariance(fit, h_inv);
  const Eigen::Matrix3d info_q = cov_q.inverse();
  const Eigen::Matrix3d bs = RotationBlock(pose) * to_px;
  const Eigen::Matrix3d prior_information = prior.covariance.inverse();
  const Eigen::Matrix3d hp = bs.transpose() * prior_information * bs;
  const Eigen::Vector3d gp = bs.transpose() * prior_information * Difference(pose, prior.pose);
  const Eigen::Vector3d q = (info_q + hp).ldlt().solve(info_q * q_image + gp);
  // Map covariance of the image estimate: map delta = −B·S·q.
  const Eigen::Matrix3d image_cov = bs * cov_q * bs.transpose();
  out->measurement = {ApplyStep(pose, q_image, res), image_cov};
  out->posterior = {ApplyStep(pose, q, res), (image_cov.inverse() + prior_information).inverse()};
  out->sigma_px = WorstPositionSigma(cov_q);
  // The two differ only for a whole-frame fit (ImageCovariance).
  out->comparison_sigma_px = fit.robust_curvature_summed
                                 ? WorstPositionSigma(SandwichPlusIndependent(fit, h_inv))
                                 : out->sigma_px;
  const Eigen::Vector3d innovation = Difference(out->measurement.pose, prior.pose);
  out->prior_chi2 = innovation.dot((prior.covariance + image_cov).ldlt().solve(innovation));
  if (!out->posterior.pose.ToVector().allFinite() || !out->posterior.covariance.allFinite()) {
    out->reason = "diverged";
  }
}

}  // namespace fleetloc::tracking
