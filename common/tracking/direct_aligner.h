// Dense direct alignment of a whole camera frame against the normalized mosaic (issue 15): the
// frame's pyramid, locally normalized like the mosaic, is registered to the mosaic by robust
// inverse-compositional Gauss–Newton over the camera pose (SE(2)), coarse to fine, with the
// odometry prediction as a prior (a maximum a posteriori fit: an iterated Kalman update whose
// measurement is every selected pixel). Tukey weights drop the pixels the mosaic does not explain
// (dust, debris, tyre marks, shadows); local normalization removes gain, bias, vignetting and
// uneven light. When the prediction is poor, an exhaustive correlation of the whole frame at the
// coarsest level finds the basin first. The result says whether it can be trusted, and why not.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "imaging/spectral_ncc.h"
#include "tracking/dense_linearization.h"
#include "tracking/noise_precision.h"
#include "tracking/normalized_mosaic.h"
#include "tracking/tracker_options.h"

namespace fleetloc::tracking {

struct DirectAlignment {
  bool valid = false;
  const char* reason = "";                   // why not valid ("" when valid)
  geometry::PoseWithCovariance posterior;    // camera_ground in map: prior and image combined
  geometry::PoseWithCovariance measurement;  // the image alone (covariance of the image term)
  double correlation = 0.0;                  // weighted NCC at the finest level
  double coarse_correlation = 0.0;  // weighted NCC at the level above the finest (or the search's)
  double inlier_fraction = 0.0;     // at the finest level
  double peak_ratio = 0.0;          // of the coarse search (0 when none ran)
  // The search peak's correlation above the rest of the search surface, in its standard
  // deviations (0 when no search ran).
  double peak_z = 0.0;
  double prior_chi2 = 0.0;
  double sigma_px = 0.0;  // image-only worst-direction position sigma, level-0 px
  // The same from h⁻¹·M·h⁻¹ + σ²·h⁻¹, which the polish's choices compare (SandwichPlusIndependent
  // in tracking/dense_linearization.h).
  double comparison_sigma_px = 0.0;
  double view_blur_px = 0.0;  // the polish's estimate of the frame's blur against the view
  int window_px = 0;          // the polish's normalization window (level-0 px)
  bool unsmoothed = false;    // a level-0 polish normalized without the matching's smoothing
  ResidualNoise noise;        // the residual noise the polish weighed its pixels by
  int points = 0;             // pixels used at the finest level
  int iterations = 0;         // Gauss–Newton iterations over all levels
  bool searched = false;      // the coarse exhaustive search ran
  int searches = 0;           // how many times (one per heading tried)
  // Valid only once the full-resolution polish confirms it (a significant peak whose aligned
  // frame correlates below min_significant_correlation; see DirectAlignOptions).
  bool needs_polish = false;
};

// What the polish models of the camera beyond the frame itself: the frame's blur against the
// view and its residual noise. Both are estimated from the frame when absent; both change slowly,
// so a caller tracking a run estimates them every few frames (MosaicTracker, with
// view_blur_every_frames).
struct PolishModel {
  double view_blur_px = -1.0;          // < 0: estimated
  std::optional<ResidualNoise> noise;  // absent: fitted (when direct.noise_model)
  // The normalization window above level 0 (level-0 px); < 0: the more precise of the mosaic's
  // and direct.polish_wide_window_px.
  int window_px = -1;
  // At level 0, whether the frame and the view are normalized without the matching's smoothing
  // (match_smoothing_sigma_px); absent: the more precise
  // (direct.polish_unsmoothed_max_sigma_ratio).
  std::optional<bool> unsmoothed;
};

// How a polish normalizes the frame and the view: over `window_px` (level-0 px), and at level 0
// with the matching's smoothing (from the mosaic's normalized tiles) unless `unsmoothed`.
struct PolishNormalization {
  int window_px = 0;
  bool unsmoothed = false;
};

class DirectAligner {
 public:
  // `mosaic` must outlive the aligner.
  DirectAligner(const DirectAlignOptions& options, const geometry::CameraModel& camera,
                NormalizedMosaic* mosaic);

  // Aligns `frame` (CV_8UC1, camera size) given the prediction `prior` (camera_ground in map)
  // starting from `start` (the prior's pose, or a better guess such as a template fit).
  // `prediction_confirms`: the prediction comes from a frame that was itself located, so a weak
  // fit close to it may be trusted; false after coasting or a loss, where only a strong fit is.
  // `refine_only`: `start` is already within a fraction of a pixel (a template fit): only the
  // finest level is aligned, with no search.
  DirectAlignment Align(const cv::Mat& frame, const geometry::PoseWithCovariance& prior,
                        const geometry::Pose2& start, bool prediction_confirms = true,
                        bool refine_only = false) const;

  // The final refinement of a fit already within a fraction of a pixel (a template fit, or a
  // validated dense fit that ended above level 0): a few Gauss–Newton steps over every pixel of
  // the frame at full resolution, with the same robust weights, prior and sandwich covariance.
  // Valid when it moved at most max_polish_shift_px, still correlates and pins the position; the
  // validation of the pose itself stays the caller's (the fit it starts from). `frame`: the
  // camera's frame, or already its pyramid level `level` (each level area-averaged from the last,
  // as cv::resize INTER_AREA halves). The view is blurred by model.view_blur_px, or (< 0) by the
  // frame's blur estimated here when max_view_blur_px > 0; the pixels are weighed by model.noise,
  // or by the noise fitted here. The result holds both as used. `confirming`: the fit is valid
  // only once polished (DirectAlignment::needs_polish), and gets confirm_polish_iterations steps.
  // `level`: the pyramid level it works at (< 0: PolishLevel()). Above level 0 the frame and the
  // view are normalized over model.window_px, or polished over both candidate windows and the
  // more precise fit taken (see DirectAlignOptions::polish_wide_window_px). At level 0 they are
  // normalized with the matching's smoothing or without it as model.unsmoothed says, or both ways
  // and the more precise fit taken (DirectAlignOptions::polish_unsmoothed_max_sigma_ratio).
  DirectAlignment Polish(const cv::Mat& frame, const geometry::PoseWithCovariance& prior,
                         const geometry::Pose2& start, const PolishModel& model = {},
                         bool confirming = false, int level = -1) const;

  // Levels of the frame pyramid this camera uses (coarsest = count − 1).
  int levels() const { return levels_; }
  // The pyramid level the polish works at (direct.polish_max_level_pixels).
  int PolishLevel() const { return PolishLevel(options_.polish_max_level_pixels); }
  // The pyramid level the alignment (Align) ends at.
  int FinestLevel() const { return finest_level_; }
  // The finest level whose frame has at most `max_level_pixels` (0: level 0).
  int PolishLevel(int max_level_pixels) const;

 private:
  struct Level;
  struct MosaicBlock;
  using Source = std::unique_ptr<MosaicBlock>;
  // A linearization at a pose with a residual scale (≤ 0: estimate) and gain (≤ 0: estimate).
  using LinearizeAt =
      std::function<Linearization(const geometry::Pose2&, double sigma, double gain)>;
  // The frame pyramid up to `coarsest`, normalized and with pixels chosen from finest_level_ up.
  std::vector<Level> BuildLevels(const cv::Mat& frame, int finest, int coarsest) const;
  geometry::Pose2 AlignLevel(const Level& level, const geometry::PoseWithCovariance& prior,
                             geometry::Pose2 pose, double tolerance_px, int* iterations,
                             Linearization* final_fit, bool fit_gain = false) const;
  void RefineAtFullResolution(const Level& level, const geometry::PoseWithCovariance& prior,
                              const geometry::Pose2& pose, DirectAlignment* out) const;
  geometry::Pose2 GaussNewton(const LinearizeAt& linearize, int level, int max_iterations,
                              const geometry::PoseWithCovariance& prior, geometry::Pose2 pose,
                              double tolerance_px, int* iterations, Linearization* final_fit,
                              bool fit_gain, double final_at_start_px = -1.0) const;
  // The maximum a posteriori step (level-0 px, px, rad) from `lin` at `pose` under `prior`, with
  // `lin.sigma` as the residual scale, and how far it moves the level's pixels at most.
  Eigen::Vector3d MapStep(const Linearization& lin, const geometry::Pose2& pose,
                          const geometry::PoseWithCovariance& prior) const;
  double StepPx(const Eigen::Vector3d& q, int level) const;
  std::vector<cv::Range> SpansInMosaic(const geometry::Pose2& pose, const cv::Rect& inner,
                                       int level) const;
  Source ReadSource(const Level& level, const geometry::Pose2& pose) const;
  struct LevelWarp;
  Linearization Linearize(const Level& level, const MosaicBlock& source,
                          const geometry::Pose2& pose, double sigma, double gain,
                          PointViews* views) const;
  void Combine(const Linearization& fit, const geometry::PoseWithCovariance& prior,
               const geometry::Pose2& pose, DirectAlignment* out) const;
  int SearchLevel(double sigma_px) const;
  const char* Verdict(const DirectAlignment& fit, bool prediction_confirms,
                      double min_significant_correlation) const;
  DirectAlignment PolishOverWindow(const cv::Mat& frame, const geometry::PoseWithCovariance& prior,
                                   const geometry::Pose2& start, const PolishModel& model,
                                   bool confirming, int level,
                                   PolishNormalization normalization) const;
  void FinishPolish(const Linearization& fit, const geometry::PoseWithCovariance& prior,
                    const geometry::Pose2& start, const geometry::Pose2& pose,
                    DirectAlignment* out) const;
  const char* PolishRefusal(const DirectAlignment& polished, const Linearization& fit,
                            const geometry::Pose2& pose, const geometry::PoseWithCovariance& prior,
                            const geometry::Pose2& start) const;
  // The search's best peak, and the best outside its exclusion radius (the rival); the best
  // outside both exclusion radii, as a share of the best peak (third_ratio).
  struct SearchHit {
    geometry::Pose2 pose, rival_pose;
    double correlation = 0.0, peak_ratio = 1.0, peak_z = 0.0, third_ratio = 1.0;
  };
  SearchHit CoarseSearch(const Level& level, const geometry::PoseWithCovariance& prior,
                         const geometry::Pose2& start, DirectAlignment* out) const;
  void CompareWithRival(const std::vector<Level>& levels, int search_level,
                        const geometry::PoseWithCovariance& prior, const SearchHit& hit,
                        geometry::Pose2* pose, DirectAlignment* out,
                        Linearization* final_fit) const;
  geometry::Pose2 AlignLevels(const std::vector<Level>& levels, int coarsest,
                              const geometry::PoseWithCovariance& prior, geometry::Pose2 pose,
                              DirectAlignment* out, Linearization* final_fit) const;
  SearchHit SearchAt(const Level& level, const imaging::SpectralNcc& frame_ncc,
                     const geometry::Pose2& pose, int r) const;
  SearchHit ClimbHeadings(const Level& level, const imaging::SpectralNcc& frame_ncc,
                          const geometry::Pose2& start, int r, double step, int steps,
                          const SearchHit& at_start, int* searches) const;
  SearchHit ClimbHeadingsOverWholeWindows(const Level& level, const imaging::SpectralNcc& frame_ncc,
                                          const geometry::Pose2& start, int r, double step,
                                          int steps, const SearchHit& at_start,
                                          std::map<int, SearchHit> hits, int* searches) const;
  SearchHit ClimbHeadingsFromTentativePeak(const Level& level,
                                           const imaging::SpectralNcc& frame_ncc,
                                           const geometry::Pose2& start, int r, double step,
                                           int steps, const SearchHit& at_start,
                                           int* searches) const;
  // The end of a heading climb probed near a peak (ClimbProbedHeadings): the heading step (0: the
  // climb stayed), the probe's peak in its ±heading_probe_px surface, its pose and correlation.
  struct ProbedHeading {
    int k = 0;
    cv::Point at;
    geometry::Pose2 pose;
    double correlation = 0.0;
  };
  ProbedHeading ClimbProbedHeadings(const Level& level, const imaging::SpectralNcc& frame_ncc,
                                    double step, int steps, const SearchHit& at_start) const;
  static SearchHit TurnedHit(const SearchHit& at_start, const geometry::Pose2& pose,
                             double correlation);
  geometry::Pose2 PoseAtShift(const Level& level, const geometry::Pose2& pose,
                              const cv::Point& shift) const;
  static cv::Rect InnerRect(const Level& level);

  DirectAlignOptions options_;
  geometry::CameraModel camera_;
  NormalizedMosaic* mosaic_;
  int levels_ = 1;
  int finest_level_ = 0;  // where the alignment ends
};

}  // namespace fleetloc::tracking
