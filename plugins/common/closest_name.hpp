// "Did you mean ...?": the name among candidates closest to a misspelt one, by edit distance.
// Shared by ballastd's profile schema and the plugins' sections.
#pragma once

#include <algorithm>
#include <utility>
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

/// Up to `count` candidates nearest to `name`, nearest first, however far (for "no link 'foot';
/// closest: left_ankle_roll_link, ..."): fewest edits, where each '_'-separated word shared with
/// name counts as three edits fewer (vendor names differ in more than typos).
template <typename Names, typename NameOf>
std::vector<std::string> closestNames(const std::string& name, const Names& candidates,
                                      NameOf nameOf, std::size_t count = 3) {
  auto words = [](const std::string& s) {
    std::vector<std::string> w;
    std::string cur;
    for (char c : s + "_") {
      if (c == '_' || c == '-' || c == '/') {
        if (!cur.empty()) w.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    return w;
  };
  const std::vector<std::string> mine = words(name);
  std::vector<std::pair<long, std::string>> scored;
  for (const auto& c : candidates) {
    const std::string n = nameOf(c);
    long score = static_cast<long>(editDistance(name, n));
    for (const std::string& w : words(n))
      if (std::find(mine.begin(), mine.end(), w) != mine.end()) score -= 3;
    scored.emplace_back(score, n);
  }
  std::stable_sort(scored.begin(), scored.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string> out;
  for (const auto& [score, n] : scored) {
    if (out.size() == count) break;
    if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
  }
  return out;
}

/// "a, b, c" of closestNames, for messages.
template <typename Names, typename NameOf>
std::string closestNamesText(const std::string& name, const Names& candidates, NameOf nameOf,
                             std::size_t count = 3) {
  std::string text;
  for (const std::string& n : closestNames(name, candidates, nameOf, count))
    text += (text.empty() ? "" : ", ") + n;
  return text;
}

}  // namespace ballast
