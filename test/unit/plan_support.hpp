// What a locomotion plan says about the steps: the touch-downs of every swing it holds.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "locomotion/plan.hpp"

namespace ballast::test {

struct TouchDown {
  int contact;
  Eigen::Vector3d position;  ///< world
};

/// Every swing of the plan's horizon once, sampled every 5 ms (shorter than any swing).
inline std::vector<TouchDown> plannedTouchDowns(const locomotion::Plan& plan) {
  std::vector<TouchDown> out;
  for (int c = 0; c < locomotion::kNumContacts; ++c) {
    const gait::SwingTrajectory* last = nullptr;
    for (double t = plan.t0; t < plan.t0 + plan.nodes * plan.dt; t += 0.005)
      if (const gait::SwingTrajectory* s = plan.swings.swingAt(c, t); s && s != last) {
        out.push_back({c, s->touchDownPosition});
        last = s;
      }
  }
  return out;
}

}  // namespace ballast::test
