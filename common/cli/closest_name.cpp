// ClosestName: optimal string alignment distance over short names.
#include "cli/closest_name.h"

#include <algorithm>

namespace fleetloc::cli {

int EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<int>> d(a.size() + 1, std::vector<int>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = static_cast<int>(i);
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

std::optional<std::string> ClosestName(const std::string& typed,
                                       const std::vector<std::string>& candidates) {
  if (typed.empty()) return std::nullopt;
  std::optional<std::string> best;
  int best_distance = 0;
  for (const std::string& c : candidates) {
    const int distance = c.rfind(typed, 0) == 0 ? 1 : EditDistance(typed, c);
    if (!best || distance < best_distance) {
      best = c;
      best_distance = distance;
    }
  }
  const int limit = std::max<int>(2, static_cast<int>(typed.size()) / 3);
  if (!best || best_distance > limit) return std::nullopt;
  return best;
}

}  // namespace fleetloc::cli
