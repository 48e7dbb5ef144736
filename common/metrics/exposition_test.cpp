// ParseExposition: accepts the format, refuses each kind of broken line with its line number.
#include "metrics/exposition.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::metrics {
namespace {

TEST(ParseExposition, ReadsHelpTypeSamplesAndTimestamps) {
  const char* text =
      "# HELP a_total Things.\n# TYPE a_total counter\na_total{x=\"1\",y=\"2\",} 3 1700000000000\n"
      "# a comment\n\n# TYPE g gauge\ng NaN\ng{k=\"v\"} -Inf\ng{k=\"w\"} Nan\n";
  Result<Exposition> e = ParseExposition(text);
  ASSERT_TRUE(e.ok()) << e.status().message();
  ASSERT_EQ(e->samples.size(), 4u);  // "Nan" as prometheus-cpp writes it: Prometheus reads it too
  EXPECT_EQ(*e->Value("a_total", {{"y", "2"}}), 3);
  EXPECT_TRUE(std::isinf(*e->Value("g", {{"k", "v"}})));
  EXPECT_FALSE(e->Value("a_total", {{"y", "3"}}).ok());
}

TEST(ParseExposition, RefusesBrokenLinesNamingTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"# TYPE a counter\na 1\nb 2\n", "line 3: sample b before its TYPE"},
      {"# TYPE a counter\na{x=1} 1\n", "line 2: label x"},
      {"# TYPE a counter\na{x=\"1\" 1\n", "line 2: expected , or }"},
      {"# TYPE a counter\na one\n", "line 2: bad value"},
      {"# TYPE a counter\na -1\n", "negative counter"},
      {"# TYPE a widget\n", "line 1: unknown type"},
      {"# TYPE a gauge\n# TYPE a gauge\n", "line 2: second TYPE"},
      {"# TYPE a gauge\na 1 12x\n", "bad timestamp"},
      {"# TYPE 1a gauge\n", "line 1: bad metric name"},
      {"# TYPE a gauge\na 1", "no newline"},
      {"# TYPE a gauge\na{x=\"\\q\"} 1\n", "bad escape"},
  };
  for (const auto& [text, want] : cases) {
    Result<Exposition> e = ParseExposition(text);
    ASSERT_FALSE(e.ok()) << text;
    EXPECT_NE(e.status().message().find(want), std::string::npos)
        << e.status().message() << " for " << text;
  }
}

TEST(ParseExposition, ChecksHistogramShape) {
  const std::string head = "# TYPE h histogram\n";
  EXPECT_TRUE(
      ParseExposition(head + "h_bucket{le=\"1\"} 1\nh_bucket{le=\"+Inf\"} 2\nh_sum 3\nh_count 2\n")
          .ok());
  const std::pair<std::string, const char*> cases[] = {
      {"h_bucket{le=\"1\"} 1\nh_sum 3\nh_count 1\n", "no +Inf"},
      {"h_bucket{le=\"1\"} 3\nh_bucket{le=\"+Inf\"} 2\nh_count 2\n", "not cumulative"},
      {"h_bucket{le=\"+Inf\"} 2\nh_count 3\n", "differs from _count"},
      {"h_bucket 2\nh_count 2\n", "without a numeric le"},
  };
  for (const auto& [body, want] : cases) {
    Result<Exposition> e = ParseExposition(head + body);
    ASSERT_FALSE(e.ok()) << body;
    EXPECT_NE(e.status().message().find(want), std::string::npos) << e.status().message();
  }
}

}  // namespace
}  // namespace fleetloc::metrics
