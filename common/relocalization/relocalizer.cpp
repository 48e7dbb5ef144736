// Global relocalization: match, vote, cluster, verify (see relocalizer.h); the dense and
// multi-frame steps are in relocalizer_dense.cpp.
#include "relocalization/relocalizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "timing/elapsed.h"

namespace fleetloc::relocalization {
namespace {

using timing::MsSince;

std::string Describe(const Relocalization& r) {
  return std::to_string(r.frame_features) + " frame features, " + std::to_string(r.matches) +
         " matches, " + std::to_string(r.candidates) + " candidates";
}

}  // namespace

Status Validate(const RelocalizerOptions& options) {
  if (options.query_cell_px < 8) return InvalidInput("relocalizer: query_cell_px must be >= 8");
  if (options.query_features_per_cell < 1)
    return InvalidInput("relocalizer: query_features_per_cell must be >= 1");
  if (options.neighbours < 1 || options.neighbours > 16)
    return InvalidInput("relocalizer: neighbours must be 1..16");
  if (options.max_descriptor_distance < 0 || options.max_descriptor_distance > 256)
    return InvalidInput("relocalizer: max_descriptor_distance must be 0..256");
  FLEETLOC_RETURN_IF_ERROR(Validate(options.clustering));
  if (options.max_verified_candidates < 1)
    return InvalidInput("relocalizer: max_verified_candidates must be >= 1");
  if (!(options.verify_sigma_m > 0.0 && options.verify_sigma_m < 1.0))
    return InvalidInput("relocalizer: verify_sigma_m must be in (0, 1)");
  if (!(options.verify_sigma_rad > 0.0 && options.verify_sigma_rad < 0.5))
    return InvalidInput("relocalizer: verify_sigma_rad must be in (0, 0.5)");
  if (options.min_verified_inliers < options.tracker.min_inliers)
    return InvalidInput("relocalizer: min_verified_inliers must be >= tracker.min_inliers");
  if (options.confident_inliers < options.min_verified_inliers)
    return InvalidInput("relocalizer: confident_inliers must be >= min_verified_inliers");
  if (options.ambiguity_margin_inliers < 0)
    return InvalidInput("relocalizer: ambiguity_margin_inliers must be >= 0");
  if (!(options.twin_ratio > 0.0 && options.twin_ratio <= 1.0))
    return InvalidInput("relocalizer: twin_ratio must be in (0, 1]");
  if (!(options.dense_min_correlation > 0.0 && options.dense_min_correlation < 1.0))
    return InvalidInput("relocalizer: dense_min_correlation must be in (0, 1)");
  if (!(options.dense_max_second_ratio > 0.0 && options.dense_max_second_ratio < 1.0))
    return InvalidInput("relocalizer: dense_max_second_ratio must be in (0, 1)");
  if (!(options.twin_contrast_min_share > 0.0 && options.twin_contrast_min_share <= 1.0))
    return InvalidInput("relocalizer: twin_contrast_min_share must be in (0, 1]");
  if (!(options.twin_contrast_max_ratio > 0.0 && options.twin_contrast_max_ratio < 1.0))
    return InvalidInput("relocalizer: twin_contrast_max_ratio must be in (0, 1)");
  if (!(options.twin_contrast_min_sigmas >= 2.0 && options.twin_contrast_min_sigmas <= 20.0))
    return InvalidInput("relocalizer: twin_contrast_min_sigmas must be in [2, 20]");
  FLEETLOC_RETURN_IF_ERROR(Validate(options.dense));
  FLEETLOC_RETURN_IF_ERROR(Validate(options.dense_fine));
  if (!(options.dense_fine_min_correlation > 0.0 && options.dense_fine_min_correlation < 1.0))
    return InvalidInput("relocalizer: dense_fine_min_correlation must be in (0, 1)");
  if (options.dense_fine_refine_sweep_finest_stride < 1)
    return InvalidInput("relocalizer: dense_fine_refine_sweep_finest_stride must be >= 1");
  if (!(options.dense_attempt_budget_ms >= 0.0))
    return InvalidInput("relocalizer: dense_attempt_budget_ms must be >= 0");
  if (options.trajectory_frames < 1 || options.trajectory_frames > 20)
    return InvalidInput("relocalizer: trajectory_frames must be 1..20");
  if (!(options.trajectory_max_travel_m > 0.0 && options.trajectory_max_travel_m <= 10.0))
    return InvalidInput("relocalizer: trajectory_max_travel_m must be in (0, 10]");
  if (!(options.trajectory_min_correlation > 0.0 && options.trajectory_min_correlation < 1.0))
    return InvalidInput("relocalizer: trajectory_min_correlation must be in (0, 1)");
  if (!(options.trajectory_max_second_ratio > 0.0 && options.trajectory_max_second_ratio < 1.0))
    return InvalidInput("relocalizer: trajectory_max_second_ratio must be in (0, 1)");
  if (!(options.trajectory_max_mb > 0.0))
    return InvalidInput("relocalizer: trajectory_max_mb must be > 0");
  return tracking::Validate(options.tracker);
}

Relocalizer::Relocalizer(const PlaceIndex* index, mosaic::RasterSource* mosaic,
                         const geometry::CameraModel& camera, const RelocalizerOptions& options)
    : index_(index),
      camera_(camera),
      options_(options),
      tracker_(tracking::CountingTemplateInliers(options.tracker), camera, mosaic) {}

Result<std::unique_ptr<Relocalizer>> Relocalizer::Create(const PlaceIndex* index,
                                                         mosaic::RasterSource* mosaic,
                                                         const geometry::CameraModel& camera,
                                                         const RelocalizerOptions& options) {
  FLEETLOC_CHECK(mosaic != nullptr);
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  const double resolution_m = mosaic->layout().geo.resolution;
  if (std::abs(camera.resolution_m / resolution_m - 1.0) > 1e-6) {
    return InvalidInput("relocalizer: camera resolution " + std::to_string(camera.resolution_m) +
                        " m/px differs from the mosaic's " + std::to_string(resolution_m));
  }
  std::unique_ptr<Relocalizer> relocalizer(new Relocalizer(index, mosaic, camera, options));
  if (options.dense_search) {
    // A mosaic too large for the dense search is relocalized by its features alone.
    Result<std::unique_ptr<DensePlaceSearch>> dense =
        DensePlaceSearch::Create(*mosaic, camera, options.dense);
    if (dense.ok()) {
      relocalizer->dense_ = std::move(dense).value();
    } else if (index == nullptr) {
      return InvalidInput("relocalizer: no place index, and " + dense.status().message());
    }
  }
  if (relocalizer->dense_ && options.dense_fine_search) {
    // Too large for the fine options: the dense search alone.
    Result<std::unique_ptr<DensePlaceSearch>> fine =
        DensePlaceSearch::Create(*mosaic, camera, options.dense_fine);
    if (fine.ok()) relocalizer->dense_fine_ = std::move(fine).value();
  }
  const auto level = options.trajectory_refine_level ? TrajectoryPlaceSearch::SweepLevel::kRefine
                                                     : TrajectoryPlaceSearch::SweepLevel::kCoarse;
  if (relocalizer->dense_ && options.trajectory_frames > 1 &&
      TrajectoryPlaceSearch::MemoryBytes(*relocalizer->dense_, level) <=
          options.trajectory_max_mb * 1e6) {
    relocalizer->trajectory_ =
        std::make_unique<TrajectoryPlaceSearch>(relocalizer->dense_.get(), camera, level);
  }
  if (index == nullptr && relocalizer->dense_ == nullptr)
    return InvalidInput("relocalizer: neither a place index nor the dense search");
  return relocalizer;
}

Relocalizer::DenseMemory Relocalizer::dense_memory() const {
  DenseMemory memory;
  if (dense_) memory.dense = dense_->MemoryBytes();
  if (dense_fine_) memory.dense_fine = dense_fine_->MemoryBytes();
  if (trajectory_)
    memory.trajectory = TrajectoryPlaceSearch::MemoryBytes(*dense_, trajectory_->level());
  return memory;
}

std::vector<FeatureMatch> Relocalizer::MatchFrame(const cv::Mat& frame, Relocalization* out) const {
  const auto start = std::chrono::steady_clock::now();
  FloorFeatureOptions detect = index_->options().features;
  detect.cell_px = options_.query_cell_px;
  detect.features_per_cell = options_.query_features_per_cell;
  const int scale = 1 << detect.level;
  cv::Mat at_level = frame;
  if (scale > 1) cv::resize(frame, at_level, frame.size() / scale, 0, 0, cv::INTER_AREA);
  const FloorFeatures features =
      DetectFloorFeatures(at_level, {}, cv::Rect(cv::Point(), at_level.size()), detect);
  out->frame_features = static_cast<int>(features.size());
  out->detect_ms = MsSince(start);

  const auto match_start = std::chrono::steady_clock::now();
  std::vector<FeatureMatch> matches;
  for (const DescriptorMatch& m :
       index_->Match(features.descriptors, options_.neighbours, options_.max_descriptor_distance)) {
    FeatureMatch match;
    match.query = m.query;
    match.ground_m = camera_.PixelToGround(features.points_px[m.query] * scale);
    // An image direction (cos a, sin a) with v down is (-sin a, -cos a) in camera_ground.
    match.ground_heading_rad = -M_PI / 2 - features.angles_rad[m.query];
    match.map_m = index_->position_m(m.feature);
    match.map_heading_rad = index_->heading_rad(m.feature);
    matches.push_back(match);
  }
  out->matches = static_cast<int>(matches.size());
  out->match_ms = MsSince(match_start);
  return matches;
}

std::optional<Relocalizer::Verified> Relocalizer::Verify(const cv::Mat& frame,
                                                         const PoseCandidate& candidate) {
  return Verify(frame, candidate, options_.verify_sigma_m, options_.verify_sigma_rad);
}

std::optional<Relocalizer::Verified> Relocalizer::Verify(const cv::Mat& frame,
                                                         const PoseCandidate& candidate,
                                                         double sigma_m, double sigma_rad) {
  geometry::PoseWithCovariance camera_in_map{candidate.camera_in_map, Eigen::Matrix3d::Zero()};
  camera_in_map.covariance.diagonal() << sigma_m * sigma_m, sigma_m * sigma_m,
      sigma_rad * sigma_rad;
  tracker_.Reset(geometry::ComposeFixed(camera_in_map, camera_.mount.Inverse()), geometry::Pose2{});
  const tracking::FrameResult result = tracker_.Track(frame, 0.0, geometry::Pose2{});
  if (result.state != tracking::LockState::kTracking) return std::nullopt;
  return Verified{result.base_in_map, result.inliers, result.templates, candidate.inliers};
}

std::vector<Relocalizer::Verified> Relocalizer::VerifyCandidates(
    const cv::Mat& frame, const std::vector<PoseCandidate>& candidates, Relocalization* out) {
  std::vector<Verified> verified;
  std::optional<geometry::Pose2> confident;  // the first confident pose
  for (const PoseCandidate& candidate : candidates) {
    if (!confident && out->verified >= options_.max_verified_candidates) break;
    // Once one is confident, only its best distinct alternative is verified, then no more.
    if (confident && !Distinct(*confident, candidate.camera_in_map * camera_.mount.Inverse()))
      continue;
    ++out->verified;
    std::optional<Verified> v = Verify(frame, candidate);
    if (v) verified.push_back(*v);
    if (confident) break;
    if (v && v->inliers >= options_.confident_inliers) confident = v->base_in_map.pose;
  }
  return verified;
}

bool Relocalizer::Distinct(const geometry::Pose2& a, const geometry::Pose2& b) const {
  const geometry::Pose2 d = geometry::Between(a, b);
  return std::hypot(d.x, d.y) > options_.clustering.radius_m ||
         std::abs(d.theta) > options_.clustering.heading_tolerance_rad;
}

void Relocalizer::Choose(std::vector<Verified> verified, Relocalization* out) const {
  std::sort(verified.begin(), verified.end(),
            [](const Verified& a, const Verified& b) { return a.inliers > b.inliers; });
  if (verified.empty() || verified[0].inliers < options_.min_verified_inliers) {
    out->reason = "no candidate confirmed by the tracker (best " +
                  std::to_string(verified.empty() ? 0 : verified[0].inliers) + " inliers, " +
                  std::to_string(options_.min_verified_inliers) + " needed; " + Describe(*out) +
                  ", " + std::to_string(out->verified) + " verified)";
    return;
  }
  const Verified& best = verified[0];
  for (std::size_t i = 1; i < verified.size(); ++i) {
    if (Distinct(best.base_in_map.pose, verified[i].base_in_map.pose) &&
        verified[i].inliers >= best.inliers - options_.ambiguity_margin_inliers) {
      out->ambiguous = true;
      out->reason = "ambiguous: two distinct poses confirmed with " + std::to_string(best.inliers) +
                    " and " + std::to_string(verified[i].inliers) + " inliers";
      return;
    }
  }
  out->found = true;
  out->base_in_map = best.base_in_map;
  out->inliers = best.inliers;
  out->templates = best.templates;
  out->candidate_inliers = best.candidate_inliers;
}

Result<Relocalization> Relocalizer::Relocalize(const cv::Mat& frame,
                                               const geometry::Pose2& base_in_odom) {
  if (!trajectory_) return Relocalize(frame);
  FLEETLOC_RETURN_IF_ERROR(CheckFrame(frame));
  const geometry::Pose2 camera_in_odom = base_in_odom * camera_.mount;
  if (trajectory_->frames() >= options_.trajectory_frames ||
      trajectory_->TravelTo(camera_in_odom) > options_.trajectory_max_travel_m)
    trajectory_->Reset();
  if (trajectory_->frames() == 0) trajectory_saw_twin_ = false;
  trajectory_->Begin(frame, camera_in_odom);
  feed_trajectory_ = trajectory_->level() == TrajectoryPlaceSearch::SweepLevel::kCoarse;
  trajectory_fed_ = false;
  Result<Relocalization> out = Relocalize(frame);
  feed_trajectory_ = false;
  if (out->found) {
    trajectory_->Reset();
    return out;
  }
  trajectory_saw_twin_ = trajectory_saw_twin_ || out->ambiguous;
  TrajectoryRelocalize(frame, &*out);
  RefuseNamedTwins(&*out);
  return out;
}

void Relocalizer::RefuseNamedTwins(Relocalization* out) const {
  if (!out->found) return;
  const geometry::Pose2 camera = out->base_in_map.pose * camera_.mount;
  const double radius_m =
      0.5 * std::min(camera_.width_px, camera_.height_px) * camera_.resolution_m;
  for (const SimilarPlace& p : twin_places_) {
    for (const geometry::Pose2& named : {p.place, p.twin}) {
      if (std::hypot(camera.x - named.x, camera.y - named.y) >= radius_m) continue;
      out->found = false;
      out->ambiguous = true;
      out->reason = "ambiguous: the self-similarity report names this place (" +
                    std::to_string(p.place.x) + ", " + std::to_string(p.place.y) +
                    ") and its twin (" + std::to_string(p.twin.x) + ", " +
                    std::to_string(p.twin.y) + ")";
      return;
    }
  }
}

Status Relocalizer::CheckFrame(const cv::Mat& frame) const {
  if (frame.empty()) return InvalidInput("relocalize: the frame is empty");
  if (frame.type() != CV_8UC1 || frame.cols != camera_.width_px ||
      frame.rows != camera_.height_px) {
    return InvalidInput("relocalize: the frame must be 8-bit gray " +
                        std::to_string(camera_.width_px) + "x" + std::to_string(camera_.height_px) +
                        ", got " + std::to_string(frame.cols) + "x" + std::to_string(frame.rows) +
                        " with " + std::to_string(frame.channels()) + " channel(s)");
  }
  return Status::Ok();
}

Result<Relocalization> Relocalizer::Relocalize(const cv::Mat& frame) {
  FLEETLOC_RETURN_IF_ERROR(CheckFrame(frame));
  Relocalization out;
  if (index_ == nullptr) {
    out.reason = "no place index";
    DenseRelocalize(frame, &out);
    RefuseNamedTwins(&out);
    return out;
  }
  const std::vector<FeatureMatch> matches = MatchFrame(frame, &out);
  const auto cluster_start = std::chrono::steady_clock::now();
  const std::vector<PoseCandidate> candidates = ClusterVotes(matches, options_.clustering);
  out.candidates = static_cast<int>(candidates.size());
  out.cluster_ms = MsSince(cluster_start);
  const auto verify_start = std::chrono::steady_clock::now();
  if (candidates.empty()) {
    out.reason = "no consistent pose votes (" + Describe(out) + ")";
  } else {
    Choose(VerifyCandidates(frame, candidates, &out), &out);
    if (out.found && dense_) CheckDenseTwin(frame, &out);
  }
  out.verify_ms = MsSince(verify_start);
  // A pose refused for its twin is ambiguous: the dense search would find one of the two.
  if (!out.found && dense_ && !out.twin_checked) DenseRelocalize(frame, &out);
  RefuseNamedTwins(&out);
  return out;
}

}  // namespace fleetloc::relocalization
