// Dense global place search: the refinement of a peak one level finer, the best distinct
// alternative to a place (one frame or a trajectory), and the distinct best of a list of peaks
// (see dense_place_search.h).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "imaging/masked_correlator.h"
#include "relocalization/dense_place_search.h"
#include "relocalization/dense_place_search_parts.h"

namespace fleetloc::relocalization {

namespace {

// Sub-pixel offset of a peak from three samples (quadratic), within ±0.5.
double QuadraticOffset(double left, double centre, double right) {
  const double denominator = left - 2 * centre + right;
  if (denominator >= 0) return 0;
  return std::clamp(0.5 * (left - right) / denominator, -0.5, 0.5);
}

// The refined sub-pixel position of the maximum of `scores` at integer `at`.
Eigen::Vector2d SubPixel(const cv::Mat& scores, cv::Point at) {
  Eigen::Vector2d p(at.x, at.y);
  const auto s = [&](int x, int y) { return static_cast<double>(scores.at<float>(y, x)); };
  if (at.x > 0 && at.x + 1 < scores.cols)
    p.x() += QuadraticOffset(s(at.x - 1, at.y), s(at.x, at.y), s(at.x + 1, at.y));
  if (at.y > 0 && at.y + 1 < scores.rows)
    p.y() += QuadraticOffset(s(at.x, at.y - 1), s(at.x, at.y), s(at.x, at.y + 1));
  return p;
}

}  // namespace

DensePeak DensePlaceSearch::Refine(const cv::Mat& frame, const DensePeak& coarse,
                                   int radius_px) const {
  const Level& f = *fine_;
  cv::Mat small;
  cv::resize(frame, small, cv::Size(frame.cols >> f.level, frame.rows >> f.level), 0, 0,
             cv::INTER_AREA);
  const cv::Mat normalized = NormalizeClipped(small, options_.normalize_window_px, options_.clip);
  const Eigen::Vector2d centre_ground =
      camera_.PixelToGround({0.5 * camera_.width_px, 0.5 * camera_.height_px});
  DensePeak best{coarse.camera_in_map, -2.0};
  for (int j = -options_.refine_heading_steps; j <= options_.refine_heading_steps; ++j) {
    const double theta = coarse.camera_in_map.theta + j * f.heading_step_rad;
    const Template t = RotatedFrame(normalized, FrameToMosaic(camera_, f.geo, theta));
    const Eigen::Vector2d at = f.geo.MapToPixel(coarse.camera_in_map * centre_ground);
    const cv::Point corner(static_cast<int>(std::lround(at.x() - t.centre.x())) - radius_px,
                           static_cast<int>(std::lround(at.y() - t.centre.y())) - radius_px);
    const cv::Rect area(corner, t.pixels.size() + cv::Size(2 * radius_px, 2 * radius_px));
    if ((area & cv::Rect(0, 0, f.normalized.cols, f.normalized.rows)) != area) continue;
    cv::Mat scores;
    imaging::MatchAtFewPlacements(f.normalized(area), t.pixels, t.mask, &scores);
    FiniteScores(&scores);
    double value = 0;
    cv::Point peak;
    cv::minMaxLoc(scores, nullptr, &value, nullptr, &peak);
    if (!(value > best.correlation)) continue;
    const Eigen::Vector2d sub = SubPixel(scores, peak);
    best = {PoseAt(camera_, f.geo, Eigen::Vector2d(corner.x, corner.y) + sub + t.centre, theta),
            value};
  }
  return best;
}

DensePeak DensePlaceSearch::Alternative(const std::vector<cv::Mat>& frames,
                                        const std::vector<geometry::Pose2>& motions,
                                        const geometry::Pose2& first) const {
  FLEETLOC_CHECK(!frames.empty() && frames.size() == motions.size());
  const SweepLevel fine = SweepLevel::kRefine;
  std::vector<cv::Mat> normalized;
  normalized.reserve(frames.size());
  for (const cv::Mat& frame : frames) normalized.push_back(NormalizedFrame(frame, fine));
  const Eigen::Vector2d centre_ground =
      camera_.PixelToGround({0.5 * camera_.width_px, 0.5 * camera_.height_px});
  const double step = 2 * M_PI / heading_steps(fine);
  const double resolution = sweep_resolution_m(fine);
  const Eigen::Vector2d own = SweepPixel(first * centre_ground, fine);
  const int radius_px = static_cast<int>(std::ceil(separation_m() / resolution));
  // The frames' mean map at each of the 5 headings, own place blanked, and its best place; the
  // headings on parallel stripes, chosen in heading order.
  constexpr int kHeadings = 5;
  constexpr int kMiddle = kHeadings / 2;  // the slot of first.theta
  struct Place {
    double value = 0;
    cv::Point at;
  };
  std::vector<Place> places(kHeadings);
  const auto theta_of = [&](int slot) { return first.theta + (slot - kMiddle) * step; };
  InParallel(kHeadings, options_.threads, [&](int slot) {
    const double theta = theta_of(slot);
    cv::Mat sum = cv::Mat::zeros(sweep_size(fine), CV_32F), scores;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      ScoresAt(normalized[i], theta + motions[i].theta, fine, &scores);
      const Eigen::Vector2d offset = motions[i] * centre_ground - centre_ground;
      sum += ShiftedScores(scores, Eigen::Rotation2Dd(theta) * offset, resolution);
    }
    sum /= static_cast<double>(frames.size());
    cv::circle(
        sum,
        cv::Point(static_cast<int>(std::lround(own.x())), static_cast<int>(std::lround(own.y()))),
        radius_px, cv::Scalar(-1), cv::FILLED);
    cv::minMaxLoc(sum, nullptr, &places[slot].value, nullptr, &places[slot].at);
  });
  DensePeak best{first * motions.back(), 0.0};
  for (int slot = 0; slot < kHeadings; ++slot) {
    const Place& p = places[slot];
    if (p.value <= best.correlation) continue;
    best = {SweepPose(Eigen::Vector2d(p.at.x, p.at.y), theta_of(slot), fine) * motions.back(),
            p.value};
  }
  return best;
}

bool DensePlaceSearch::Distinct(const DensePeak& a, const std::vector<DensePeak>& kept) const {
  return std::none_of(kept.begin(), kept.end(), [&](const DensePeak& k) {
    return std::hypot(a.camera_in_map.x - k.camera_in_map.x,
                      a.camera_in_map.y - k.camera_in_map.y) < separation_m() &&
           std::abs(geometry::WrapAngle(a.camera_in_map.theta - k.camera_in_map.theta)) <
               heading_separation_rad();
  });
}

std::vector<DensePeak> DensePlaceSearch::DistinctBest(std::vector<DensePeak> peaks, int n) const {
  std::stable_sort(peaks.begin(), peaks.end(), [](const DensePeak& a, const DensePeak& b) {
    return a.correlation > b.correlation;
  });
  std::vector<DensePeak> out;
  for (const DensePeak& p : peaks) {
    if (static_cast<int>(out.size()) >= n) break;
    if (Distinct(p, out)) out.push_back(p);
  }
  return out;
}

}  // namespace fleetloc::relocalization
