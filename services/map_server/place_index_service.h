// The place index the map server serves its vehicles for global relocalization: for each mosaic
// version it serves, a worker thread loads the index from the mosaic file's cache or builds it
// from the mosaic (with progress; a large mosaic takes a while), and the DDS thread then publishes
// it in chunks (PlaceIndexChunk, durable). The previous version's index stays published while the
// next one is built: it still relocalizes everywhere outside the re-mapped region, and the
// relocalizer verifies every candidate against the current tiles. Once an index is ready, the
// worker also checks the floor's self-similarity (relocalization::FindSelfSimilarity: frame-sized
// places on a grid, each searched densely over the whole floor), logs every place with a twin
// and keeps a warning for the health report.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "map_server/server_counters.h"
#include "transport/place_index_channel.h"

namespace fleetloc::map_server {

class PlaceIndexService {
 public:
  static std::vector<std::string> CounterNames();

  // `self_similarity_grid`: places per side checked after each index (0: none).
  PlaceIndexService(std::string mosaic_path, transport::PlaceIndexPublisher* publisher,
                    ServerCounters* counters, int self_similarity_grid = 0);
  ~PlaceIndexService();  // cancels a build in progress and joins the worker

  // Asks for the index of the mosaic's current version (what the file holds when the worker
  // gets to it); requests made while one is pending are merged.
  void RequestCurrent();
  // On the DDS thread: publishes the index the worker finished, if any.
  void PublishReady();
  long long published_version() const { return published_version_; }
  // "N of M places have a twin: ..." while the newest check named some; any thread.
  std::optional<std::string> self_similarity_warning() const;

 private:
  struct Ready {
    std::string mosaic_id;
    long long version = 0;
    std::vector<std::uint8_t> blob;
  };
  void Work();
  // Loads or builds the index of the mosaic's current version; nullopt (counted) on failure.
  std::optional<Ready> LoadOrBuild();
  // The self-similarity of the mosaic's current version, seen by a 640×480 frame at the mosaic's
  // resolution; skipped (logged, counted) when the mosaic is too large for the dense search.
  void CheckSelfSimilarity();

  const std::string mosaic_path_;
  transport::PlaceIndexPublisher* publisher_;
  ServerCounters* counters_;
  long long published_version_ = -1;
  const int self_similarity_grid_;
  mutable std::mutex mutex_;
  std::optional<std::string> self_similarity_warning_;
  std::condition_variable wake_;
  bool requested_ = false;
  std::optional<Ready> ready_;
  std::atomic<bool> stopping_{false};
  std::thread worker_;
};

}  // namespace fleetloc::map_server
