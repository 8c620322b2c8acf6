// The paper's four contact points, the toe and heel of each foot: their number and, in the order
// every module uses (the schedule's flags, the MPC's forces, the estimator's state, the loop's
// status), the frames of the shipped humanoid, which are the profile's default.
#pragma once

#include <array>

namespace ballast::model {

inline constexpr int kNumContacts = 4;
/// Left toe, left heel, right toe, right heel.
inline constexpr std::array<const char*, kNumContacts> kContactFrameNames = {
    "left_toe", "left_heel", "right_toe", "right_heel"};

}  // namespace ballast::model
