// Cubic swing trajectory of one contact point between lift-off and touch-down.
//
// Horizontal: a cubic from the lift-off to the touch-down position with zero velocity at both
// ends. Vertical: two cubics, lift-off height -> apex at mid-swing -> touch-down height, each
// with zero vertical velocity at its ends, so the point leaves and lands vertically at rest.
// Over a step (a stage edge, a stair), the horizontal cubic can be held back for a fraction of
// the swing at each end (`lift`): the foot rises before it moves towards the edge and moves
// before it comes down, instead of catching the edge with its toe.
// All positions are world coordinates; velocity and acceleration are d/dt and d²/dt².
#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace ballast::gait {

struct PointReference {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
};

/// s(τ) = 3τ² − 2τ³ and its first two derivatives in τ.
struct SmoothStep {
  double s, ds, dds;
  explicit SmoothStep(double tau)
      : s(tau * tau * (3.0 - 2.0 * tau)), ds(6.0 * tau * (1.0 - tau)), dds(6.0 - 12.0 * tau) {}
};

struct SwingTrajectory {
  double liftOff = 0.0;
  double touchDown = 1.0;
  Eigen::Vector3d liftOffPosition = Eigen::Vector3d::Zero();
  Eigen::Vector3d touchDownPosition = Eigen::Vector3d::Zero();
  double apexHeight = 0.1;  ///< world z at mid-swing
  double lift = 0.0;        ///< fraction of the swing at each end without horizontal motion

  /// Reference at time t (clamped to [liftOff, touchDown]).
  PointReference at(double t) const {
    const double duration = touchDown - liftOff;
    const double tau = std::clamp((t - liftOff) / duration, 0.0, 1.0);
    PointReference r;
    // Horizontal time runs over [lift, 1 − lift] of the swing.
    const double span = 1.0 - 2.0 * lift;
    const SmoothStep h(std::clamp((tau - lift) / span, 0.0, 1.0));
    const double moving = duration * span;
    const Eigen::Vector3d delta = touchDownPosition - liftOffPosition;
    r.position = liftOffPosition + delta * h.s;
    r.velocity = delta * (h.ds / moving);
    r.acceleration = delta * (h.dds / (moving * moving));
    // Vertical: two halves through the apex; time runs twice as fast in each half.
    const bool rising = tau < 0.5;
    const double z0 = rising ? liftOffPosition.z() : apexHeight;
    const double z1 = rising ? apexHeight : touchDownPosition.z();
    const SmoothStep v(rising ? 2.0 * tau : 2.0 * tau - 1.0);
    const double half = 0.5 * duration;
    r.position.z() = z0 + (z1 - z0) * v.s;
    r.velocity.z() = (z1 - z0) * v.ds / half;
    r.acceleration.z() = (z1 - z0) * v.dds / (half * half);
    return r;
  }
};

}  // namespace ballast::gait
