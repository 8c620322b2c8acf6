// Standing recovery steps (issue 13): when a standing robot has to step, with which foot first,
// and when the steps have done their work.
//
// Standing, the centre of pressure can be anywhere in the support polygon (the hull of the four
// contact points). Against a horizontal force f the capture point ξ holds still when the centre of
// pressure is at ξ + d, d = f/(m ω²) (capture_point.hpp): that point is what must stay inside. A
// push carries it out; once it is outside by more than `margin`, no ankle or hip torque brings
// the body back and the robot steps (the step adjustment's footholds from the capture point,
// step_adjustment.hpp, at zero commanded velocity: deadbeat in the pendulum model). The first
// foot to step is the one on the side the point left to: a step of the other foot towards it
// would have to cross the stance leg (the feet-distance constraint keeps it on its own side).
// Stepping stops once the point is inside again by `margin` and the centre of mass moves slower
// than `settleSpeed`: standing then holds it where the feet are.
//
// Step timing: the recovery walks the walking gait, but with a shorter period when its first
// step would otherwise land too late. That step lands half a period after the recovery begins
// (the double support, then the swing); meanwhile the centre of pressure is at best the point p
// of the stance foot's support nearest ξ + d (the controllers' model: its toe-heel segment), and
// ξ + d runs away from p by e^{ωt}. The period is the longest, up to the walking gait's, at
// whose touch-down ξ + d is still within the step's reach of the stance foot (StepLimits: ahead,
// behind, the widest step); when none is, the shortest the legs swing (`minPeriod`). A push
// sideways needs a step of the foot it loads, after a single support on the other foot whose
// toe-heel line holds no sideways centre of pressure: that step has to be quick. A push along
// the feet keeps the centre of pressure on a toe or a heel and the step its time.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "gait/capture_point.hpp"
#include "gait/contact.hpp"
#include "gait/step_adjustment.hpp"

namespace ballast::gait {

/// Filled by the profile (gait.recovery_*: defaults and bounds in daemon/profile/schema.cpp).
struct RecoveryParameters {
  bool enabled = true;
  // 0: the point leaving the polygon at all starts steps. At 0.02 m a push on a diagonal (or
  // 70 N along an axis) tipped the standing robot over a foot's corner or edge, the other foot
  // unloaded, before the point was that far out, and the first step fell.
  double margin = 0.0;       ///< m beyond the support polygon that starts steps (and inside it, ends them)
  double settleSpeed = 0.1;  ///< m/s: the centre of mass slower than this ends the steps
  double minPeriod = 0.6;    ///< s: the shortest gait cycle of the recovery steps
  /// Walking on the paper's footholds, an estimated push (horizontal, past the estimator's
  /// deadband) stronger than this times the robot's mass hands the footholds to the capture
  /// point's, the push in the MPC's dynamics, until it has stayed under half that for a gait
  /// cycle. Per kilogram because what a push does to the gait is the acceleration it gives the
  /// body. 0: never.
  double walkingPushForcePerKg = 0.32;  ///< N/kg

  /// N: the walking push switch on a robot of this mass (kg).
  double walkingPushForce(double mass) const { return walkingPushForcePerKg * mass; }
};

/// Walking, under a push (the walking push switch): the footholds are the capture point's along
/// `axis` (unit, world); across it they are the capture point's moved a fraction `paperAcross`
/// (0 to 1) of the way to the paper's.
struct WalkingPushAxis {
  Eigen::Vector2d axis = Eigen::Vector2d::Zero();
  double paperAcross = 0.0;
};

/// `push`: the estimated push's direction, `walking`: the commanded velocity, world x, y. The
/// axis is the push's; paperAcross is cos 2θ, θ the angle between the push and the walk, down to
/// none from 45° on (and standing).
///
/// A push along the walk takes the gait past its command: steps held to the step limits,
/// shorter cycles, faster swings, the heavy legs' swings rocking the body sideways. The capture
/// point's footholds across the push answer that sway with a deadbeat step each time, and the
/// sway grew (1.0 m/s, 60 N along +x: the body's sideways velocity from ±0.2 to ±0.45 m/s, the
/// feet 0.54 m apart, a step crossed in next to the other foot and the robot fell). Across such
/// a push there is nothing to catch: the paper's footholds, which walk steadier (README, the
/// study), keep the gait there. A push against or across the walk keeps the capture point's
/// footholds both ways: with the paper's sideways under a push from ahead at 0.5 m/s the body
/// rolled 10° and fell. In between the share goes down smoothly: with all or nothing at 45°,
/// a diagonal push's estimate crossed that line back and forth, and 1.0 m/s at 45° fell at 3 more
/// phases of 8.
inline WalkingPushAxis walkingPushAxis(const Eigen::Vector2d& push,
                                       const Eigen::Vector2d& walking) {
  WalkingPushAxis a;
  const double norms = push.squaredNorm() * walking.squaredNorm();
  if (!(norms > 0.0)) return a;
  a.axis = push.normalized();
  const double along = push.dot(walking);
  const double across = push.x() * walking.y() - push.y() * walking.x();
  if (along > 0.0) a.paperAcross = std::clamp((along * along - across * across) / norms, 0.0, 1.0);
  return a;
}

/// Where the robot's centre of pressure must be to hold its capture point still, and how far that
/// is outside the support polygon.
struct SupportCheck {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< ξ + d, world
  double outside = 0.0;  ///< signed distance to the polygon of the contacts, m (> 0 outside)
};

inline SupportCheck supportCheck(const std::array<Eigen::Vector3d, kNumContacts>& contacts,
                                 const Eigen::Vector2d& com, const Eigen::Vector2d& comVelocity,
                                 const Eigen::Vector2d& force, double mass, double omega) {
  Eigen::Matrix<double, 2, kNumContacts> polygon;
  for (int c = 0; c < kNumContacts; ++c) polygon.col(c) = contacts[c].head<2>();
  SupportCheck s;
  s.point = capturePoint(com, comVelocity, omega) + forceOffset(force, mass, omega);
  s.outside = signedDistanceToHull<kNumContacts>(polygon, s.point);
  return s;
}

/// A recovery begins: the point is outside the support polygon by more than the margin.
inline bool needsStep(const SupportCheck& s, const RecoveryParameters& p) {
  return p.enabled && s.outside > p.margin;
}

/// The recovery has done its work: the point inside by the margin, the centre of mass slow.
inline bool recovered(const SupportCheck& s, double comSpeed, const RecoveryParameters& p) {
  return s.outside < -p.margin && comSpeed < p.settleSpeed;
}

/// The left foot steps first when the point is left of the middle of the feet (heading frame
/// `yaw`), else the right.
inline bool leftFootFirst(const Eigen::Vector2d& point,
                          const std::array<Eigen::Vector3d, kNumContacts>& contacts, double yaw) {
  Eigen::Vector2d middle = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& c : contacts) middle += c.head<2>() / kNumContacts;
  const Eigen::Vector2d d = point - middle;
  return toHeading(d, yaw).y() >= 0.0;
}

/// The recovery gait's period, s (step timing, header comment). `point`: ξ + d (world x, y);
/// `toe`, `heel`: the stance foot's contact points (world x, y); `yaw`: the heading;
/// `leftSwings`: the left foot takes the first step; ω in 1/s. Between
/// min(minPeriod, walkPeriod) and walkPeriod.
inline double recoveryPeriod(const Eigen::Vector2d& point, const Eigen::Vector2d& toe,
                             const Eigen::Vector2d& heel, double yaw, bool leftSwings,
                             const StepLimits& limits, double omega, double walkPeriod,
                             double minPeriod) {
  const double shortest = std::min(minPeriod, walkPeriod);
  // p: the point of the toe-heel segment nearest ξ + d.
  const Eigen::Vector2d along = toe - heel;
  const double a = along.squaredNorm() > 0.0
                       ? std::clamp((point - heel).dot(along) / along.squaredNorm(), 0.0, 1.0)
                       : 0.0;
  const Eigen::Vector2d p = heel + a * along;
  // Heading frame, from the stance foot's middle: p, and the direction ξ + d runs away in.
  const Eigen::Vector2d from = toHeading(p - 0.5 * (toe + heel), yaw);
  const Eigen::Vector2d away = toHeading(point - p, yaw);
  const double side = leftSwings ? 1.0 : -1.0;
  // Largest e^{ωt} with from + away·e^{ωt} within reach (the feet-distance side always is: the
  // foothold is moved out to it).
  double reach = std::numeric_limits<double>::infinity();
  if (away.x() > 0.0) reach = std::min(reach, (limits.maxForward - from.x()) / away.x());
  if (away.x() < 0.0) reach = std::min(reach, (-limits.maxBackward - from.x()) / away.x());
  if (side * away.y() > 0.0) reach = std::min(reach, (limits.maxWidth - side * from.y()) / (side * away.y()));
  if (reach <= 1.0) return shortest;
  return std::clamp(2.0 * std::log(reach) / omega, shortest, walkPeriod);
}

}  // namespace ballast::gait
