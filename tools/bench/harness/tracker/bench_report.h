// `fleetctl bench tracker` results: each replay scored with `fleetctl track`'s JSON summary, the
// per-floor and overall tables, and the verdict (is fleetloc more accurate than every peer, and
// faster than every peer of comparable accuracy).
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "harness/tracker/bench_tracker.h"

namespace fleetloc::bench {

// The replays a floor's table shows: every method's, plus "fleetloc@N" (fleetloc's first N frames)
// when the peers replayed only the first N frames, so fleetloc is judged on the peers' frames.
std::vector<MethodReplay> TableReplays(const FloorBench& floor);

// TableReplays of every floor, those with the same label concatenated (the overall table).
std::vector<MethodReplay> OverallReplays(const std::vector<FloorBench>& floors);

// One table row: a replay scored as `fleetctl track` scores it (TrackSummary).
struct BenchRow {
  MethodReplay replay;
  nlohmann::json summary;
  const std::string& label() const { return replay.label; }
  std::size_t frames() const { return replay.replayed.poses.size(); }
};
std::vector<BenchRow> ScoreRows(std::vector<MethodReplay> replays);

// fleetloc against one peer, both on the peer's frames. RMS values are of base_link in pixels,
// infinite when there is no locked frame to take them over.
struct Comparison {
  std::string peer;
  std::string fleetloc;  // the fleetloc row compared with ("fleetloc" or "fleetloc@N")
  double peer_rms_px = 0, fleetloc_rms_px = 0;  // each over its own locked frames (the table's)
  std::size_t common_frames = 0;                // frames both locked
  double peer_common_rms_px = 0, fleetloc_common_rms_px = 0;  // over those
  double peer_lock_rate = 0, fleetloc_lock_rate = 0;
  double peer_ms = 0, fleetloc_ms = 0;  // median per frame
  // Lower RMS on the frames both locked (or the peer never locked while fleetloc did) and a lock
  // rate at least as high: accuracy compared like for like, never bought by skipping hard frames.
  bool more_accurate = false;
  bool comparable = false;  // peer RMS within 2x fleetloc's (own locked frames): speed is raced
  bool faster = false;      // lower median time per frame
};

struct Verdict {
  bool applicable = false;  // fleetloc and at least one peer were run
  bool more_accurate = false;
  bool faster = false;  // than every comparable peer
  std::vector<Comparison> comparisons;
};
Verdict Judge(const std::vector<BenchRow>& rows);

void PrintTable(std::ostream& out, const std::string& title, const std::vector<BenchRow>& rows);
void PrintVerdict(std::ostream& out, const std::string& title, const Verdict& verdict);

// {label: summary} and the verdict with its comparisons, for --json.
nlohmann::json RowsJson(const std::vector<BenchRow>& rows);
nlohmann::json VerdictJson(const Verdict& verdict);

}  // namespace fleetloc::bench
