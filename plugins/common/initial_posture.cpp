#include "initial_posture.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace ballast::plugin {
namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

std::vector<double> initialPosture(const std::vector<std::string>& names,
                                   const std::map<std::string, std::pair<double, double>>& limits,
                                   const std::string& posture, const schema::NamedNumbers& overrides,
                                   const schema::Locations& where, const std::string& urdfPath) {
  const int n = static_cast<int>(names.size());
  auto index = [&](const std::string& name) {
    return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  const bool stand = posture == "stand";
  std::vector<double> q(names.size(), 0.0);
  if (stand)
    for (std::size_t j = 0; j < names.size(); ++j) {
      if (endsWith(names[j], "hip_pitch")) q[j] = -0.4;
      if (endsWith(names[j], "knee")) q[j] = 0.8;
    }
  std::set<int> given;
  for (const auto& [name, angle] : overrides) {
    const int j = index(name);
    const std::string key = "initial_joints." + name;
    if (j == n)
      throw std::runtime_error(where.where(key) + urdfPath + " has no movable joint '" + name + "'");
    const auto [lower, upper] = limits.at(name);
    if (angle < lower || angle > upper)
      throw std::runtime_error(where.where(key) + std::to_string(angle) +
                               " rad is outside the joint's limits [" + std::to_string(lower) +
                               ", " + std::to_string(upper) + "]");
    q[j] = angle;
    given.insert(j);
  }
  if (stand)  // level soles: the ankle undoes hip and knee pitch
    for (std::size_t j = 0; j < names.size(); ++j) {
      if (!endsWith(names[j], "ankle_pitch") || given.count(static_cast<int>(j))) continue;
      const std::string side = names[j].substr(0, names[j].size() - std::string("ankle_pitch").size());
      const int hip = index(side + "hip_pitch"), knee = index(side + "knee");
      if (hip < n && knee < n) q[j] = -(q[hip] + q[knee]);
    }
  return q;
}

}  // namespace ballast::plugin
