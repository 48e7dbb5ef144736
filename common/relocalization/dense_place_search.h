// Dense global place search (issue 17): where a floor has too few distinctive features for the
// place index (plain or polished concrete, epoxy, upscaled photos) or dust hides them, the whole
// camera frame, reduced to a coarse pyramid level and locally normalized (gain, bias, vignetting
// and uneven light removed; values clipped so dust and debris weigh little), is correlated with
// the whole normalized mosaic at that level at every heading (FFT correlation, masked to the
// rotated frame). The best peaks are refined one level finer over nearby headings and positions.
// The answer is a short list of camera poses with their correlations, best first, distinct from
// each other — the caller verifies them and refuses when the best does not clearly beat the
// second. Cost grows with the mosaic's area: meant for mosaics up to a few square metres (the
// options bound it). Pure: reads the mosaic through a RasterSource once, at construction.
#pragma once

#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "mosaic/raster_source.h"

namespace fleetloc::relocalization {

struct DensePlaceSearchOptions {
  // The refine level is the coarsest whose frame short side is >= this many pixels; the heading
  // search runs one level coarser.
  int min_short_side_px = 48;
  double heading_step_scale = 1.0;  // heading step = this / frame half-diagonal (search level px)
  // The sweep level's heading step is this many times the above (fewer headings swept), and the
  // refinement searches ± refine_heading_steps of the refine level's steps around a peak (the
  // default 2 covers twice the largest heading error of the default sweep).
  double sweep_heading_step_factor = 1.0;
  int refine_heading_steps = 2;
  // Search's sweep of the refine level itself (SweepLevel::kRefine) visits every this-many-th of
  // that level's headings; the refinement's ± refine_heading_steps must cover half of it
  // (checked).
  int refine_sweep_heading_stride = 1;
  int normalize_window_px = 7;  // local mean and deviation window at both levels, odd
  double clip = 2.5;            // normalized values are clipped to ±this
  int coarse_peaks = 12;        // distinct peaks of the heading search refined
  int max_peaks = 4;            // distinct refined poses returned
  // Mosaics whose refine level has more pixels are refused (the search would be too slow).
  double max_refine_level_mpx = 0.6;
  // Heading pairs of a sweep, refinements and alternative headings computed at once, each on
  // its own stripe of cv::parallel_for_ (so at most cv::getNumThreads() at a time). Results do
  // not depend on it: every stripe fills its own slot and the slots are read in heading order.
  // At most 2: the vehicles' CPUs are small. 1 by default: on a loaded 2-core machine the
  // stripes wait for each other at every pair of headings and 2 measured slower (benchmarks.md,
  // session 32); on an idle one 2 cut the attempts' p95 by 35–40 % (320×240 plain concrete,
  // session 46), and the tracker agent (relocalize_threads) and the bench use 2.
  int threads = 1;
};

// Flat range checks; InvalidInput naming the field.
Status Validate(const DensePlaceSearchOptions& options);

struct DensePeak {
  geometry::Pose2 camera_in_map;  // camera_ground in map
  double correlation = 0.0;       // masked normalized cross-correlation at the refine level
};

class DensePlaceSearch {
 public:
  // Reads the whole mosaic at the two levels the camera's frames need and normalizes it.
  // InvalidInput for bad options, a camera whose resolution differs from the mosaic's, or a mosaic
  // too large for the options' bound (the message says how large).
  static Result<std::unique_ptr<DensePlaceSearch>> Create(mosaic::RasterSource& mosaic,
                                                          const geometry::CameraModel& camera,
                                                          const DensePlaceSearchOptions& options);

  // The heading sweep of `frame` (CV_8UC1, the camera's size) at the coarse level (or, slower,
  // at the refine level), one heading at a time, in no set order (k and k + heading_steps / 2,
  // its turn by π, are computed together): heading k of heading_steps(level) is
  // sweep_heading_rad(k, level); `scores` covers the padded mosaic at that level, its pixel (x, y)
  // the masked correlation with the frame's centre at continuous coordinates (x, y) (0 where the
  // frame does not fit); `suppress_px` the radius within which another maximum is the same peak.
  // Search runs on the coarse one; the multi-frame search on either.
  enum class SweepLevel { kCoarse, kRefine };
  struct SweepMap {
    int k = 0;
    double theta = 0;
    const cv::Mat& scores;
    int suppress_px = 2;
  };
  // `stride` > 1 visits every stride-th heading pair only (k a multiple of it, and k + steps / 2).
  void Sweep(const cv::Mat& frame, const std::function<void(const SweepMap&)>& visit,
             SweepLevel level = SweepLevel::kCoarse, int stride = 1) const;
  // One heading of a sweep: `frame` reduced to the level and normalized, then its map at any θ
  // (the SweepMap layout; returns its suppress_px, 0 when the frame does not fit the mosaic).
  cv::Mat NormalizedFrame(const cv::Mat& frame, SweepLevel level) const;
  int ScoresAt(const cv::Mat& normalized, double theta, SweepLevel level, cv::Mat* centred) const;
  // ScoresAt, and the map at θ + π into *turned (null: not computed) for a little more than the
  // cost of one (imaging::MaskedCorrelator::MatchWithTurned).
  int ScoresAtAndTurned(const cv::Mat& normalized, double theta, SweepLevel level, cv::Mat* centred,
                        cv::Mat* turned) const;
  // Continuous pixel coordinates of a map point at the level (the SweepMap layout).
  Eigen::Vector2d SweepPixel(const Eigen::Vector2d& map_xy, SweepLevel level) const;

  // Up to max_peaks distinct poses of `frame` (CV_8UC1, the camera's size: checked), best first.
  // `also`, when given, sees every map of the sweep (the multi-frame search reuses it). `sweep`:
  // the level whose heading sweep gives the peaks Refine refines; kRefine sweeps the refine level
  // itself, every `refine_stride`-th of its headings (0: refine_sweep_heading_stride; at every
  // one, about 8 times the coarse sweep's work), for a floor whose detail is gone one level
  // coarser.
  std::vector<DensePeak> Search(const cv::Mat& frame,
                                const std::function<void(const SweepMap&)>& also = {},
                                SweepLevel sweep = SweepLevel::kCoarse,
                                int refine_stride = 0) const;

  int heading_steps(SweepLevel level = SweepLevel::kCoarse) const;  // even
  // A sweep's work: the level's padded pixels × the heading pairs it transforms (with `stride`).
  double SweepWork(SweepLevel level, int stride = 1) const;
  double sweep_heading_rad(int k, SweepLevel level = SweepLevel::kCoarse) const;
  cv::Size sweep_size(SweepLevel level = SweepLevel::kCoarse) const;
  double sweep_resolution_m(SweepLevel level = SweepLevel::kCoarse) const;
  // The camera pose whose frame centre is at continuous coordinates `at` of the level, heading θ.
  geometry::Pose2 SweepPose(const Eigen::Vector2d& at, double theta,
                            SweepLevel level = SweepLevel::kCoarse) const;

  // The two best places of a sweep map (scores with the SweepMap layout; overwritten) at heading
  // θ, appended to *peaks.
  void AppendCoarsePeaks(cv::Mat scores, double theta, int suppress_px,
                         std::vector<DensePeak>* peaks,
                         SweepLevel level = SweepLevel::kCoarse) const;

  // The best pose one level finer within ± refine_heading_steps heading steps and ± radius_px
  // pixels of `coarse` (4: a coarse peak's pixel is two of the finer level's; a peak of the
  // refine level's own sweep needs less).
  DensePeak Refine(const cv::Mat& frame, const DensePeak& coarse, int radius_px = 4) const;

  // The best place distinct from `first` (the first frame's camera) for the newest of `frames`
  // (frame i's camera is first ⊕ motions[i], motions[0] the identity; the same count), with the
  // frames' mean correlation summed at the refine level over ±2 of its heading steps around
  // first's heading, first's own place blanked: the best distinct alternative of a pose, measured
  // at the level the pose was (on weak floors a twin need not be among the coarse peaks).
  DensePeak Alternative(const std::vector<cv::Mat>& frames,
                        const std::vector<geometry::Pose2>& motions,
                        const geometry::Pose2& first) const;

  // How well `frame` fits its camera at `own` and at `rival` where the mosaic's views from the
  // two differ: the refine level's normalized mosaic seen from each pose, in the normalized
  // frame's pixels; the pixels inside the mosaic whose local mean squared difference (the
  // normalization's window) reaches differing_mean_square; the masked correlation of the frame
  // with each view there (Σ F·V / √(Σ F² · Σ V²)), and those pixels' share of the frame. A place
  // whose twin is a copy of part of the frame (a cloned patch) is told from it by the rest; an
  // exact twin leaves nothing (share 0, correlations 0).
  struct TwinContrast {
    double own = 0, rival = 0, share = 0;
    int pixels = 0;  // where the views differ (share × the frame's pixels at the level)
  };
  TwinContrast ContrastTwins(const cv::Mat& frame, const geometry::Pose2& own,
                             const geometry::Pose2& rival,
                             double differing_mean_square = 0.5) const;

  // Whether `peak` is distinct (see below) from every one of `kept`; the best n of `peaks` that
  // are distinct from each other, best first.
  bool Distinct(const DensePeak& peak, const std::vector<DensePeak>& kept) const;
  std::vector<DensePeak> DistinctBest(std::vector<DensePeak> peaks, int n) const;
  const DensePlaceSearchOptions& options() const { return options_; }

  // Two peaks are distinct places when their positions differ by separation_m (a quarter of the
  // frame's short side, at least 4 refine-level pixels) or their headings by
  // heading_separation_rad (8 refine-level heading steps).
  double separation_m() const;
  double heading_separation_rad() const;
  int refine_level() const { return refine_level_; }
  std::size_t MemoryBytes() const;

 private:
  struct Level;
  DensePlaceSearch(const geometry::CameraModel& camera, const DensePlaceSearchOptions& options);
  std::vector<DensePeak> CoarsePeaks(const cv::Mat& frame,
                                     const std::function<void(const SweepMap&)>& also,
                                     SweepLevel sweep, int stride) const;
  const Level& LevelOf(SweepLevel level) const;

  geometry::CameraModel camera_;
  DensePlaceSearchOptions options_;
  int refine_level_ = 0;
  std::shared_ptr<const Level> coarse_, fine_;
};

// moved(c) = scores(c + d): a score map (the SweepMap layout) moved so that a frame whose centre
// is `d` (map metres) from another's lines up with it; pixels x right, y down (north-up raster).
cv::Mat ShiftedScores(const cv::Mat& scores, const Eigen::Vector2d& d, double resolution_m);

}  // namespace fleetloc::relocalization
