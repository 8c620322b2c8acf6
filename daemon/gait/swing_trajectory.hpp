// Cubic swing trajectory of one contact point between lift-off and touch-down.
//
// Horizontal: a cubic from the lift-off to the touch-down position with zero velocity at both
// ends. Vertical: two cubics, lift-off height -> apex at mid-swing -> touch-down height, each
// with zero vertical velocity at its ends, so the point leaves and lands vertically at rest.
// Over a step (a stage edge, a stair), the horizontal cubic can be held back for a fraction of
// the swing at each end (`lift`): the foot rises before it moves towards the edge and moves
// before it comes down, instead of catching the edge with its toe.
// A swing whose touch-down point moves while the foot is on its way (step adjustment) moves on
// from where its reference is then: from `moveFrom` the horizontal path is the cubic from the
// reference's position and velocity at that time to the new touch-down point, at rest there
// (a cubic Hermite), so the reference stays continuous in position and velocity. With the
// touch-down point unchanged it is the same cubic as before.
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
  /// Retargeted: the horizontal path restarts at this time (< 0: from lift-off) from
  /// movePosition with moveVelocity (x, y; z unused).
  double moveFrom = -1.0;
  Eigen::Vector3d movePosition = Eigen::Vector3d::Zero();
  Eigen::Vector3d moveVelocity = Eigen::Vector3d::Zero();
  /// The foot's reference point (middle of its contact points) at touch-down, world x, y: what
  /// step adjustment chose for the whole foot, or where the paper's foothold puts it.
  Eigen::Vector2d foothold = Eigen::Vector2d::Zero();

  /// Start and end of the horizontal motion, s.
  double moveStart() const { return liftOff + lift * (touchDown - liftOff); }
  double moveEnd() const { return touchDown - lift * (touchDown - liftOff); }

  /// Reference at time t (clamped to [liftOff, touchDown]).
  PointReference at(double t) const {
    const double duration = touchDown - liftOff;
    const double tau = std::clamp((t - liftOff) / duration, 0.0, 1.0);
    PointReference r;
    if (moveFrom >= 0.0 && moveFrom < moveEnd()) {
      // Cubic Hermite from (movePosition, moveVelocity) at moveFrom to (touch-down, 0).
      const double T = moveEnd() - moveFrom;
      const double s = std::clamp((t - moveFrom) / T, 0.0, 1.0);
      const double s2 = s * s, s3 = s2 * s;
      const Eigen::Vector3d p0 = movePosition, v0 = moveVelocity * T, p1 = touchDownPosition;
      const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2;
      const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s;
      const double a00 = 12 * s - 6, a10 = 6 * s - 4, a01 = -12 * s + 6;
      const bool moving = t > moveFrom && t < moveEnd();
      r.position = h00 * p0 + h10 * v0 + h01 * p1;
      r.velocity = moving ? Eigen::Vector3d((d00 * p0 + d10 * v0 + d01 * p1) / T)
                          : Eigen::Vector3d(t <= moveFrom ? moveVelocity : Eigen::Vector3d::Zero());
      r.acceleration = moving ? Eigen::Vector3d((a00 * p0 + a10 * v0 + a01 * p1) / (T * T))
                              : Eigen::Vector3d::Zero();
    } else {
      // Horizontal time runs over [lift, 1 − lift] of the swing.
      const double span = 1.0 - 2.0 * lift;
      const SmoothStep h(std::clamp((tau - lift) / span, 0.0, 1.0));
      const double moving = duration * span;
      const Eigen::Vector3d delta = touchDownPosition - liftOffPosition;
      r.position = liftOffPosition + delta * h.s;
      r.velocity = delta * (h.ds / moving);
      r.acceleration = delta * (h.dds / (moving * moving));
    }
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
