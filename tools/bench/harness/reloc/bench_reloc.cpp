// Relocalization trials (see bench_reloc.h).
#include "harness/reloc/bench_reloc.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <opencv2/core/utility.hpp>
#include <random>

#include "harness/reloc/bench_drive.h"
#include "replay/replay.h"
#include "runtime/progress_log.h"
#include "sim/camera_renderer.h"
#include "sim/random_pose.h"
#include "support/reloc_index.h"

namespace fleetloc::bench {
namespace {

// The bench's camera: the settings' frame size at the mosaic's resolution, mounted 0.40 m ahead
// of base_link.
geometry::CameraModel BenchCamera(const mosaic::MosaicLayout& layout,
                                  const RelocTrialSettings& settings) {
  geometry::CameraModel camera;
  camera.width_px = settings.width_px;
  camera.height_px = settings.height_px;
  camera.cx_px = 0.5 * settings.width_px;
  camera.cy_px = 0.5 * settings.height_px;
  camera.resolution_m = layout.geo.resolution;
  camera.mount = {0.40, 0.0, 0.0};
  return camera;
}

// The floor's velocity across the image while the vehicle drives straight ahead at speed_m_s
// (for the motion blur of a camera condition with an exposure time).
Eigen::Vector2d ImageVelocity(const geometry::CameraModel& camera, double speed_m_s) {
  constexpr double kDt = 1e-3;
  const geometry::Pose2 moved = camera.mount.Inverse() * geometry::Pose2{speed_m_s * kDt, 0, 0} *
                                camera.mount;  // the camera's motion in its own frame
  return (camera.GroundToPixel(moved.Inverse() * Eigen::Vector2d::Zero()) -
          camera.GroundToPixel(Eigen::Vector2d::Zero())) /
         kDt;
}

double Ms(const relocalization::Relocalization& r) {
  return r.detect_ms + r.match_ms + r.cluster_ms + r.verify_ms + r.dense_ms;
}

// The vehicle's odometry (base_link in odom, odom = the first frame's pose) at `truth`, after
// `travelled_m` of driving: the true motion 2 % long (a straight drive, forwards and back alike),
// turning 0.5° more per metre travelled, as a drifting wheel encoder's.
geometry::Pose2 DriftedOdometry(const geometry::Pose2& first, const geometry::Pose2& truth,
                                double travelled_m) {
  const geometry::Pose2 motion = first.Inverse() * truth;
  return {1.02 * motion.x, 1.02 * motion.y, motion.theta + 0.0087 * travelled_m};
}

bool Correct(const geometry::Pose2& pose, const geometry::Pose2& truth, const RelocTrialSettings& s,
             RelocTrial* out) {
  out->error_m = std::hypot(pose.x - truth.x, pose.y - truth.y);
  out->error_rad = std::abs(geometry::WrapAngle(pose.theta - truth.theta));
  return out->error_m < s.max_error_m && out->error_rad < s.max_error_rad;
}

// A pose the features found that the twin check or the self-similarity report refused, against
// the truth.
RelocTrial::Refused RefusedTwin(const relocalization::Relocalization& r,
                                const geometry::Pose2& truth, const RelocTrialSettings& s) {
  RelocTrial scratch;
  RelocTrial::Refused refused;
  refused.correct = Correct(r.base_in_map.pose, truth, s, &scratch);
  refused.error_m = scratch.error_m;
  refused.error_rad = scratch.error_rad;
  refused.own = r.twin_own;
  refused.twin = r.twin_correlation;
  refused.twin_inliers = r.twin_inliers;
  refused.by_report = r.reason.find("self-similarity report") != std::string::npos;
  return refused;
}

// Whether the floor repeats where the camera of base_link at `base` looks: the ideal frame there
// (the floor as an ideal area sensor sees it, no camera effect) has a distinct place in `dense`
// correlating more than `max_second_ratio` of its best (the relocalizer's ambiguity gate), its best
// distinct alternative at the refine level included. Such a place is on the floor twice (the
// stress floors' photographs have cloned patches: worn asphalt g8 repeats a region 0.24 m away),
// and refusing it as ambiguous is right.
bool FloorRepeatsAt(sim::CameraRenderer& ideal, const relocalization::DensePlaceSearch& dense,
                    const geometry::Pose2& base, double max_second_ratio) {
  cv::Mat frame;
  ideal.RenderFloor(base * ideal.camera().mount, 0).convertTo(frame, CV_8U);
  std::vector<relocalization::DensePeak> peaks = dense.Search(frame);
  if (peaks.empty()) return false;
  peaks.push_back(dense.Alternative({frame}, {geometry::Pose2{}}, peaks[0].camera_in_map));
  peaks = dense.DistinctBest(std::move(peaks), 2);
  return peaks.size() == 2 && peaks[1].correlation > max_second_ratio * peaks[0].correlation;
}

// One trial; the relocalizer starts from a cold tile cache (and cold normalized tiles). With
// multi-frame relocalization the frames go on until the single-frame path has answered too.
Result<RelocTrial> RunTrial(const std::shared_ptr<mosaic::TileStore>& store,
                            const relocalization::PlaceIndex* index, sim::CameraRenderer& renderer,
                            const geometry::Pose2& start, int trial, const RelocTrialSettings& s) {
  const mosaic::MosaicLayout layout = store->layout();
  mosaic::MosaicView view(layout, mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(s.tile_cache_bytes));
  relocalization::RelocalizerOptions options = s.relocalizer;
  options.dense.threads = options.dense_fine.threads = s.threads;
  auto relocalizer = relocalization::Relocalizer::Create(index, &view, renderer.camera(), options);
  if (!relocalizer.ok()) return relocalizer.status();
  const bool multi = s.relocalizer.trajectory_frames > 1;
  RelocTrial out;
  out.memory = (*relocalizer)->dense_memory();
  std::vector<geometry::Pose2> truths;
  const geometry::Pose2 first = PoseAtFrame(layout, renderer.camera(), start, 0, s.step_m);
  for (int k = 0; k < s.attempts && !(out.found && (out.single_found || !multi)); ++k) {
    const geometry::Pose2 truth = PoseAtFrame(layout, renderer.camera(), start, k, s.step_m);
    truths.push_back(truth);
    const Eigen::Vector2d velocity = ImageVelocity(renderer.camera(), s.step_m / s.frame_period_s);
    const cv::Mat frame =
        renderer.Render(truth, velocity, static_cast<std::uint64_t>(trial) * 16 + k).image;
    cv::setNumThreads(s.threads);
    Result<relocalization::Relocalization> r =
        multi ? (*relocalizer)->Relocalize(frame, DriftedOdometry(first, truth, k * s.step_m))
              : (*relocalizer)->Relocalize(frame);
    cv::setNumThreads(1);
    if (!r.ok()) return Internal("trial " + std::to_string(trial) + ": " + r.status().message());
    out.runs.push_back(*r);
    if (r->twin_checked && !r->found) out.refused.push_back(RefusedTwin(*r, truth, s));
    const double wait_s = k > 0 ? s.frame_period_s : 0.0;
    if (!out.single_found) out.single_time_s += Ms(*r) / 1000.0 + wait_s;
    if (r->found && !r->from_trajectory && !out.single_found) {
      out.single_found = true;
      RelocTrial scratch;
      out.single_correct = Correct(r->base_in_map.pose, truth, s, &scratch);
    }
    if (out.found) continue;
    out.attempts = k + 1;
    out.time_to_pose_s += (Ms(*r) + r->trajectory_ms) / 1000.0 + wait_s;
    if (!r->found) continue;
    out.found = true;
    out.accepted_run = k;
    out.correct = Correct(r->base_in_map.pose, truth, s, &out);
  }
  const relocalization::DensePlaceSearch* dense = (*relocalizer)->dense_search();
  const bool refused_ambiguous =
      std::any_of(out.runs.begin(), out.runs.end(), [](const auto& r) { return r.ambiguous; });
  if (!out.found && refused_ambiguous && dense != nullptr) {
    out.at_repeated_place = std::all_of(truths.begin(), truths.end(), [&](const auto& truth) {
      return FloorRepeatsAt(renderer, *dense, truth, s.relocalizer.dense_max_second_ratio);
    });
  }
  return out;
}

// Every trial `chosen` keeps, with what the relocalizer saw.
nlohmann::json TrialsJson(const std::vector<RelocTrial>& trials,
                          const std::function<bool(const RelocTrial&)>& chosen) {
  nlohmann::json failures = nlohmann::json::array();
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const RelocTrial& t = trials[i];
    if (!chosen(t)) continue;
    nlohmann::json runs = nlohmann::json::array();
    for (const relocalization::Relocalization& r : t.runs)
      runs.push_back(fleetctl::RelocalizationJson(r));
    failures.push_back({{"trial", i},
                        {"found", t.found},
                        {"error_m", t.error_m},
                        {"error_rad", t.error_rad},
                        {"at_repeated_place", t.at_repeated_place},
                        {"time_to_pose_ms", t.time_to_pose_s * 1e3},
                        {"attempts", runs}});
  }
  return failures;
}

// [correct, tracker inliers, templates, candidate feature inliers, from the trajectory, dense best,
// dense second, from the fine dense search] of every accepted pose: the margins of the acceptance
// gates (for a pose the features found: its own dense correlation and its best distinct
// alternative's; for one the fine dense search found, its peaks).
nlohmann::json Accepted(const std::vector<RelocTrial>& trials) {
  nlohmann::json accepted = nlohmann::json::array();
  for (const RelocTrial& t : trials) {
    if (!t.found) continue;
    const relocalization::Relocalization& r = t.runs[t.accepted_run];
    accepted.push_back({t.correct, r.inliers, r.templates, r.candidate_inliers, r.from_trajectory,
                        r.from_trajectory ? r.trajectory_best
                        : r.dense_fine    ? r.dense_fine_best
                        : r.dense         ? r.dense_best
                                          : r.twin_own,
                        r.from_trajectory ? r.trajectory_second
                        : r.dense_fine    ? r.dense_fine_second
                        : r.dense         ? r.dense_second
                                          : r.twin_correlation,
                        r.dense_fine && !r.from_trajectory});
  }
  return accepted;
}

// [correct, the best's correlation where the views differ, the last rival's, those pixels' share
// of the frame and their count at the level] of every accepted pose whose dense rivals were told
// apart (twin_contrast).
nlohmann::json ToldApart(const std::vector<RelocTrial>& trials) {
  nlohmann::json told_apart = nlohmann::json::array();
  for (const RelocTrial& t : trials) {
    if (!t.found) continue;
    const relocalization::Relocalization& r = t.runs[t.accepted_run];
    if (r.twins_told_apart == 0) continue;
    told_apart.push_back({t.correct, r.twin_contrast.own, r.twin_contrast.rival,
                          r.twin_contrast.share, r.twin_contrast.pixels});
  }
  return told_apart;
}

// [correct, error m, error °, own dense correlation, twin's, twin's tracker inliers, refused by
// the self-similarity report] of every refused feature pose.
nlohmann::json RefusedTwins(const std::vector<RelocTrial>& trials) {
  nlohmann::json refused = nlohmann::json::array();
  for (const RelocTrial& t : trials) {
    for (const RelocTrial::Refused& r : t.refused) {
      refused.push_back({r.correct, r.error_m, r.error_rad * 180 / M_PI, r.own, r.twin,
                         r.twin_inliers, r.by_report});
    }
  }
  return refused;
}

// Every attempt's time and its stages' times, over all trials.
struct AttemptTimes {
  std::vector<double> attempt_ms, detect, match, verify, dense, dense_fine, trajectory;
};

AttemptTimes TimesOf(const std::vector<RelocTrial>& trials) {
  AttemptTimes a;
  for (const RelocTrial& t : trials) {
    for (const relocalization::Relocalization& r : t.runs) {
      a.attempt_ms.push_back(Ms(r) + r.trajectory_ms);
      a.detect.push_back(r.detect_ms);
      a.match.push_back(r.match_ms);
      a.verify.push_back(r.verify_ms);
      // The dense stages' p50 over the attempts they ran in.
      if (r.dense) a.dense.push_back(r.dense_ms - r.dense_fine_ms);
      if (r.dense_fine) a.dense_fine.push_back(r.dense_fine_ms);
      if (r.trajectory_frames > 0) a.trajectory.push_back(r.trajectory_ms);
    }
  }
  return a;
}

// The trials and accepted poses worth reading one by one (see RelocTrialStats).
nlohmann::json TrialLists(const std::vector<RelocTrial>& trials, double target_s) {
  return {{"failures", TrialsJson(trials, [](const RelocTrial& t) { return !t.correct; })},
          {"late", TrialsJson(trials,
                              [&](const RelocTrial& t) {
                                return t.correct && t.time_to_pose_s > target_s;
                              })},
          {"accepted", Accepted(trials)},
          {"refused_twins", RefusedTwins(trials)},
          {"told_apart", ToldApart(trials)}};
}

}  // namespace

nlohmann::json RelocTrialStats(const std::vector<RelocTrial>& trials, const RelocTrialSettings& s) {
  int correct = 0, within = 0, wrong = 0, not_found = 0, repeated = 0;
  int single_within = 0, single_wrong = 0, single_none = 0;
  std::vector<double> to_pose_ms;
  for (const RelocTrial& t : trials) {
    single_within += t.single_correct && t.single_time_s <= s.target_s;
    single_wrong += t.single_found && !t.single_correct;
    single_none += !t.single_found;
    correct += t.correct;
    within += t.correct && t.time_to_pose_s <= s.target_s;
    wrong += t.found && !t.correct;
    not_found += !t.found;
    repeated += t.at_repeated_place;
    if (t.correct) to_pose_ms.push_back(t.time_to_pose_s * 1e3);
  }
  const AttemptTimes times = TimesOf(trials);
  const std::vector<double>&attempt_ms = times.attempt_ms, &detect = times.detect,
        &match = times.match, &verify = times.verify, &dense = times.dense,
        &dense_fine = times.dense_fine, &trajectory = times.trajectory;
  const double n = static_cast<double>(trials.size());
  const auto pct = [](const std::vector<double>& v) {
    return nlohmann::json{{"p50", replay::Percentile(v, 50)},
                          {"p95", replay::Percentile(v, 95)},
                          {"max", replay::Percentile(v, 100)}};
  };
  nlohmann::json stats = {{"trials", trials.size()},
                          {"correct", correct},
                          {"success_rate", correct / n},
                          {"correct_within_target", within},
                          {"success_rate_within_target", within / n},
                          {"wrong_pose", wrong},
                          {"not_found", not_found},
                          {"not_found_at_repeated_place", repeated},
                          {"time_to_correct_pose_ms", pct(to_pose_ms)},
                          {"attempt_ms", pct(attempt_ms)},
                          {"attempts", attempt_ms.size()},
                          {"stage_ms_p50",
                           {{"detect", replay::Percentile(detect, 50)},
                            {"match", replay::Percentile(match, 50)},
                            {"verify", replay::Percentile(verify, 50)},
                            {"dense", replay::Percentile(dense, 50)},
                            {"dense_fine", replay::Percentile(dense_fine, 50)},
                            {"trajectory", replay::Percentile(trajectory, 50)}}}};
  stats.update(TrialLists(trials, s.target_s));
  if (!trials.empty()) {
    const relocalization::Relocalizer::DenseMemory& m = trials.front().memory;
    stats["dense_memory_bytes"] = {
        {"dense", m.dense}, {"dense_fine", m.dense_fine}, {"trajectory", m.trajectory}};
  }
  if (s.relocalizer.trajectory_frames > 1) {
    stats["trajectory_frames"] = s.relocalizer.trajectory_frames;
    stats["single_frame"] = {{"correct_within_target", single_within},
                             {"wrong_pose", single_wrong},
                             {"not_found", single_none}};
  }
  return stats;
}

Result<std::vector<RelocTrial>> RunRelocTrials(const std::shared_ptr<mosaic::TileStore>& store,
                                               const relocalization::PlaceIndex* index,
                                               const RelocTrialSettings& settings) {
  const mosaic::MosaicLayout layout = store->layout();
  // The renderer reads the same mosaic through its own view and cache, so it never warms the
  // relocalizer's tiles.
  mosaic::MosaicView floor(layout, mosaic::MakeTileLoader(store),
                           std::make_shared<mosaic::TileCache>(256LL << 20));
  sim::CameraRenderer renderer(&floor, BenchCamera(layout, settings), settings.render,
                               settings.seed);
  std::mt19937_64 rng(settings.seed);
  runtime::PercentLog log("relocalization trials", "trials", 5);
  std::vector<RelocTrial> trials;
  for (int t = 0; t < settings.trials; ++t) {
    const geometry::Pose2 start = sim::RandomFullFramePose(layout, renderer.camera(), rng);
    Result<RelocTrial> trial = RunTrial(store, index, renderer, start, t, settings);
    if (!trial.ok()) return trial.status();
    trials.push_back(std::move(trial).value());
    log(t + 1, settings.trials);
  }
  return trials;
}

}  // namespace fleetloc::bench
