// Benchmark tables and verdict.
#include "harness/tracker/bench_report.h"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "support/tracker_summary.h"

namespace fleetloc::bench {
namespace {

constexpr double kComparableRmsFactor = 2.0;  // peers this close in accuracy are raced

replay::ReplayResult FirstResults(const replay::ReplayResult& replayed, std::size_t count) {
  replay::ReplayResult first = replayed;
  first.poses.resize(std::min(count, first.poses.size()));
  first.cycle_ms.resize(std::min(count, first.cycle_ms.size()));
  return first;
}

template <typename T>
void Append(std::vector<T>* to, const std::vector<T>& from) {
  to->insert(to->end(), from.begin(), from.end());
}

// Appends `more` (frames, truth, poses, times) to `all`; the camera is the first one's.
void Concatenate(MethodReplay* all, const MethodReplay& more) {
  Append(&all->run.frames, more.run.frames);
  Append(&all->run.truth, more.run.truth);
  Append(&all->replayed.poses, more.replayed.poses);
  Append(&all->replayed.cycle_ms, more.replayed.cycle_ms);
}

bool IsFleetloc(const std::string& label) { return label.rfind("fleetloc", 0) == 0; }

double LockRate(const BenchRow& row) { return row.summary.value("lock_rate", 0.0); }
double MedianMs(const BenchRow& row) { return row.summary["ms_per_frame"]["median"]; }

// base_link RMS over the locked frames; infinite when the method never locked (no accuracy).
double RmsPx(const BenchRow& row) {
  if (LockRate(row) == 0.0 || !row.summary.contains("error")) {
    return std::numeric_limits<double>::infinity();
  }
  return row.summary["error"]["position_rms_px"];
}

bool Locked(const run_io::PoseRecord& pose) {
  return pose.status == "tracking" || pose.status == "relocalized";
}

// base_link RMS (px) of `m` over the frames where both `m` and `other` are locked, infinite when
// there is none; *common gets their number. Requires both to be replays of the same frames.
double CommonRmsPx(const MethodReplay& m, const MethodReplay& other, std::size_t* common) {
  std::vector<run_io::PoseRecord> poses;
  std::vector<geometry::StampedPose> truth;
  for (std::size_t i = 0; i < m.replayed.poses.size() && i < m.run.truth.size(); ++i) {
    if (!Locked(m.replayed.poses[i]) || !Locked(other.replayed.poses[i])) continue;
    poses.push_back(m.replayed.poses[i]);
    truth.push_back(m.run.truth[i]);
  }
  *common = poses.size();
  if (poses.empty()) return std::numeric_limits<double>::infinity();
  const geometry::CameraModel& camera = m.run.camera.model;
  return replay::Evaluate(poses, truth, camera).position_rms_m / camera.resolution_m;
}

bool MoreAccurate(const Comparison& c) {
  const bool lower = c.common_frames > 0 ? c.fleetloc_common_rms_px < c.peer_common_rms_px
                                         : c.fleetloc_lock_rate > 0 && c.peer_lock_rate == 0;
  return lower && c.fleetloc_lock_rate >= c.peer_lock_rate;
}

Comparison Compare(const BenchRow& fleetloc, const BenchRow& peer) {
  Comparison c;
  c.peer = peer.label();
  c.fleetloc = fleetloc.label();
  c.peer_rms_px = RmsPx(peer);
  c.fleetloc_rms_px = RmsPx(fleetloc);
  c.fleetloc_common_rms_px = CommonRmsPx(fleetloc.replay, peer.replay, &c.common_frames);
  c.peer_common_rms_px = CommonRmsPx(peer.replay, fleetloc.replay, &c.common_frames);
  c.peer_lock_rate = LockRate(peer);
  c.fleetloc_lock_rate = LockRate(fleetloc);
  c.peer_ms = MedianMs(peer);
  c.fleetloc_ms = MedianMs(fleetloc);
  c.more_accurate = MoreAccurate(c);
  c.comparable = c.peer_rms_px <= kComparableRmsFactor * c.fleetloc_rms_px;
  c.faster = c.fleetloc_ms < c.peer_ms;
  return c;
}

// A cell of an error column: "-" when the method never locked (errors over no frames).
std::string ErrorCell(const BenchRow& row, const char* field, int decimals) {
  if (LockRate(row) == 0.0 || !row.summary.contains("error")) return "-";
  return fmt::format("{:.{}f}", row.summary["error"][field].get<double>(), decimals);
}

std::string RmsText(double rms_px) {
  return std::isfinite(rms_px) ? fmt::format("{:.4f} px", rms_px) : "-";
}

}  // namespace

std::vector<MethodReplay> TableReplays(const FloorBench& floor) {
  std::vector<MethodReplay> replays = floor.methods;
  const bool has_peer = std::any_of(replays.begin(), replays.end(),
                                    [](const MethodReplay& m) { return !IsFleetloc(m.label); });
  if (!has_peer || floor.peer_frames >= floor.frames) return replays;
  const auto fleetloc = std::find_if(replays.begin(), replays.end(),
                                     [](const MethodReplay& m) { return m.label == "fleetloc"; });
  if (fleetloc == replays.end()) return replays;
  const std::size_t n = static_cast<std::size_t>(floor.peer_frames);
  MethodReplay first{"fleetloc@" + std::to_string(n), FirstFrames(fleetloc->run, n),
                     FirstResults(fleetloc->replayed, n)};
  replays.insert(fleetloc + 1, std::move(first));
  return replays;
}

std::vector<MethodReplay> OverallReplays(const std::vector<FloorBench>& floors) {
  std::vector<MethodReplay> overall;
  for (const FloorBench& floor : floors) {
    for (const MethodReplay& replay : TableReplays(floor)) {
      const auto same = std::find_if(overall.begin(), overall.end(), [&](const MethodReplay& m) {
        return m.label == replay.label;
      });
      if (same == overall.end()) {
        overall.push_back(replay);
      } else {
        Concatenate(&*same, replay);
      }
    }
  }
  return overall;
}

std::vector<BenchRow> ScoreRows(std::vector<MethodReplay> replays) {
  std::vector<BenchRow> rows;
  for (MethodReplay& m : replays) {
    nlohmann::json summary = fleetctl::TrackSummary(m.run, m.replayed);
    rows.push_back({std::move(m), std::move(summary)});
  }
  return rows;
}

Verdict Judge(const std::vector<BenchRow>& rows) {
  Verdict verdict;
  verdict.more_accurate = verdict.faster = true;
  for (const BenchRow& peer : rows) {
    if (IsFleetloc(peer.label())) continue;
    const auto fleetloc = std::find_if(rows.begin(), rows.end(), [&](const BenchRow& r) {
      return IsFleetloc(r.label()) && r.frames() == peer.frames();
    });
    if (fleetloc == rows.end()) continue;
    const Comparison c = Compare(*fleetloc, peer);
    verdict.applicable = true;
    verdict.more_accurate &= c.more_accurate;
    verdict.faster &= c.faster || !c.comparable;
    verdict.comparisons.push_back(c);
  }
  return verdict;
}

void PrintTable(std::ostream& out, const std::string& title, const std::vector<BenchRow>& rows) {
  if (!title.empty()) out << title << "\n";
  out << fmt::format("{:<14} {:>6} {:>8} {:>8} {:>10} {:>11} {:>9} {:>6} {:>9} {:>9}\n", "method",
                     "frames", "RMS px", "p95 px", "cam RMS px", "heading RMS", "lock rate", "lost",
                     "ms median", "ms p95");
  out << fmt::format("{:<14} {:>6} {:>8} {:>8} {:>10} {:>11} {:>9} {:>6} {:>9} {:>9}\n", "", "", "",
                     "", "", "deg", "", "frames", "per frame", "per frame");
  for (const BenchRow& row : rows) {
    const nlohmann::json& ms = row.summary["ms_per_frame"];
    const int lost = row.summary["status_counts"].value("lost", 0);
    out << fmt::format(
        "{:<14} {:>6} {:>8} {:>8} {:>10} {:>11} {:>9.3f} {:>6} {:>9.2f} {:>9.2f}\n", row.label(),
        row.frames(), ErrorCell(row, "position_rms_px", 3), ErrorCell(row, "position_p95_px", 3),
        ErrorCell(row, "camera_position_rms_px", 3), ErrorCell(row, "heading_rms_deg", 4),
        LockRate(row), lost, ms["median"].get<double>(), ms["p95"].get<double>());
  }
}

void PrintVerdict(std::ostream& out, const std::string& title, const Verdict& verdict) {
  if (!verdict.applicable) {
    out << "verdict " << title << ": n/a (needs fleetloc and at least one peer)\n";
    return;
  }
  for (const Comparison& c : verdict.comparisons) {
    out << fmt::format(
        "  {} vs {}: RMS {} vs {} on the {} frames both locked, lock rate {:.3f} vs {:.3f} -> {}; "
        "median {:.2f} vs {:.2f} ms -> {}\n",
        c.fleetloc, c.peer, RmsText(c.fleetloc_common_rms_px), RmsText(c.peer_common_rms_px),
        c.common_frames, c.fleetloc_lock_rate, c.peer_lock_rate,
        c.more_accurate ? "more accurate" : "NOT more accurate", c.fleetloc_ms, c.peer_ms,
        !c.comparable ? "not raced (peer RMS > 2x)" : (c.faster ? "faster" : "NOT faster"));
  }
  out << fmt::format(
      "verdict {}: more accurate than every peer: {}; faster than every peer "
      "within 2x of its RMS: {}\n",
      title, verdict.more_accurate ? "yes" : "no", verdict.faster ? "yes" : "no");
}

nlohmann::json RowsJson(const std::vector<BenchRow>& rows) {
  nlohmann::json json = nlohmann::json::object();
  for (const BenchRow& row : rows) json[row.label()] = row.summary;
  return json;
}

nlohmann::json VerdictJson(const Verdict& verdict) {
  nlohmann::json comparisons = nlohmann::json::array();
  const auto finite_or_null = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nullptr;
  };
  for (const Comparison& c : verdict.comparisons) {
    comparisons.push_back({{"peer", c.peer},
                           {"fleetloc", c.fleetloc},
                           {"peer_rms_px", finite_or_null(c.peer_rms_px)},
                           {"fleetloc_rms_px", finite_or_null(c.fleetloc_rms_px)},
                           {"common_locked_frames", c.common_frames},
                           {"peer_common_rms_px", finite_or_null(c.peer_common_rms_px)},
                           {"fleetloc_common_rms_px", finite_or_null(c.fleetloc_common_rms_px)},
                           {"peer_lock_rate", c.peer_lock_rate},
                           {"fleetloc_lock_rate", c.fleetloc_lock_rate},
                           {"peer_ms_median", c.peer_ms},
                           {"fleetloc_ms_median", c.fleetloc_ms},
                           {"more_accurate", c.more_accurate},
                           {"speed_compared", c.comparable},
                           {"faster", c.faster}});
  }
  if (!verdict.applicable) return {{"applicable", false}};
  return {{"applicable", true},
          {"more_accurate_than_every_peer", verdict.more_accurate},
          {"faster_than_every_comparable_peer", verdict.faster},
          {"comparisons", comparisons}};
}

}  // namespace fleetloc::bench
