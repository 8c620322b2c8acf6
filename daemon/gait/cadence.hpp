// The walking gait at a speed: faster walking takes shorter cycles and a shorter double support,
// as a human's does, so that a step stays within the legs' reach and a swing leg is not asked to
// move faster than it can.
//
// At planar speed v a cycle of period T covers a stride v·T: each step puts a foot v·T/2 ahead
// of the other, and each swing foot covers the stride in the swing, ½(1 − double support)·T,
// at a mean speed of 2v / (1 − double support), whatever T is. With heavy legs the swing's speed
// is what the body feels (the leg's reaction moves the torso): at 1.5 m/s the humanoid falls
// within 3 s with its swing at 3.75 m/s (gait.double_support 0.2) whatever the period (0.6-1.0
// s), within 6 s at 3.53 m/s, and walks at 3.33; with steps of 0.75 m (period 1.0 s) it falls
// whatever the swing.
#pragma once

#include <algorithm>

#include "gait/contact_schedule.hpp"

namespace ballast::gait {

/// `walk` with its double support shortened (to none at the most) so that a swing over
/// `distance` (m, horizontal) moves its foot at a mean speed of at most `maxSwingSpeed` (m/s):
/// the swing takes ½(1 − double support)·period, and a step's touch-downs stay where they are
/// (every half period). False when even with no double support the swing would be faster; the
/// double support is then none. A limit ≤ 0 is none.
inline bool fitSwing(Gait& walk, double distance, double maxSwingSpeed) {
  if (!(maxSwingSpeed > 0.0)) return true;
  const double doubleSupport = 1.0 - 2.0 * distance / (walk.period * maxSwingSpeed);
  walk.doubleSupport = std::clamp(doubleSupport, 0.0, walk.doubleSupport);
  return doubleSupport >= 0.0;
}

/// `walk` at planar speed `speed` (m/s): the period shortened so that a step, speed·period/2,
/// is at most `maxStepLength` (m), then the double support shortened (to none at the most) so
/// that a swing foot's mean speed is at most `maxSwingSpeed` (m/s). A limit ≤ 0 is none.
/// Unchanged where both hold, and when standing.
inline Gait gaitAtSpeed(Gait walk, double speed, double maxStepLength, double maxSwingSpeed) {
  if (!walk.walking || !(speed > 0.0)) return walk;
  if (maxStepLength > 0.0 && 0.5 * speed * walk.period > maxStepLength)
    walk.period = 2.0 * maxStepLength / speed;
  fitSwing(walk, speed * walk.period, maxSwingSpeed);  // each swing covers the stride v·T
  return walk;
}

}  // namespace ballast::gait
