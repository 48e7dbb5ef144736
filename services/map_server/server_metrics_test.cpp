// Map server metric families: counters, the reply latency histogram and the cache hit ratio.
#include "map_server/server_metrics.h"

#include <gtest/gtest.h>

#include "metrics/exposition.h"

namespace fleetloc::map_server {
namespace {

TEST(MapServerMetrics, ExposesCountersLatencyAndCacheHitRatio) {
  metrics::Histogram latency(metrics::Histogram::LatencyBoundsS());
  latency.Observe(0.0008);
  latency.Observe(0.003);
  latency.Observe(0.003);
  MapServerMetricsInput in;
  in.counters = {{"tiles_served", 120}, {"rejected_tile_request", 2}};
  in.tile_reply_latency = latency.Snapshot();
  in.cache.hits = 90;
  in.cache.misses = 30;
  in.cache.bytes = 4096;
  in.tile_requests_pending = 4;
  in.mosaic_version = 7;
  metrics::FamilyBuilder b(kMapServerMetricPrefix, {{"service_id", "map-1"}});
  AddMapServerFamilies(in, &b);
  const std::string text = metrics::ToText(b.Take());
  Result<metrics::Exposition> e = metrics::ParseExposition(text);
  ASSERT_TRUE(e.ok()) << e.status().message() << "\n" << text;
  EXPECT_EQ(*e->Value("fleetloc_map_server_tiles_served_total", {{"service_id", "map-1"}}), 120);
  EXPECT_EQ(*e->Value("fleetloc_map_server_rejected_tile_request_total"), 2);
  EXPECT_EQ(*e->Value("fleetloc_map_server_tile_cache_hit_ratio"), 0.75);
  EXPECT_EQ(*e->Value("fleetloc_map_server_tile_reply_seconds_bucket", {{"le", "0.001"}}), 1);
  EXPECT_EQ(*e->Value("fleetloc_map_server_tile_reply_seconds_bucket", {{"le", "0.004"}}), 3);
  EXPECT_EQ(*e->Value("fleetloc_map_server_tile_reply_seconds_count"), 3);
  EXPECT_EQ(*e->Value("fleetloc_map_server_tile_requests_pending"), 4);
  EXPECT_EQ(*e->Value("fleetloc_map_server_mosaic_version"), 7);
}

TEST(MapServerMetrics, HitRatioIsOneBeforeAnyLookup) {
  metrics::FamilyBuilder b(kMapServerMetricPrefix, {});
  AddMapServerFamilies({}, &b);
  Result<metrics::Exposition> e = metrics::ParseExposition(metrics::ToText(b.Take()));
  ASSERT_TRUE(e.ok()) << e.status().message();
  EXPECT_EQ(*e->Value("fleetloc_map_server_tile_cache_hit_ratio"), 1);
}

}  // namespace
}  // namespace fleetloc::map_server
