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
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

#include "gait/capture_point.hpp"
#include "gait/contact.hpp"

namespace ballast::gait {

/// Filled by the profile (gait.recovery_*: defaults and bounds in daemon/profile/schema.cpp).
struct RecoveryParameters {
  bool enabled = true;
  double margin = 0.02;      ///< m beyond the support polygon that starts steps (and inside it, ends them)
  double settleSpeed = 0.1;  ///< m/s: the centre of mass slower than this ends the steps
};

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
  return -std::sin(yaw) * d.x() + std::cos(yaw) * d.y() >= 0.0;
}

}  // namespace ballast::gait
