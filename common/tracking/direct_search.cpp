// The dense aligner's coarse search: an exhaustive normalized correlation of the whole frame over
// the prediction's window at a coarse level, climbing over headings when no clear peak is found
// (see direct_aligner.h).
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "imaging/spectral_ncc.h"
#include "tracking/direct_aligner.h"
#include "tracking/direct_aligner_parts.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/predicted_view.h"

namespace fleetloc::tracking {

using direct_detail::CornerSigmaPx;
using direct_detail::GrownBy;
using geometry::Pose2;
using geometry::PoseWithCovariance;

namespace {

// The heading step (of ±steps) a climb from the predicted heading (`start_correlation`) ends at:
// the correlation rises towards the true heading, so one step each side, then onwards in the
// better direction while it keeps rising; 0 when neither side beats the start.
int ClimbToBestHeading(double start_correlation, int steps,
                       const std::function<double(int)>& correlation_at) {
  const double minus = correlation_at(-1), plus = correlation_at(1);
  const int direction = plus >= minus ? 1 : -1;
  double next = std::max(minus, plus), best = start_correlation;
  int best_k = 0;
  for (int k = direction; next > best; k += direction) {
    best = next;
    best_k = k;
    if (std::abs(k) >= steps) break;
    next = correlation_at(k + direction);
  }
  return best_k;
}

}  // namespace

// The level the search starts at: at least one above the finest (a wider window at a finer level
// holds more chance peaks: measured at 320×240 on a plain dusty floor, searching at 160×120 left
// 15 % of the frames ambiguous, at 80×60 3 %), and the finest of those whose image has at most
// search_level_pixels (the search is then cheap, and every coarser level holds less of a weak
// floor's texture), or coarser while the prediction's 3-sigma would exceed max_search_px there.
int DirectAligner::SearchLevel(double sigma_px) const {
  const long long pixels = static_cast<long long>(camera_.width_px) * camera_.height_px;
  int level = std::min(finest_level_ + 1, levels_ - 1);
  while (level + 1 < levels_ &&
         ((pixels >> (2 * level)) > options_.search_level_pixels ||
          options_.search_sigma_multiple * sigma_px / (1 << level) > options_.max_search_px)) {
    ++level;
  }
  return level;
}

// Exhaustive normalized correlation of the level's frame over a ±r window of the mosaic view
// rendered at `pose`: the best shift's pose, its correlation and the second peak's ratio to it.
DirectAligner::SearchHit DirectAligner::SearchAt(const Level& level,
                                                 const imaging::SpectralNcc& frame_ncc,
                                                 const Pose2& pose, int r) const {
  const cv::Rect inner = InnerRect(level);
  const FrameMosaicWarp warp =
      FrameMosaicWarp::For(pose, camera_, mosaic_->layout().geo).AtLevel(level.level);
  const cv::Mat view = RenderNormalizedView(mosaic_, GrownBy(inner, r), warp, level.level);
  const cv::Mat surface = frame_ncc.Surface(view);
  SearchHit hit;
  cv::Point best_at, second_at;
  cv::minMaxLoc(surface, nullptr, &hit.correlation, nullptr, &best_at);
  cv::Mat off_peak(surface.size(), CV_8U, cv::Scalar(255));
  cv::circle(off_peak, best_at, options_.peak_exclusion_px, cv::Scalar(0), cv::FILLED);
  double second = 0.0;
  cv::minMaxLoc(surface, nullptr, &second, nullptr, &second_at, off_peak);
  hit.peak_ratio = hit.correlation > 0.0 ? std::max(0.0, second) / hit.correlation : 1.0;
  cv::Scalar mean, spread;
  cv::meanStdDev(surface, mean, spread, off_peak);
  cv::circle(off_peak, second_at, options_.peak_exclusion_px, cv::Scalar(0), cv::FILLED);
  double third = 0.0;
  cv::minMaxLoc(surface, nullptr, &third, nullptr, nullptr, off_peak);
  hit.third_ratio = hit.correlation > 0.0 ? std::max(0.0, third) / hit.correlation : 1.0;
  hit.peak_z = spread[0] > 0.0 ? (hit.correlation - mean[0]) / spread[0] : 0.0;
  hit.pose = PoseAtShift(level, pose, best_at - cv::Point(r, r));
  hit.rival_pose = PoseAtShift(level, pose, second_at - cv::Point(r, r));
  return hit;
}

// The frame's content sits at +shift (level px) in a view rendered at `pose`: the camera moved by
// shift, which is −shift_y, −shift_x in camera_ground axes.
Pose2 DirectAligner::PoseAtShift(const Level& level, const Pose2& pose,
                                 const cv::Point& shift) const {
  const double step_m = camera_.resolution_m * (1 << level.level);
  return pose * Pose2{-shift.y * step_m, -shift.x * step_m, 0.0};
}

// The coarse search over the prediction's window: at the predicted heading, and when that finds
// no clear peak and the heading is uncertain enough to misalign the level's frame edges by a
// pixel, at headings spread over ±3 sigma too (a frame turned against the view correlates
// weakly everywhere; measured on fast runs over coarse asphalt: a prediction 34 px and 1.8° off
// gave an ambiguous peak at the predicted heading).
DirectAligner::SearchHit DirectAligner::CoarseSearch(const Level& level,
                                                     const PoseWithCovariance& prior,
                                                     const Pose2& start,
                                                     DirectAlignment* out) const {
  const double radius =
      options_.search_sigma_multiple * CornerSigmaPx(camera_, prior) / (1 << level.level);
  if (radius <= options_.search_above_px) {
    SearchHit none;
    none.pose = none.rival_pose = start;
    return none;
  }
  const int r = std::min(options_.max_search_px, static_cast<int>(std::ceil(radius)) + 1);
  out->searched = true;
  const cv::Rect inner = InnerRect(level);
  const imaging::SpectralNcc frame_ncc(level.searched(inner), GrownBy(inner, r).size());
  int searches = 1;
  SearchHit best = SearchAt(level, frame_ncc, start, r);
  // A clear peak, or a significant and distinct one, has located the frame: the alignment then
  // fits the heading too. (Significant but only unambiguous is not enough: at 320×240 under
  // `all`, peaks at z 10–14 with a second peak at 0.25–0.28 of them ended 0.8 px off or were
  // refused, where one heading step further gave z 21–23 and 0.12.)
  const bool clear =
      (best.correlation >= options_.min_strong_correlation &&
       best.peak_ratio <= options_.max_weak_peak_ratio) ||
      (options_.significant_peak_ends_search && best.peak_z >= options_.min_significant_peak_z &&
       best.peak_ratio <= options_.max_distinct_peak_ratio);
  const double half_diagonal = 0.5 * std::hypot(level.normalized.cols, level.normalized.rows);
  const double heading_3sigma = 3.0 * std::sqrt(std::max(0.0, prior.covariance(2, 2)));
  const int steps = std::min(options_.max_heading_steps,
                             static_cast<int>(std::floor(heading_3sigma * half_diagonal)));
  if (!clear && steps >= 1) {
    const double step = heading_3sigma / steps;
    // Probing near the predicted heading's peak needs that peak to be the frame's place: a
    // significant one (measured at 1280×1024 on polished concrete 024 under `all`: peaks at z ≈ 4
    // with a second peak at 0.85 of them were chance peaks, and the frame's place turned up
    // only in the whole window one heading step away, at z 15).
    const bool probe = options_.heading_probe_px > 0;
    if (probe && best.peak_z >= options_.min_significant_peak_z) {
      best = ClimbHeadings(level, frame_ncc, start, r, step, steps, best, &searches);
    } else if (probe && options_.min_tentative_peak_z > 0 &&
               best.peak_z >= options_.min_tentative_peak_z) {
      best =
          ClimbHeadingsFromTentativePeak(level, frame_ncc, start, r, step, steps, best, &searches);
    } else {
      best = ClimbHeadingsOverWholeWindows(level, frame_ncc, start, r, step, steps, best, {},
                                           &searches);
    }
  }
  out->peak_ratio = best.peak_ratio;
  out->peak_z = best.peak_z;
  out->searches = searches;
  return best;
}

// The heading climb of CoarseSearch over whole windows (measured under fast turns: the best
// heading is almost always one step off the prediction, so this costs 2–3 searches instead of
// 2·steps). `hits`: headings already searched over the whole window.
DirectAligner::SearchHit DirectAligner::ClimbHeadingsOverWholeWindows(
    const Level& level, const imaging::SpectralNcc& frame_ncc, const Pose2& start, int r,
    double step, int steps, const SearchHit& at_start, std::map<int, SearchHit> hits,
    int* searches) const {
  const int best_k = ClimbToBestHeading(at_start.correlation, steps, [&](int k) {
    if (hits.count(k) == 0) {
      ++*searches;
      hits[k] = SearchAt(level, frame_ncc, start * Pose2{0.0, 0.0, k * step}, r);
    }
    return hits[k].correlation;
  });
  return best_k == 0 ? at_start : hits[best_k];
}

// The heading climb of CoarseSearch with each heading probed only near the predicted heading's
// significant peak (`at_start`): the view turned about that peak's place, which stays put as the
// heading turns (the pose's origin is the principal point), searched ±heading_probe_px directly
// (SpectralNcc::SurfaceNear, ~0.3 M instructions at 640×480's search level against 7.8 M for a
// whole window's two transforms). The climb is the same as over whole windows. The heading it ends
// at keeps its probe's peak when that lies inside the probed neighbourhood, with the predicted
// heading's second and third peaks, z and rival: a whole window at that heading (two more
// transforms) would find the same peak, and the other places' peaks do not rise with it (see
// TurnedHit). A peak on the neighbourhood's edge may lie beyond it: that heading is searched over
// the whole window.
DirectAligner::SearchHit DirectAligner::ClimbHeadings(const Level& level,
                                                      const imaging::SpectralNcc& frame_ncc,
                                                      const Pose2& start, int r, double step,
                                                      int steps, const SearchHit& at_start,
                                                      int* searches) const {
  const int p = options_.heading_probe_px;
  const ProbedHeading climb = ClimbProbedHeadings(level, frame_ncc, step, steps, at_start);
  if (climb.k == 0) return at_start;
  const cv::Point at = climb.at;
  if (at.x > 0 && at.y > 0 && at.x < 2 * p && at.y < 2 * p) {
    return TurnedHit(at_start, climb.pose, climb.correlation);
  }
  ++*searches;
  const SearchHit turned = SearchAt(level, frame_ncc, start * Pose2{0.0, 0.0, climb.k * step}, r);
  return turned.correlation > at_start.correlation ? turned : at_start;
}

// The probes' climb of ClimbHeadings: each heading's view turned about the predicted heading's
// peak and correlated within ±heading_probe_px of it; the heading step it ends at, that probe's
// peak (its place in the probed surface and its pose) and correlation.
DirectAligner::ProbedHeading DirectAligner::ClimbProbedHeadings(
    const Level& level, const imaging::SpectralNcc& frame_ncc, double step, int steps,
    const SearchHit& at_start) const {
  const int p = options_.heading_probe_px;
  const cv::Rect near = GrownBy(InnerRect(level), p);
  const geometry::Geotransform& geo = mosaic_->layout().geo;
  std::map<int, std::pair<double, cv::Point>> peaks;  // heading step → probe peak, its place
  const auto probe = [&](int k) {
    const FrameMosaicWarp warp =
        FrameMosaicWarp::For(at_start.pose * Pose2{0.0, 0.0, k * step}, camera_, geo)
            .AtLevel(level.level);
    auto& [correlation, at] = peaks[k];
    cv::minMaxLoc(frame_ncc.SurfaceNear(RenderNormalizedView(mosaic_, near, warp, level.level)),
                  nullptr, &correlation, nullptr, &at);
    return correlation;
  };
  ProbedHeading climb;
  climb.k = ClimbToBestHeading(at_start.correlation, steps, probe);
  if (climb.k == 0) return climb;
  std::tie(climb.correlation, climb.at) = peaks[climb.k];
  const Pose2 turned = at_start.pose * Pose2{0.0, 0.0, climb.k * step};
  climb.pose = PoseAtShift(level, turned, climb.at - cv::Point(p, p));
  return climb;
}

// The heading climb of CoarseSearch from a predicted heading's peak that may be the frame's place
// or chance (z ≥ min_tentative_peak_z, below min_significant_peak_z): the probes' climb as in
// ClimbHeadings, then the heading it ends at searched over the whole window. When that window's
// peak is the probed one (within heading_probe_px level pixels) and beats the predicted heading's,
// the peak was the frame's place and the search ends there, with the whole window's second peak,
// z and rival. Otherwise (the climb stayed, or the window's peak lies elsewhere) the climb goes on
// over whole windows, reusing the one searched. Measured on painted pavement 001 at 640×480 under
// `all`: 31 of 60 frames climbed over four whole windows from peaks at z 3.3–7.7, and every one
// but a frame at z 3.6 ended within 2 level pixels of its predicted heading's peak.
DirectAligner::SearchHit DirectAligner::ClimbHeadingsFromTentativePeak(
    const Level& level, const imaging::SpectralNcc& frame_ncc, const Pose2& start, int r,
    double step, int steps, const SearchHit& at_start, int* searches) const {
  const ProbedHeading climb = ClimbProbedHeadings(level, frame_ncc, step, steps, at_start);
  if (climb.k == 0) {
    return ClimbHeadingsOverWholeWindows(level, frame_ncc, start, r, step, steps, at_start, {},
                                         searches);
  }
  ++*searches;
  const SearchHit turned = SearchAt(level, frame_ncc, start * Pose2{0.0, 0.0, climb.k * step}, r);
  const double level_px_m = camera_.resolution_m * (1 << level.level);
  const double apart_px =
      std::hypot(turned.pose.x - climb.pose.x, turned.pose.y - climb.pose.y) / level_px_m;
  if (apart_px <= options_.heading_probe_px && turned.correlation > at_start.correlation) {
    return turned;
  }
  return ClimbHeadingsOverWholeWindows(level, frame_ncc, start, r, step, steps, at_start,
                                       {{climb.k, turned}}, searches);
}

// The predicted heading's hit moved to a better heading's peak (`pose`, `correlation`) found by a
// probe: the second and third peaks are other places, whose correlation does not rise as the
// heading turns towards the frame's own, so their ratios are taken against the new peak; the
// predicted heading's z and rival are kept (the z, a lower bound, only has to pass
// min_significant_peak_z, which the predicted heading's already did).
DirectAligner::SearchHit DirectAligner::TurnedHit(const SearchHit& at_start, const Pose2& pose,
                                                  double correlation) {
  SearchHit hit = at_start;
  hit.pose = pose;
  hit.correlation = correlation;
  const double scale = correlation > 0.0 ? at_start.correlation / correlation : 1.0;
  hit.peak_ratio = std::min(1.0, at_start.peak_ratio * scale);
  hit.third_ratio = std::min(1.0, at_start.third_ratio * scale);
  return hit;
}

}  // namespace fleetloc::tracking
