// The nearest of a few names to a mistyped one, for "did you mean" hints.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace fleetloc::cli {

// Edit distance (insertions, deletions, substitutions, adjacent transpositions) between a and b.
int EditDistance(const std::string& a, const std::string& b);

// The candidate nearest to `typed` if it is within max(2, size/3) edits (a prefix of a candidate
// also counts), else nullopt. Ties go to the first candidate.
std::optional<std::string> ClosestName(const std::string& typed,
                                       const std::vector<std::string>& candidates);

}  // namespace fleetloc::cli
