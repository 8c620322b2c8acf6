// "Did you mean ...?": the name among candidates closest to a misspelt one, by edit distance.
// Shared by ballastd's profile schema and the plugins' sections.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace ballast {

/// Levenshtein distance.
inline std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diag = up;
    }
  }
  return row[b.size()];
}

/// The candidate closest to `name` when it is a typo (at most 3 edits away), else "".
template <typename Names, typename NameOf>
std::string closestName(const std::string& name, const Names& candidates, NameOf nameOf) {
  std::string best;
  std::size_t bestDistance = 4;  // more edits than this is not a typo
  for (const auto& c : candidates) {
    const std::string n = nameOf(c);
    const std::size_t d = editDistance(name, n);
    if (d < bestDistance) bestDistance = d, best = n;
  }
  return best;
}

}  // namespace ballast
