// The four contact points of the paper's model (toe and heel of each foot) and their flags.
#pragma once

#include <array>

#include "model/contact_points.hpp"

namespace ballast::gait {

using model::kContactFrameNames;
using model::kNumContacts;
enum Contact : int { kLeftToe = 0, kLeftHeel = 1, kRightToe = 2, kRightHeel = 3 };

/// true = closed contact (stance), false = open (swing).
using ContactFlags = std::array<bool, kNumContacts>;

inline constexpr ContactFlags kAllStance = {true, true, true, true};

inline bool isLeft(int contact) { return contact == kLeftToe || contact == kLeftHeel; }
inline int numStance(const ContactFlags& f) {
  int n = 0;
  for (bool s : f) n += s;
  return n;
}

}  // namespace ballast::gait
