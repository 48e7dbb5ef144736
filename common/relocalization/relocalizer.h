// Global relocalization (issue 5): the camera pose from one rectified frame with no prior,
// anywhere on the mosaic. The frame's features are matched against the place index, each match
// votes for a camera pose, votes are clustered (heading, then mean shift over position) and
// fitted into a few candidates, and each candidate is verified by one cycle of the mosaic tracker
// (the same coarse-to-fine correlation and Kalman update as tracking) started from it with a
// small covariance; the pose the tracker confirms with most inliers, unambiguously, is returned.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "mosaic/raster_source.h"
#include "relocalization/dense_place_search.h"
#include "relocalization/place_index.h"
#include "relocalization/pose_votes.h"
#include "relocalization/self_similarity.h"
#include "relocalization/trajectory_place_search.h"
#include "tracking/mosaic_tracker.h"
#include "tracking/tracker_options.h"

namespace fleetloc::relocalization {

struct RelocalizerOptions {
  int query_cell_px = 16;            // frame feature buckets (index level pixels)
  int query_features_per_cell = 3;   // strongest frame features per bucket
  int neighbours = 2;                // index features matched per frame feature
  int max_descriptor_distance = 70;  // Hamming distance (of 256 bits) a match may have
  VoteClusterOptions clustering;
  // Verification: candidates are tried best-supported first, up to max_verified, until one's
  // tracker cycle keeps confident_inliers correspondences; then its best distinct alternative
  // (the next candidate distinct from it) is verified too, every time. The one with most inliers
  // wins — if it has min_verified_inliers and no other verified, distinct pose comes within
  // ambiguity_margin_inliers of it (a floor that repeats itself confirms its twin as well; one
  // that partly repeats itself confirms a wrong pose with the templates on the repeated part).
  // With the dense search, a pose the features found is also checked against its best distinct
  // dense alternative (DensePlaceSearch::Alternative): when that reaches dense_max_second_ratio
  // of the pose's own correlation, a tracker cycle verifies it, and the pose is refused as
  // ambiguous when the cycle confirms the alternative within ambiguity_margin_inliers, or when
  // the alternative reaches twin_ratio of the pose's own correlation (a twin the tracker missed).
  // Measured on a photo repeated between two other strips (relocalizer_test): a frame across the
  // copies' border, whose twin shares about half of it, 0.53–0.65 of the pose, its twin not
  // confirmed by the tracker; an exact twin correlates like the pose itself.
  int max_verified_candidates = 6;
  int confident_inliers = 26;
  int min_verified_inliers = 18;
  int ambiguity_margin_inliers = 8;
  double twin_ratio = 0.8;
  double verify_sigma_m = 0.002;  // candidate covariance the tracker searches (1-sigma)
  double verify_sigma_rad = 0.01;
  tracking::TrackerOptions tracker;  // the verifying tracker cycle
  // Dense place search (issue 17), tried when the features give no pose and the mosaic is small
  // enough for it (DensePlaceSearchOptions::max_refine_level_mpx): its best peak is verified by a
  // tracker cycle and accepted only when it correlates at least dense_min_correlation and the
  // best distinct peak reaches at most dense_max_second_ratio of it (a self-similar floor: refused
  // as ambiguous). Measured on the stress floors' tuning split: right peaks 0.25–0.7 with seconds
  // at most 0.35 of them; a floor photo with cloned patches gave a wrong best at 0.60 with its
  // second at 0.50 (0.83 of it).
  bool dense_search = true;
  DensePlaceSearchOptions dense;
  double dense_min_correlation = 0.2;
  double dense_max_second_ratio = 0.6;
  // A dense best whose rivals reach dense_max_second_ratio of it is still accepted (then verified
  // by the tracker) when it is told from each of them where the mosaic's views from the two
  // differ (DensePlaceSearch::ContrastTwins): those pixels make at least twin_contrast_min_share
  // of the frame, the best correlates there at least the gate's minimum, the rival at most
  // twin_contrast_max_ratio of it, and the best beats the rival by twin_contrast_min_sigmas
  // standard deviations of the correlation of unrelated images over those N pixels, 2 / √N (the
  // normalized levels' neighbouring pixels are alike over about 2 px: N / 4 independent ones).
  // A floor photograph with a cloned patch has a twin for every frame partly over the patch; the
  // rest of the frame tells them apart. An exact twin leaves no such pixels and stays ambiguous.
  // Measured on the stress bench at 320×240 (worn asphalt g8's cloned patch; plain concrete b1
  // and r1, whose similar places look alike over part of the frame): 40 poses accepted, all
  // right, the best 0.34–0.72 where the views differ (18–64 % of the frame), the rival 0.02–0.22
  // and at most 0.38 of it.
  bool twin_contrast = true;
  double twin_contrast_min_share = 0.15;
  double twin_contrast_max_ratio = 0.5;
  double twin_contrast_min_sigmas = 4;
  // The fine dense search (issue 17, dust): when the dense search finds nothing and saw no clear
  // twin, the same search one pyramid level finer (refine level 2 mm/px at 640×480 instead of 4)
  // at twice the heading step, under the same gate but its own minimum correlation. Under 30 %
  // dust on the tuning polished concrete, painted pavement and plain concrete b1 at 640×480, the
  // sweep at 8 mm/px misses the true place (found in 1 of 20 frames; wrong bests 0.06–0.17,
  // their second 0.78–1.0 of them); at 4 mm/px the best is the truth in 20 of 25 (0.19–0.36, its
  // second 0.11–0.50 of it; where it misses, a noise peak at 0.05 with its second at 0.73–1.0 of
  // it); 320×240 polished concrete at 2 mm/px: 10 of 10 at 0.15–0.20 (docs/benchmarks.md, issue
  // 17, 2026-11-26). Off (not built) when the mosaic is too large for these options; it costs
  // several times the dense search. Its minimum correlation: wrong bests at these levels reach
  // 0.03–0.06; under every effect at once (`all`) the right bests on 320×240 polished concrete
  // correlate 0.10–0.15 with seconds at 0.3–0.45 of them, which 0.12 refused in 3 of 10 trials
  // (docs/benchmarks.md, session 45).
  bool dense_fine_search = true;
  DensePlaceSearchOptions dense_fine{
      .min_short_side_px = 96, .heading_step_scale = 2.0, .refine_sweep_heading_stride = 3};
  double dense_fine_min_correlation = 0.09;
  // When the fine dense search finds nothing and saw no clear twin, its refine level swept
  // itself at every 2nd or 3rd of that level's headings (DensePlaceSearch::Search with
  // SweepLevel::kRefine and a stride, see below; all of them took 1.3–2.4 s an attempt at
  // 1280×1024), under the same gate. At 1280×1024 (sweep 8 mm/px, refine 4 mm/px) on polished
  // concrete 024 under dust and painted pavement 001 under every effect, the truth refined at 4
  // mm/px correlates 0.11–0.18 where the 8 mm/px sweep's best is a noise peak at 0.04–0.06: the
  // coarser sweep never offered it (docs/benchmarks.md, issue 17, session 48).
  bool dense_fine_refine_sweep = true;
  // It runs only when the attempt's time so far plus its predicted time (the fine search's own,
  // scaled by SweepWork) stays within this: on a floor twice as large (the stress bench's repeated
  // layouts) it would take the attempt past 1 s for a pose that is then refused as ambiguous.
  // It sweeps at the finest stride from dense_fine_refine_sweep_finest_stride to
  // dense_fine.refine_sweep_heading_stride that fits: on painted pavement 001 at 1280×1024 under
  // dust and under every effect, every 3rd heading missed the truth in all three frames of one
  // trial and the first two of another; every 2nd found both on their first frame
  // (docs/benchmarks.md, session 51).
  double dense_attempt_budget_ms = 800;
  int dense_fine_refine_sweep_finest_stride = 2;
  // Multi-frame relocalization (issue 17; Relocalize with odometry): when one frame gives no pose,
  // the dense heading sweeps of up to trajectory_frames frames (1: off) whose cameras stay within
  // trajectory_max_travel_m of the first are combined (TrajectoryPlaceSearch); the newest frame's
  // best combined pose is verified by a tracker cycle and accepted under the gate below. Off when
  // the summed sweep would need more than trajectory_max_mb.
  int trajectory_frames = 1;
  bool trajectory_refine_level = false;  // sum the sweeps at the refine level (slower)
  double trajectory_max_travel_m = 1.0;
  double trajectory_min_correlation = 0.1;
  double trajectory_max_second_ratio = 0.6;
  double trajectory_max_mb = 64;
};

// Flat range checks (and the tracker's); InvalidInput naming the field.
Status Validate(const RelocalizerOptions& options);

struct Relocalization {
  bool found = false;
  geometry::PoseWithCovariance base_in_map;  // when found
  std::string reason;                        // when not found: why
  bool ambiguous = false;  // not found because a distinct place is (about) as good: a twin
  int frame_features = 0;
  int matches = 0;
  int candidates = 0;
  int verified = 0;           // tracker cycles run
  int templates = 0;          // correspondences the accepted tracker cycle measured
  int inliers = 0;            // of those, kept by its pose update
  int candidate_inliers = 0;  // feature inliers of the accepted candidate
  // The dense place search, when it ran: its best and second (distinct) peak's correlations.
  bool dense = false;
  double dense_best = 0, dense_second = 0;
  // The fine dense search, when it ran (after the dense search): its best and second peaks.
  bool dense_fine = false;
  double dense_fine_best = 0, dense_fine_second = 0;
  bool dense_fine_refine_sweep = false;  // the fine search swept its refine level (its peaks above)
  int dense_fine_refine_sweep_stride = 0;           // at every this-many-th heading
  double dense_fine_refine_sweep_predicted_ms = 0;  // when it was considered (run or not)
  // The multi-frame search, when it ran: frames combined, its best and second peaks (mean
  // correlations), and whether the accepted pose came from it.
  int trajectory_frames = 0;
  double trajectory_best = 0, trajectory_second = 0;
  bool from_trajectory = false;
  // The dense check of a pose the features found (see RelocalizerOptions): whether it ran, the
  // pose's own refine-level correlation, its best distinct alternative's, and the inliers of the
  // tracker cycle that confirmed the alternative (0: not run, or not confirmed); twin_ms is part
  // of verify_ms.
  bool twin_checked = false;
  double twin_own = 0, twin_correlation = 0;
  int twin_inliers = 0;
  // Dense rivals told apart from the best where the views differ (see twin_contrast), and the
  // contrast with the last one tried: the best's and the rival's correlation there, its share.
  int twins_told_apart = 0;
  DensePlaceSearch::TwinContrast twin_contrast;
  double detect_ms = 0, match_ms = 0, cluster_ms = 0, verify_ms = 0, dense_ms = 0;
  double trajectory_ms = 0, twin_ms = 0;
  double dense_fine_ms = 0;  // part of dense_ms
};

class Relocalizer {
 public:
  // `index` and `mosaic` must outlive the relocalizer and describe the same mosaic; `index` may be
  // null (a floor without features: the dense search alone). InvalidInput for bad options, a
  // camera whose resolution differs from the mosaic's, or no index and a mosaic too large for
  // the dense search.
  static Result<std::unique_ptr<Relocalizer>> Create(const PlaceIndex* index,
                                                     mosaic::RasterSource* mosaic,
                                                     const geometry::CameraModel& camera,
                                                     const RelocalizerOptions& options);

  // base_link's pose in map at the frame's time. InvalidInput for an empty frame, or one that is
  // not CV_8UC1 of the camera's size. found == false with a reason when no candidate verifies.
  Result<Relocalization> Relocalize(const cv::Mat& frame);
  // The same, and when that finds nothing, the frame joins the trajectory (a new one when it
  // already holds trajectory_frames frames or the camera moved beyond trajectory_max_travel_m)
  // and the trajectory's frames are searched together (from 2 frames on). `base_in_odom`:
  // base_link in odom at the frame's time. A found pose starts a new trajectory.
  Result<Relocalization> Relocalize(const cv::Mat& frame, const geometry::Pose2& base_in_odom);
  void ResetTrajectory();
  // Places a self-similarity report named (FindSelfSimilarity): a pose found with its camera
  // within half a frame's short side of one of them or of its twin is refused as ambiguous.
  void SetTwinPlaces(std::vector<SimilarPlace> places) { twin_places_ = std::move(places); }
  // The dense place search (null: off, or the mosaic is too large for it).
  const DensePlaceSearch* dense_search() const { return dense_.get(); }
  // Bytes the dense and the fine dense search hold (their normalized levels and the levels'
  // spectra), and the multi-frame search's summed sweeps while it holds frames; 0 for what is off.
  struct DenseMemory {
    std::size_t dense = 0, dense_fine = 0, trajectory = 0;
  };
  DenseMemory dense_memory() const;

 private:
  Relocalizer(const PlaceIndex* index, mosaic::RasterSource* mosaic,
              const geometry::CameraModel& camera, const RelocalizerOptions& options);
  std::vector<FeatureMatch> MatchFrame(const cv::Mat& frame, Relocalization* out) const;
  struct Verified {
    geometry::PoseWithCovariance base_in_map;
    int inliers = 0, templates = 0, candidate_inliers = 0;
  };
  // One tracker cycle from the candidate; nullopt when the tracker does not lock.
  std::optional<Verified> Verify(const cv::Mat& frame, const PoseCandidate& candidate);
  std::optional<Verified> Verify(const cv::Mat& frame, const PoseCandidate& candidate,
                                 double sigma_m, double sigma_rad);
  // The verified poses of the candidates, as the options' verification rule says.
  std::vector<Verified> VerifyCandidates(const cv::Mat& frame,
                                         const std::vector<PoseCandidate>& candidates,
                                         Relocalization* out);
  // Accepts the best of `verified` into *out, or sets the reason why none is accepted.
  void Choose(std::vector<Verified> verified, Relocalization* out) const;
  // Whether two base poses are distinct places for the verification (the clustering's radius and
  // heading tolerance).
  bool Distinct(const geometry::Pose2& a, const geometry::Pose2& b) const;
  // Refuses the pose found in *out as ambiguous when its best distinct dense alternative is as
  // good (see RelocalizerOptions).
  void CheckDenseTwin(const cv::Mat& frame, Relocalization* out);
  // The dense place search and the verification of its best peak, then the fine one when that
  // found nothing and saw no clear twin (see RelocalizerOptions).
  void DenseRelocalize(const cv::Mat& frame, Relocalization* out);
  // The fine dense search of `frame` with the peaks of the `sweep` level's heading sweep (of the
  // refine level: every `refine_stride`-th heading, 0 for the options').
  void FineRelocalize(const cv::Mat& frame, DensePlaceSearch::SweepLevel sweep, Relocalization* out,
                      int refine_stride = 0);
  // The finest heading stride at which the fine search's refine-level sweep fits the attempt's
  // budget (0: none does), `fine_ms` the fine search's own time and `dense_start` the dense
  // searches' start (see RelocalizerOptions).
  int RefineSweepStride(double fine_ms, std::chrono::steady_clock::time_point dense_start,
                        Relocalization* out) const;
  // Accepts the best of `peaks` (poses of `frame`'s camera, from `search`) when it correlates
  // min_correlation, the second reaches at most max_second_ratio of it and a tracker cycle
  // confirms it.
  struct Gate {
    double min_correlation, max_second_ratio;
  };
  // One dense search of `frame` (`feed` sees its coarse sweep), its best's distinct alternative
  // added when the gate would accept the best, then AcceptDensePeaks; the peaks, best first.
  std::vector<DensePeak> SearchDense(
      const DensePlaceSearch& search, const cv::Mat& frame,
      const std::function<void(const DensePlaceSearch::SweepMap&)>& feed, Gate gate,
      Relocalization* out,
      DensePlaceSearch::SweepLevel sweep = DensePlaceSearch::SweepLevel::kCoarse,
      int refine_stride = 0);
  void AcceptDensePeaks(const DensePlaceSearch& search, const cv::Mat& frame,
                        const std::vector<DensePeak>& peaks, Gate gate, Relocalization* out);
  // Whether the best of `peaks` is told apart from every rival that reaches the gate's second
  // ratio of it (see twin_contrast); *out (may be null) records the contrasts and the reason.
  bool TwinsToldApart(const DensePlaceSearch& search, const cv::Mat& frame,
                      const std::vector<DensePeak>& peaks, Gate gate, Relocalization* out) const;
  // The multi-frame search once the frame has joined the trajectory (see Relocalize).
  void TrajectoryRelocalize(const cv::Mat& frame, Relocalization* out);
  // Refuses the trajectory's found pose as ambiguous when, placed on its best distinct
  // alternative, the trajectory correlates as well at the finest search's level.
  void CheckTrajectoryTwin(Relocalization* out);
  Status CheckFrame(const cv::Mat& frame) const;
  // Refuses a found pose in a place of twin_places_ (see SetTwinPlaces).
  void RefuseNamedTwins(Relocalization* out) const;

  const PlaceIndex* index_;
  geometry::CameraModel camera_;
  RelocalizerOptions options_;
  tracking::MosaicTracker tracker_;
  std::unique_ptr<DensePlaceSearch> dense_;       // null: off, or the mosaic is too large for it
  std::unique_ptr<DensePlaceSearch> dense_fine_;  // null: off, or too large, or no dense_
  std::unique_ptr<TrajectoryPlaceSearch> trajectory_;  // null: off
  bool feed_trajectory_ = false;  // the dense search's coarse sweep also feeds trajectory_
  bool trajectory_fed_ = false;   // and it did, for the current frame
  // A frame of the current trajectory was refused as ambiguous on its own: it saw a twin.
  bool trajectory_saw_twin_ = false;
  std::vector<SimilarPlace> twin_places_;
};

}  // namespace fleetloc::relocalization
