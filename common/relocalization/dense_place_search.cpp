// Dense global place search: heading sweep at a coarse level, refinement one level finer (see
// dense_place_search.h).
#include "relocalization/dense_place_search.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "imaging/masked_correlator.h"

namespace fleetloc::relocalization {

// The whole mosaic at one pyramid level, normalized, with its geotransform.
struct DensePlaceSearch::Level {
  int level = 0;
  cv::Mat normalized;  // CV_32F
  geometry::Geotransform geo;
  double half_diagonal_px = 0;  // of a frame at this level
  int pad_px = 0;               // zero border around the mosaic
  double heading_step_rad = 0;
  std::unique_ptr<imaging::MaskedCorrelator> correlator;  // of `normalized`: its spectra kept
};

namespace {

constexpr double kEpsilonDn = 0.5;  // keeps flat areas from being amplified into noise

// (I − μ) / (σ + ε) over a window, clipped to ±clip; CV_32F.
cv::Mat NormalizeClipped(const cv::Mat& image, int window, double clip) {
  cv::Mat f, mean, mean_sq, sigma;
  image.convertTo(f, CV_32F);
  cv::boxFilter(f, mean, CV_32F, cv::Size(window, window), cv::Point(-1, -1), true,
                cv::BORDER_REFLECT);
  cv::boxFilter(f.mul(f), mean_sq, CV_32F, cv::Size(window, window), cv::Point(-1, -1), true,
                cv::BORDER_REFLECT);
  cv::sqrt(cv::max(mean_sq - mean.mul(mean), 0.0), sigma);
  cv::Mat out = (f - mean) / (sigma + kEpsilonDn);
  return cv::min(cv::max(out, -clip), clip);
}

// The whole mosaic at `level` (resampled from the coarsest stored level when it has fewer).
cv::Mat ReadWholeLevel(mosaic::RasterSource& mosaic, int level) {
  const mosaic::MosaicLayout& layout = mosaic.layout();
  const int stored = std::min(level, layout.levels - 1);
  cv::Mat pixels = mosaic.ReadBlock(
      stored, cv::Rect(0, 0, layout.LevelWidth(stored), layout.LevelHeight(stored)));
  if (stored == level) return pixels;
  cv::Mat smaller;
  cv::resize(pixels, smaller, cv::Size(layout.LevelWidth(level), layout.LevelHeight(level)), 0, 0,
             cv::INTER_AREA);
  return smaller;
}

// Frame pixel directions → mosaic pixel directions at the same level, for heading θ.
Eigen::Matrix2d FrameToMosaic(const geometry::CameraModel& camera,
                              const geometry::Geotransform& geo, double theta) {
  Eigen::Matrix2d to_ground, to_pixel;
  const Eigen::Vector2d g0 = camera.PixelToGround({0, 0});
  to_ground << camera.PixelToGround({1, 0}) - g0, camera.PixelToGround({0, 1}) - g0;
  const Eigen::Vector2d p0 = geo.MapToPixel({0, 0});
  to_pixel << geo.MapToPixel({1, 0}) - p0, geo.MapToPixel({0, 1}) - p0;
  // The frame and the mosaic are taken at the same level: scale-free.
  const double scale = geo.resolution / camera.resolution_m;
  return scale * to_pixel * Eigen::Rotation2Dd(theta).toRotationMatrix() * to_ground;
}

// The normalized frame rotated into the mosaic's axes for heading θ: the template, its mask, and
// the template's continuous coordinates of the frame centre.
struct Template {
  cv::Mat pixels, mask;
  Eigen::Vector2d centre;
};

Template RotatedFrame(const cv::Mat& frame, const Eigen::Matrix2d& l) {
  const Eigen::Vector2d half(0.5 * frame.cols, 0.5 * frame.rows);
  const Eigen::Vector2d extent = l.cwiseAbs() * half;
  const cv::Size size(2 * static_cast<int>(std::ceil(extent.x())) + 2,
                      2 * static_cast<int>(std::ceil(extent.y())) + 2);
  Template t;
  t.centre = Eigen::Vector2d(0.5 * size.width, 0.5 * size.height);
  // Index coordinates (centres at integers): dst = L·(src + ½ − c_f) + c_t − ½.
  const Eigen::Vector2d offset =
      l * (Eigen::Vector2d(0.5, 0.5) - half) + t.centre - Eigen::Vector2d(0.5, 0.5);
  const cv::Matx23d m(l(0, 0), l(0, 1), offset.x(), l(1, 0), l(1, 1), offset.y());
  cv::warpAffine(frame, t.pixels, m, size, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  cv::warpAffine(cv::Mat(frame.size(), CV_8UC1, cv::Scalar(255)), t.mask, m, size,
                 cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  cv::erode(t.mask, t.mask, cv::Mat());
  return t;
}

// Places where the template meets only the zero border (0 / 0) score 0, not NaN or infinity.
void FiniteScores(cv::Mat* scores) {
  cv::patchNaNs(*scores, 0.0);
  scores->setTo(0.0f, cv::abs(*scores) > 1.0f);
}

// body(i) for every i in [0, n), on up to `threads` stripes of OpenCV's pool; body(i) may write
// only what belongs to i.
void InParallel(int n, int threads, const std::function<void(int)>& body) {
  cv::parallel_for_(
      cv::Range(0, n),
      [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i) body(i);
      },
      std::min(n, threads));
}

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

// The camera pose whose frame centre lands at mosaic continuous coordinates `at` (of `level`).
geometry::Pose2 PoseAt(const geometry::CameraModel& camera, const geometry::Geotransform& geo,
                       const Eigen::Vector2d& at, double theta) {
  const Eigen::Vector2d centre_ground =
      camera.PixelToGround({0.5 * camera.width_px, 0.5 * camera.height_px});
  const Eigen::Vector2d xy = geo.PixelToMap(at) - Eigen::Rotation2Dd(theta) * centre_ground;
  return {xy.x(), xy.y(), geometry::WrapAngle(theta)};
}

}  // namespace

Status Validate(const DensePlaceSearchOptions& o) {
  if (o.min_short_side_px < 16 || o.min_short_side_px > 512)
    return InvalidInput("dense place search: min_short_side_px must be 16..512");
  if (!(o.heading_step_scale > 0.1 && o.heading_step_scale <= 4.0))
    return InvalidInput("dense place search: heading_step_scale must be in (0.1, 4]");
  if (!(o.sweep_heading_step_factor >= 1.0 && o.sweep_heading_step_factor <= 4.0))
    return InvalidInput("dense place search: sweep_heading_step_factor must be in [1, 4]");
  if (o.refine_heading_steps < 1 || o.refine_heading_steps > 8)
    return InvalidInput("dense place search: refine_heading_steps must be 1..8");
  if (o.normalize_window_px < 3 || o.normalize_window_px % 2 == 0)
    return InvalidInput("dense place search: normalize_window_px must be odd and >= 3");
  if (!(o.clip > 0.5 && o.clip <= 10.0))
    return InvalidInput("dense place search: clip must be in (0.5, 10]");
  if (o.coarse_peaks < 1 || o.coarse_peaks > 100)
    return InvalidInput("dense place search: coarse_peaks must be 1..100");
  if (o.max_peaks < 2 || o.max_peaks > o.coarse_peaks)
    return InvalidInput("dense place search: max_peaks must be 2..coarse_peaks");
  if (!(o.max_refine_level_mpx > 0.0 && o.max_refine_level_mpx <= 100.0))
    return InvalidInput("dense place search: max_refine_level_mpx must be in (0, 100]");
  if (o.threads < 1 || o.threads > 2)
    return InvalidInput("dense place search: threads must be 1..2");
  return Status::Ok();
}

DensePlaceSearch::DensePlaceSearch(const geometry::CameraModel& camera,
                                   const DensePlaceSearchOptions& options)
    : camera_(camera), options_(options) {}

Result<std::unique_ptr<DensePlaceSearch>> DensePlaceSearch::Create(
    mosaic::RasterSource& mosaic, const geometry::CameraModel& camera,
    const DensePlaceSearchOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  const mosaic::MosaicLayout& layout = mosaic.layout();
  if (std::abs(camera.resolution_m / layout.geo.resolution - 1.0) > 1e-6)
    return InvalidInput("dense place search: camera and mosaic resolutions differ");
  int fine = 0;
  const int short_side = std::min(camera.width_px, camera.height_px);
  while ((short_side >> (fine + 1)) >= options.min_short_side_px) ++fine;
  const double mpx = layout.LevelWidth(fine) * static_cast<double>(layout.LevelHeight(fine)) / 1e6;
  if (mpx > options.max_refine_level_mpx) {
    return InvalidInput("dense place search: the mosaic has " + std::to_string(mpx) +
                        " Mpx at level " + std::to_string(fine) + ", more than " +
                        std::to_string(options.max_refine_level_mpx));
  }
  std::unique_ptr<DensePlaceSearch> search(new DensePlaceSearch(camera, options));
  search->refine_level_ = fine;
  for (int k = 0; k < 2; ++k) {
    auto level = std::make_shared<Level>();
    level->level = fine + 1 - k;
    level->half_diagonal_px =
        0.5 * std::hypot(camera.width_px >> level->level, camera.height_px >> level->level);
    // Padded with zeros (no correlation) so a frame near the mosaic's edge can still be placed.
    level->pad_px = static_cast<int>(std::ceil(level->half_diagonal_px)) + 8;
    cv::copyMakeBorder(NormalizeClipped(ReadWholeLevel(mosaic, level->level),
                                        options.normalize_window_px, options.clip),
                       level->normalized, level->pad_px, level->pad_px, level->pad_px,
                       level->pad_px, cv::BORDER_CONSTANT, 0);
    const double pad_m = level->pad_px * layout.geo.resolution * (1 << level->level);
    level->geo = layout.geo.AtLevel(level->level);
    level->geo.origin_x -= pad_m;
    level->geo.origin_y += pad_m;
    level->heading_step_rad = options.heading_step_scale / level->half_diagonal_px *
                              (k == 0 ? options.sweep_heading_step_factor : 1.0);
    // Every rotated frame is wider and taller than the frame's short side: the correlator's
    // transforms may wrap into that much of the zero border.
    const int short_side_px = std::min(camera.width_px, camera.height_px) >> level->level;
    level->correlator = std::make_unique<imaging::MaskedCorrelator>(
        level->normalized, std::min(level->pad_px, short_side_px - 1));
    (k == 0 ? search->coarse_ : search->fine_) = level;
  }
  return search;
}

double DensePlaceSearch::separation_m() const {
  const int short_side = std::min(camera_.width_px, camera_.height_px) >> fine_->level;
  return std::max(4.0, 0.25 * short_side) * fine_->geo.resolution;
}

double DensePlaceSearch::heading_separation_rad() const { return 8.0 * fine_->heading_step_rad; }

std::size_t DensePlaceSearch::MemoryBytes() const {
  return (coarse_->normalized.total() + fine_->normalized.total()) * sizeof(float) +
         coarse_->correlator->MemoryBytes() + fine_->correlator->MemoryBytes();
}

const DensePlaceSearch::Level& DensePlaceSearch::LevelOf(SweepLevel level) const {
  return level == SweepLevel::kCoarse ? *coarse_ : *fine_;
}

int DensePlaceSearch::heading_steps(SweepLevel level) const {
  // Even: heading k + steps / 2 is heading k turned by π (the sweep computes the two together).
  const int steps = static_cast<int>(std::ceil(2 * M_PI / LevelOf(level).heading_step_rad));
  return steps + steps % 2;
}

double DensePlaceSearch::sweep_heading_rad(int k, SweepLevel level) const {
  return -M_PI + 2 * M_PI * k / heading_steps(level);
}

cv::Size DensePlaceSearch::sweep_size(SweepLevel level) const {
  return LevelOf(level).normalized.size();
}

double DensePlaceSearch::sweep_resolution_m(SweepLevel level) const {
  return LevelOf(level).geo.resolution;
}

geometry::Pose2 DensePlaceSearch::SweepPose(const Eigen::Vector2d& at, double theta,
                                            SweepLevel level) const {
  return PoseAt(camera_, LevelOf(level).geo, at, theta);
}

cv::Mat DensePlaceSearch::NormalizedFrame(const cv::Mat& frame, SweepLevel level) const {
  FLEETLOC_CHECK(frame.type() == CV_8UC1 && frame.cols == camera_.width_px &&
                 frame.rows == camera_.height_px);
  const int shift = LevelOf(level).level;
  cv::Mat small;
  cv::resize(frame, small, cv::Size(frame.cols >> shift, frame.rows >> shift), 0, 0,
             cv::INTER_AREA);
  return NormalizeClipped(small, options_.normalize_window_px, options_.clip);
}

int DensePlaceSearch::ScoresAt(const cv::Mat& normalized, double theta, SweepLevel level,
                               cv::Mat* centred) const {
  return ScoresAtAndTurned(normalized, theta, level, centred, nullptr);
}

int DensePlaceSearch::ScoresAtAndTurned(const cv::Mat& normalized, double theta, SweepLevel level,
                                        cv::Mat* centred, cv::Mat* turned) const {
  const Level& c = LevelOf(level);
  for (cv::Mat* map : {centred, turned}) {
    if (map == nullptr) continue;
    map->create(c.normalized.size(), CV_32F);
    map->setTo(0.0f);
  }
  // At θ + π the template is this one turned by π about its centre (the same samples of the
  // frame: FrameToMosaic changes sign), and its centre stays where it is.
  const Template t = RotatedFrame(normalized, FrameToMosaic(camera_, c.geo, theta));
  if (t.pixels.cols > c.normalized.cols || t.pixels.rows > c.normalized.rows) return 0;
  cv::Mat scores, turned_scores;
  if (turned != nullptr)
    c.correlator->MatchWithTurned(t.pixels, t.mask, &scores, &turned_scores);
  else
    c.correlator->Match(t.pixels, t.mask, &scores);
  // Top-left → centre: the template's centre has integer coordinates (its sides are even).
  const cv::Rect placed(cv::Point(static_cast<int>(t.centre.x()), static_cast<int>(t.centre.y())),
                        scores.size());
  FiniteScores(&scores);
  scores.copyTo((*centred)(placed));
  if (turned != nullptr) {
    FiniteScores(&turned_scores);
    turned_scores.copyTo((*turned)(placed));
  }
  return std::max(2, t.pixels.rows / 4);
}

Eigen::Vector2d DensePlaceSearch::SweepPixel(const Eigen::Vector2d& map_xy,
                                             SweepLevel level) const {
  return LevelOf(level).geo.MapToPixel(map_xy);
}

void DensePlaceSearch::Sweep(const cv::Mat& frame,
                             const std::function<void(const SweepMap&)>& visit,
                             SweepLevel level) const {
  const cv::Mat normalized = NormalizedFrame(frame, level);
  const int half = heading_steps(level) / 2;
  // One heading pair a stripe, then visited in heading order (as one stripe would).
  struct PairMaps {
    cv::Mat centred, turned;
    int suppress_px = 0;
  };
  std::vector<PairMaps> batch(options_.threads);
  for (int first = 0; first < half; first += options_.threads) {
    const int count = std::min(options_.threads, half - first);
    InParallel(count, options_.threads, [&](int i) {
      PairMaps& m = batch[i];
      m.suppress_px = ScoresAtAndTurned(normalized, sweep_heading_rad(first + i, level), level,
                                        &m.centred, &m.turned);
    });
    for (int i = 0; i < count; ++i) {
      const int k = first + i;
      if (batch[i].suppress_px == 0) continue;
      visit({k, sweep_heading_rad(k, level), batch[i].centred, batch[i].suppress_px});
      visit({k + half, sweep_heading_rad(k + half, level), batch[i].turned, batch[i].suppress_px});
    }
  }
}

void DensePlaceSearch::AppendCoarsePeaks(cv::Mat scores, double theta, int suppress_px,
                                         std::vector<DensePeak>* peaks, SweepLevel level) const {
  for (int p = 0; p < 2; ++p) {
    double best = 0;
    cv::Point at;
    cv::minMaxLoc(scores, nullptr, &best, nullptr, &at);
    peaks->push_back({SweepPose(Eigen::Vector2d(at.x, at.y), theta, level), best});
    cv::circle(scores, at, suppress_px, cv::Scalar(-1), cv::FILLED);
  }
}

std::vector<DensePeak> DensePlaceSearch::CoarsePeaks(
    const cv::Mat& frame, const std::function<void(const SweepMap&)>& also) const {
  std::vector<DensePeak> peaks;
  Sweep(frame, [&](const SweepMap& map) {
    if (also) also(map);
    AppendCoarsePeaks(map.scores.clone(), map.theta, map.suppress_px, &peaks);
  });
  std::sort(peaks.begin(), peaks.end(),
            [](const DensePeak& a, const DensePeak& b) { return a.correlation > b.correlation; });
  return peaks;
}

DensePeak DensePlaceSearch::Refine(const cv::Mat& frame, const DensePeak& coarse) const {
  const Level& f = *fine_;
  cv::Mat small;
  cv::resize(frame, small, cv::Size(frame.cols >> f.level, frame.rows >> f.level), 0, 0,
             cv::INTER_AREA);
  const cv::Mat normalized = NormalizeClipped(small, options_.normalize_window_px, options_.clip);
  const Eigen::Vector2d centre_ground =
      camera_.PixelToGround({0.5 * camera_.width_px, 0.5 * camera_.height_px});
  constexpr int kRadius = 4;  // fine pixels searched around the coarse peak
  DensePeak best{coarse.camera_in_map, -2.0};
  for (int j = -options_.refine_heading_steps; j <= options_.refine_heading_steps; ++j) {
    const double theta = coarse.camera_in_map.theta + j * f.heading_step_rad;
    const Template t = RotatedFrame(normalized, FrameToMosaic(camera_, f.geo, theta));
    const Eigen::Vector2d at = f.geo.MapToPixel(coarse.camera_in_map * centre_ground);
    const cv::Point corner(static_cast<int>(std::lround(at.x() - t.centre.x())) - kRadius,
                           static_cast<int>(std::lround(at.y() - t.centre.y())) - kRadius);
    const cv::Rect area(corner, t.pixels.size() + cv::Size(2 * kRadius, 2 * kRadius));
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
  struct Place {
    double value = 0;
    cv::Point at;
  };
  std::vector<Place> places(kHeadings);
  const auto theta_of = [&](int slot) { return first.theta + (slot - kHeadings / 2) * step; };
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

std::vector<DensePeak> DensePlaceSearch::Search(
    const cv::Mat& frame, const std::function<void(const SweepMap&)>& also) const {
  FLEETLOC_CHECK(frame.type() == CV_8UC1 && frame.cols == camera_.width_px &&
                 frame.rows == camera_.height_px);
  const std::vector<DensePeak> coarse =
      DistinctBest(CoarsePeaks(frame, also), options_.coarse_peaks);
  std::vector<DensePeak> refined(coarse.size());
  InParallel(static_cast<int>(coarse.size()), options_.threads,
             [&](int i) { refined[i] = Refine(frame, coarse[i]); });
  return DistinctBest(std::move(refined), options_.max_peaks);
}

cv::Mat ShiftedScores(const cv::Mat& scores, const Eigen::Vector2d& d, double resolution_m) {
  const cv::Matx23d shift(1, 0, d.x() / resolution_m, 0, 1, -d.y() / resolution_m);
  cv::Mat moved;
  cv::warpAffine(scores, moved, shift, scores.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_CONSTANT, 0);
  return moved;
}

}  // namespace fleetloc::relocalization
