// Table, verdict and JSON of the mosaic store benchmark.
#include "harness/mosaic/bench_mosaic_report.h"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

namespace fleetloc::bench {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

double ImportMpxPerSecond(const MosaicSizeBench& s) {
  return s.import.wall_s > 0 ? s.megapixels() / s.import.wall_s : 0;
}

std::string P50P99(const Latency& l) { return fmt::format("{:.0f}/{:.0f}", l.p50_us, l.p99_us); }

double Ratio(double num, double den) { return den > 0 ? num / den : 0; }

nlohmann::json ChildJson(const ChildRun& run) {
  return {{"wall_s", run.wall_s},
          {"user_s", run.user_s},
          {"system_s", run.system_s},
          {"peak_rss_bytes", run.peak_rss_bytes}};
}

nlohmann::json LatencyJson(const Latency& l) {
  return {
      {"samples", l.samples}, {"p50_us", l.p50_us}, {"p99_us", l.p99_us}, {"mean_us", l.mean_us}};
}

}  // namespace

ScalingVerdict JudgeScaling(const std::vector<MosaicSizeBench>& sizes) {
  FLEETLOC_CHECK(!sizes.empty());
  const auto by_pixels = [](const MosaicSizeBench& a, const MosaicSizeBench& b) {
    return a.size_px.area() < b.size_px.area();
  };
  const auto by_rss = [](const MosaicSizeBench& a, const MosaicSizeBench& b) {
    return a.import.peak_rss_bytes < b.import.peak_rss_bytes;
  };
  const auto [small, large] = std::minmax_element(sizes.begin(), sizes.end(), by_pixels);
  const auto [low, high] = std::minmax_element(sizes.begin(), sizes.end(), by_rss);
  ScalingVerdict v;
  v.applicable = sizes.size() >= 2;
  v.pixel_ratio = Ratio(large->megapixels(), small->megapixels());
  v.rss_ratio = Ratio(high->import.peak_rss_bytes, low->import.peak_rss_bytes);
  v.rss_bounded = v.rss_ratio <= kMaxImportRssRatio;
  const LookupLatencies a = Summarize(small->lookups.samples);
  const LookupLatencies b = Summarize(large->lookups.samples);
  v.tile_bytes_ratio = Ratio(b.tile_bytes.p50_us, a.tile_bytes.p50_us);
  v.tile_decoded_ratio = Ratio(b.tile_decoded.p50_us, a.tile_decoded.p50_us);
  v.block_cold_ratio = Ratio(b.block_cold.p50_us, a.block_cold.p50_us);
  v.block_warm_ratio = Ratio(b.block_warm.p50_us, a.block_warm.p50_us);
  v.lookups_flat = std::max({v.tile_bytes_ratio, v.tile_decoded_ratio, v.block_cold_ratio,
                             v.block_warm_ratio}) <= kMaxLookupP50Ratio;
  return v;
}

void PrintMosaicTable(std::ostream& out, const std::vector<MosaicSizeBench>& sizes) {
  constexpr const char* kRow =
      "{:<12} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>6} {:>9} {:>9} {:>11} {:>9}\n";
  out << fmt::format(kRow, "size", "Mpx", "compose", "import", "import", "import", "import",
                     "mosaic", "tiles", "levels", "tile read", "decoded", "block cold",
                     "block warm");
  out << fmt::format(kRow, "", "", "s", "s", "CPU s", "Mpx/s", "RSS MiB", "MiB", "", "", "p50/p99",
                     "p50/p99", "p50/p99", "p50/p99");
  out << fmt::format(kRow, "", "", "", "", "", "", "", "", "", "", "us", "us", "us", "us");
  for (const MosaicSizeBench& s : sizes) {
    const LookupLatencies l = Summarize(s.lookups.samples);
    out << fmt::format(
        kRow, fmt::format("{}x{}", s.size_px.width, s.size_px.height),
        fmt::format("{:.1f}", s.megapixels()), fmt::format("{:.1f}", s.compose.wall_s),
        fmt::format("{:.1f}", s.import.wall_s),
        fmt::format("{:.1f}", s.import.user_s + s.import.system_s),
        fmt::format("{:.1f}", ImportMpxPerSecond(s)),
        fmt::format("{:.1f}", s.import.peak_rss_bytes / kMiB),
        fmt::format("{:.0f}", s.mosaic_bytes / kMiB), s.lookups.tiles, s.lookups.levels,
        P50P99(l.tile_bytes), P50P99(l.tile_decoded), P50P99(l.block_cold), P50P99(l.block_warm));
  }
  if (!sizes.empty()) out << "tile lookup plan: " << sizes.back().lookups.query_plan << "\n";
}

void PrintScalingVerdict(std::ostream& out, const ScalingVerdict& v) {
  if (!v.applicable) {
    out << "verdict: needs at least two sizes\n";
    return;
  }
  out << fmt::format(
      "verdict: import peak RSS max/min {:.2f} over {:.0f}x the pixels -> bounded: {}; lookup p50 "
      "largest/smallest: tile read {:.2f}, decoded {:.2f}, block cold {:.2f}, block warm {:.2f} "
      "-> flat: {}\n",
      v.rss_ratio, v.pixel_ratio, v.rss_bounded ? "yes" : "no", v.tile_bytes_ratio,
      v.tile_decoded_ratio, v.block_cold_ratio, v.block_warm_ratio, v.lookups_flat ? "yes" : "no");
}

nlohmann::json MosaicSizeJson(const MosaicSizeBench& s) {
  const LookupRun& run = s.lookups;
  const LookupLatencies l = Summarize(run.samples);
  return {{"size_px", {s.size_px.width, s.size_px.height}},
          {"megapixels", s.megapixels()},
          {"compose", ChildJson(s.compose)},
          {"import", ChildJson(s.import)},
          {"import_mpx_per_s", ImportMpxPerSecond(s)},
          {"caller_rss_bytes_at_fork", s.caller_rss_bytes},
          {"pgm_bytes", s.pgm_bytes},
          {"mosaic_bytes", s.mosaic_bytes},
          {"lookup",
           {{"process", ChildJson(s.lookup)},
            {"levels", run.levels},
            {"tiles", run.tiles},
            {"query_plan", run.query_plan},
            {"missing_tiles", run.missing_tiles},
            {"tile_bytes", LatencyJson(l.tile_bytes)},
            {"tile_decoded", LatencyJson(l.tile_decoded)},
            {"block_cold", LatencyJson(l.block_cold)},
            {"block_warm", LatencyJson(l.block_warm)}}}};
}

nlohmann::json ScalingVerdictJson(const ScalingVerdict& v) {
  return {{"applicable", v.applicable},
          {"pixel_ratio", v.pixel_ratio},
          {"import_rss_ratio", v.rss_ratio},
          {"import_rss_bounded", v.rss_bounded},
          {"max_import_rss_ratio", kMaxImportRssRatio},
          {"lookup_p50_ratio",
           {{"tile_bytes", v.tile_bytes_ratio},
            {"tile_decoded", v.tile_decoded_ratio},
            {"block_cold", v.block_cold_ratio},
            {"block_warm", v.block_warm_ratio}}},
          {"lookups_flat", v.lookups_flat},
          {"max_lookup_p50_ratio", kMaxLookupP50Ratio}};
}

}  // namespace fleetloc::bench
