// Dense global place search: the normalized levels and the heading sweep at a coarse level (see
// dense_place_search.h); the refinement one level finer is in dense_place_search_refine.cpp.
#include "relocalization/dense_place_search.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "imaging/masked_correlator.h"
#include "relocalization/dense_place_search_parts.h"

namespace fleetloc::relocalization {

namespace {

constexpr double kEpsilonDn = 0.5;  // keeps flat areas from being amplified into noise

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

}  // namespace

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

void FiniteScores(cv::Mat* scores) {
  cv::patchNaNs(*scores, 0.0);
  scores->setTo(0.0f, cv::abs(*scores) > 1.0f);
}

void InParallel(int n, int threads, const std::function<void(int)>& body) {
  cv::parallel_for_(
      cv::Range(0, n),
      [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i) body(i);
      },
      std::min(n, threads));
}

geometry::Pose2 PoseAt(const geometry::CameraModel& camera, const geometry::Geotransform& geo,
                       const Eigen::Vector2d& at, double theta) {
  const Eigen::Vector2d centre_ground =
      camera.PixelToGround({0.5 * camera.width_px, 0.5 * camera.height_px});
  const Eigen::Vector2d xy = geo.PixelToMap(at) - Eigen::Rotation2Dd(theta) * centre_ground;
  return {xy.x(), xy.y(), geometry::WrapAngle(theta)};
}

Status Validate(const DensePlaceSearchOptions& o) {
  if (o.min_short_side_px < 16 || o.min_short_side_px > 512)
    return InvalidInput("dense place search: min_short_side_px must be 16..512");
  if (!(o.heading_step_scale > 0.1 && o.heading_step_scale <= 4.0))
    return InvalidInput("dense place search: heading_step_scale must be in (0.1, 4]");
  if (!(o.sweep_heading_step_factor >= 1.0 && o.sweep_heading_step_factor <= 4.0))
    return InvalidInput("dense place search: sweep_heading_step_factor must be in [1, 4]");
  if (o.refine_heading_steps < 1 || o.refine_heading_steps > 8)
    return InvalidInput("dense place search: refine_heading_steps must be 1..8");
  if (o.refine_sweep_heading_stride < 1 || o.refine_sweep_heading_stride > 4 ||
      o.refine_sweep_heading_stride > 2 * o.refine_heading_steps)
    return InvalidInput(
        "dense place search: refine_sweep_heading_stride must be 1..4 and at most twice "
        "refine_heading_steps");
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

double DensePlaceSearch::SweepWork(SweepLevel level, int stride) const {
  const int pairs = (heading_steps(level) / 2 + stride - 1) / stride;
  return static_cast<double>(sweep_size(level).area()) * pairs;
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
                             const std::function<void(const SweepMap&)>& visit, SweepLevel level,
                             int stride) const {
  const cv::Mat normalized = NormalizedFrame(frame, level);
  const int half = heading_steps(level) / 2;
  // One heading pair a stripe, then visited in heading order (as one stripe would).
  struct PairMaps {
    cv::Mat centred, turned;
    int suppress_px = 0;
  };
  std::vector<PairMaps> batch(options_.threads);
  const int pairs = (half + stride - 1) / stride;
  for (int first = 0; first < pairs; first += options_.threads) {
    const int count = std::min(options_.threads, pairs - first);
    InParallel(count, options_.threads, [&](int i) {
      PairMaps& m = batch[i];
      m.suppress_px = ScoresAtAndTurned(normalized, sweep_heading_rad((first + i) * stride, level),
                                        level, &m.centred, &m.turned);
    });
    for (int i = 0; i < count; ++i) {
      const int k = (first + i) * stride;
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
    const cv::Mat& frame, const std::function<void(const SweepMap&)>& also, SweepLevel sweep,
    int stride) const {
  std::vector<DensePeak> peaks;
  Sweep(
      frame,
      [&](const SweepMap& map) {
        if (also) also(map);
        AppendCoarsePeaks(map.scores.clone(), map.theta, map.suppress_px, &peaks, sweep);
      },
      sweep, stride);
  std::sort(peaks.begin(), peaks.end(),
            [](const DensePeak& a, const DensePeak& b) { return a.correlation > b.correlation; });
  return peaks;
}

std::vector<DensePeak> DensePlaceSearch::Search(const cv::Mat& frame,
                                                const std::function<void(const SweepMap&)>& also,
                                                SweepLevel sweep, int refine_stride) const {
  FLEETLOC_CHECK(frame.type() == CV_8UC1 && frame.cols == camera_.width_px &&
                 frame.rows == camera_.height_px);
  FLEETLOC_CHECK(refine_stride >= 0 && refine_stride <= 2 * options_.refine_heading_steps);
  int stride = 1;
  if (sweep == SweepLevel::kRefine)
    stride = refine_stride > 0 ? refine_stride : options_.refine_sweep_heading_stride;
  const std::vector<DensePeak> coarse =
      DistinctBest(CoarsePeaks(frame, also, sweep, stride), options_.coarse_peaks);
  // A peak of the refine level's own sweep is within a pixel of its place there.
  const int radius_px = sweep == SweepLevel::kRefine ? 2 : 4;
  std::vector<DensePeak> refined(coarse.size());
  InParallel(static_cast<int>(coarse.size()), options_.threads,
             [&](int i) { refined[i] = Refine(frame, coarse[i], radius_px); });
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
