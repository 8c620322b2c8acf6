// The four contact points of the paper's model (toe and heel of each foot) and their flags.
#pragma once

#include <array>

namespace ballast::gait {

inline constexpr int kNumContacts = 4;
enum Contact : int { kLeftToe = 0, kLeftHeel = 1, kRightToe = 2, kRightHeel = 3 };
/// URDF frame names, in Contact order.
inline constexpr std::array<const char*, kNumContacts> kContactFrameNames = {
    "left_toe", "left_heel", "right_toe", "right_heel"};

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
