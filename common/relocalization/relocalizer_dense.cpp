// Global relocalization's dense steps (see relocalizer.h): the dense check of a pose the features
// found, the dense place search and its fine repeat with the verification of their best peak,
// and the multi-frame search.
#include <chrono>
#include <cmath>
#include <functional>

#include "relocalization/relocalizer.h"
#include "timing/elapsed.h"

namespace fleetloc::relocalization {

using timing::MsSince;

void Relocalizer::CheckDenseTwin(const cv::Mat& frame, Relocalization* out) {
  const auto start = std::chrono::steady_clock::now();
  const geometry::Pose2 camera = out->base_in_map.pose * camera_.mount;
  const DensePeak own = dense_->Refine(frame, {camera, 0.0});
  const DensePeak twin = dense_->Alternative({frame}, {geometry::Pose2{}}, camera);
  out->twin_checked = true;
  out->twin_own = own.correlation;
  out->twin_correlation = twin.correlation;
  const bool as_good = twin.correlation >= options_.dense_max_second_ratio * own.correlation;
  if (as_good) {
    PoseCandidate candidate;
    candidate.camera_in_map = twin.camera_in_map;
    ++out->verified;
    const std::optional<Verified> v =
        Verify(frame, candidate, dense_->separation_m() / 4, dense_->heading_separation_rad() / 8);
    if (v && Distinct(v->base_in_map.pose, out->base_in_map.pose) &&
        v->inliers >= out->inliers - options_.ambiguity_margin_inliers)
      out->twin_inliers = v->inliers;
  }
  if (out->twin_inliers > 0 || twin.correlation >= options_.twin_ratio * own.correlation) {
    out->found = false;
    out->ambiguous = true;
    out->reason = "ambiguous: the pose found (" + std::to_string(out->inliers) +
                  " inliers, dense " + std::to_string(own.correlation) +
                  ") has a distinct twin (dense " + std::to_string(twin.correlation) + ", " +
                  std::to_string(out->twin_inliers) + " inliers)";
  }
  out->twin_ms = MsSince(start);
}

void Relocalizer::AcceptDensePeaks(const DensePlaceSearch& search, const cv::Mat& frame,
                                   const std::vector<DensePeak>& peaks, Gate gate,
                                   Relocalization* out) {
  const double best = peaks.empty() ? 0.0 : peaks[0].correlation;
  const double second = peaks.size() < 2 ? 0.0 : peaks[1].correlation;
  const std::string scores = std::to_string(best) + " and " + std::to_string(second);
  if (best < gate.min_correlation) {
    out->reason += ": " + scores + ", too weak";
    return;
  }
  if (second > gate.max_second_ratio * best && !TwinsToldApart(search, frame, peaks, gate, out)) {
    out->ambiguous = true;
    out->reason += ": ambiguous, " + scores;
    return;
  }
  PoseCandidate candidate;
  candidate.camera_in_map = peaks[0].camera_in_map;
  const double sigma_m = search.separation_m() / 4;
  ++out->verified;
  const std::optional<Verified> v =
      Verify(frame, candidate, sigma_m, search.heading_separation_rad() / 8);
  const geometry::Pose2 searched = candidate.camera_in_map * camera_.mount.Inverse();
  if (v && std::hypot(v->base_in_map.pose.x - searched.x, v->base_in_map.pose.y - searched.y) <
               search.separation_m()) {
    out->found = true;
    out->ambiguous = false;
    out->reason.clear();
    out->base_in_map = v->base_in_map;
    out->inliers = v->inliers;
    out->templates = v->templates;
  } else {
    out->reason += ": " + scores + ", the tracker did not confirm the best";
  }
}

bool Relocalizer::TwinsToldApart(const DensePlaceSearch& search, const cv::Mat& frame,
                                 const std::vector<DensePeak>& peaks, Gate gate,
                                 Relocalization* out) const {
  if (!options_.twin_contrast) return false;
  int told_apart = 0;
  for (std::size_t i = 1; i < peaks.size(); ++i) {
    if (peaks[i].correlation <= gate.max_second_ratio * peaks[0].correlation) continue;
    const DensePlaceSearch::TwinContrast c =
        search.ContrastTwins(frame, peaks[0].camera_in_map, peaks[i].camera_in_map);
    if (out != nullptr) out->twin_contrast = c;
    const double sigma = c.pixels > 0 ? 2.0 / std::sqrt(c.pixels) : 1.0;
    if (c.share < options_.twin_contrast_min_share || c.own < gate.min_correlation ||
        c.rival > options_.twin_contrast_max_ratio * c.own ||
        c.own - c.rival < options_.twin_contrast_min_sigmas * sigma) {
      return false;
    }
    ++told_apart;
  }
  if (out == nullptr) return true;
  out->twins_told_apart += told_apart;
  out->reason += ": " + std::to_string(told_apart) +
                 " rival(s) told apart where the views differ (" +
                 std::to_string(out->twin_contrast.own) + " against " +
                 std::to_string(out->twin_contrast.rival) + " over " +
                 std::to_string(std::lround(100 * out->twin_contrast.share)) + " % of the frame)";
  return true;
}

std::vector<DensePeak> Relocalizer::SearchDense(
    const DensePlaceSearch& search, const cv::Mat& frame,
    const std::function<void(const DensePlaceSearch::SweepMap&)>& feed, Gate gate,
    Relocalization* out, DensePlaceSearch::SweepLevel sweep, int refine_stride) {
  std::vector<DensePeak> peaks = search.Search(frame, feed, sweep, refine_stride);
  // The coarse peaks are near noise on weak floors: the best's twin on a floor that repeats
  // itself need not be among them (3 single-frame wrong poses on the repeated stress floors).
  // Searched at the refine level only for a best the gate would accept (it costs 5 refine-level
  // correlations over the whole floor), its rivals told apart or not. AcceptDensePeaks tells the
  // rivals apart again with the alternative among them.
  if (peaks.size() >= 1 && peaks[0].correlation >= gate.min_correlation &&
      (peaks.size() < 2 || peaks[1].correlation <= gate.max_second_ratio * peaks[0].correlation ||
       TwinsToldApart(search, frame, peaks, gate, nullptr))) {
    peaks.push_back(search.Alternative({frame}, {geometry::Pose2{}}, peaks[0].camera_in_map));
    peaks = search.DistinctBest(std::move(peaks), search.options().max_peaks);
  }
  AcceptDensePeaks(search, frame, peaks, gate, out);
  return peaks;
}

void Relocalizer::DenseRelocalize(const cv::Mat& frame, Relocalization* out) {
  const auto start = std::chrono::steady_clock::now();
  std::function<void(const DensePlaceSearch::SweepMap&)> feed;
  if (feed_trajectory_) {
    feed = [this](const DensePlaceSearch::SweepMap& map) { trajectory_->Accumulate(map); };
    trajectory_fed_ = true;
  }
  out->reason += "; dense peaks";
  const std::vector<DensePeak> peaks = SearchDense(
      *dense_, frame, feed, {options_.dense_min_correlation, options_.dense_max_second_ratio}, out);
  out->dense = true;
  out->dense_best = peaks.empty() ? 0.0 : peaks[0].correlation;
  out->dense_second = peaks.size() < 2 ? 0.0 : peaks[1].correlation;
  if (!out->found && !out->ambiguous && dense_fine_) {
    const auto fine_start = std::chrono::steady_clock::now();
    FineRelocalize(frame, DensePlaceSearch::SweepLevel::kCoarse, out);
    if (!out->found && !out->ambiguous && options_.dense_fine_refine_sweep) {
      const int stride = RefineSweepStride(MsSince(fine_start), start, out);
      if (stride > 0) {
        FineRelocalize(frame, DensePlaceSearch::SweepLevel::kRefine, out, stride);
        out->dense_fine_refine_sweep = true;
        out->dense_fine_refine_sweep_stride = stride;
      }
    }
    out->dense_fine_ms = MsSince(fine_start);
  }
  out->dense_ms = MsSince(start);
}

int Relocalizer::RefineSweepStride(double fine_ms,
                                   std::chrono::steady_clock::time_point dense_start,
                                   Relocalization* out) const {
  using Level = DensePlaceSearch::SweepLevel;
  const DensePlaceSearch& fine = *dense_fine_;
  const double spent_ms =
      out->detect_ms + out->match_ms + out->cluster_ms + out->verify_ms + MsSince(dense_start);
  const int coarsest = fine.options().refine_sweep_heading_stride;
  for (int stride = std::min(options_.dense_fine_refine_sweep_finest_stride, coarsest);
       stride <= coarsest; ++stride) {
    const double predicted_ms =
        fine_ms * fine.SweepWork(Level::kRefine, stride) / fine.SweepWork(Level::kCoarse);
    out->dense_fine_refine_sweep_predicted_ms = predicted_ms;
    if (spent_ms + predicted_ms <= options_.dense_attempt_budget_ms) return stride;
  }
  out->reason += "; no refine-level sweep (" +
                 std::to_string(std::lround(out->dense_fine_refine_sweep_predicted_ms)) +
                 " ms predicted after " + std::to_string(std::lround(spent_ms)) + " ms)";
  return 0;
}

void Relocalizer::FineRelocalize(const cv::Mat& frame, DensePlaceSearch::SweepLevel sweep,
                                 Relocalization* out, int refine_stride) {
  out->reason += sweep == DensePlaceSearch::SweepLevel::kCoarse
                     ? "; fine dense peaks"
                     : "; fine dense peaks swept at the refine level";
  const std::vector<DensePeak> fine =
      SearchDense(*dense_fine_, frame, {},
                  {options_.dense_fine_min_correlation, options_.dense_max_second_ratio}, out,
                  sweep, refine_stride);
  out->dense_fine = true;
  out->dense_fine_best = fine.empty() ? 0.0 : fine[0].correlation;
  out->dense_fine_second = fine.size() < 2 ? 0.0 : fine[1].correlation;
}

// A frame of the trajectory saw a twin on its own, at a level finer than the trajectory's sums
// (where the twin shows): the whole trajectory is placed at the found pose and at its best
// distinct alternative at that level, and refused as ambiguous when the alternative reaches
// twin_ratio of it. Measured on the stress bench's repeated plain concrete r1 at 640×480 under
// dust: each frame's fine search saw its place and its twin at the same 0.39–0.41, and two
// frames' coarse sums took the twin (0.17, their alternative 0.08), 0.51 m off. A trajectory that
// leaves the repeated part is not refused: shifted onto the twin, its other frames fall where
// the floor differs.
void Relocalizer::CheckTrajectoryTwin(Relocalization* out) {
  const auto start = std::chrono::steady_clock::now();
  const TrajectoryPlaceSearch::OwnAndTwin measured = trajectory_->MeasureTwin(
      dense_fine_ ? *dense_fine_ : *dense_, out->base_in_map.pose * camera_.mount);
  out->twin_checked = true;
  out->twin_own = measured.own;
  out->twin_correlation = measured.twin;
  if (measured.twin >= options_.twin_ratio * measured.own) {
    out->found = false;
    out->ambiguous = true;
    out->reason += ": ambiguous, the frames' place (" + std::to_string(measured.own) +
                   ") has a distinct twin (" + std::to_string(measured.twin) + ")";
  }
  out->twin_ms += MsSince(start);
}

void Relocalizer::ResetTrajectory() {
  if (trajectory_) trajectory_->Reset();
}

void Relocalizer::TrajectoryRelocalize(const cv::Mat& frame, Relocalization* out) {
  const auto start = std::chrono::steady_clock::now();
  // The single-frame path did not sweep it at the trajectory's level.
  if (!trajectory_fed_) trajectory_->SweepNewest();
  out->trajectory_frames = trajectory_->frames();
  if (trajectory_->frames() >= 2) {
    const std::vector<DensePeak> peaks = trajectory_->Search();
    out->trajectory_best = peaks.empty() ? 0.0 : peaks[0].correlation;
    out->trajectory_second = peaks.size() < 2 ? 0.0 : peaks[1].correlation;
    out->reason += "; " + std::to_string(trajectory_->frames()) + " frames' mean peaks";
    AcceptDensePeaks(*dense_, frame, peaks,
                     {options_.trajectory_min_correlation, options_.trajectory_max_second_ratio},
                     out);
    if (out->found && trajectory_saw_twin_) CheckTrajectoryTwin(out);
    out->from_trajectory = out->found;
    if (out->found) trajectory_->Reset();
  }
  out->trajectory_ms = MsSince(start);
}

}  // namespace fleetloc::relocalization
