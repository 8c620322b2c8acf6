// Footholds by the paper's eq. (desired_swing_traj): Raibert heuristic, capture-point velocity
// feedback and a centrifugal term,
//     p_d = p_hip + Δt/2·v_des + k (v − v_des) + (h/|g|)·v × ω_des,      k = 0.15,
// with Δt the stance duration, v and v_des the measured and desired base velocity (world), h the
// nominal base height and ω_des the desired base angular velocity. p_hip is where the contact
// point sits under its hip in the nominal stance, at the touch-down time: the base pose is
// predicted there by integrating the commanded velocity. The height comes from the terrain.
// The centrifugal term is the inverted pendulum's: a steady turn accelerates the centre of mass
// inwards by v·ω, which the pendulum gets from its centre of pressure (h/|g|)·v·ω outside it.
// The paper writes sqrt(h/|g|) there, which gives m/s, not m; at h = 0.85 m its offset is
// sqrt(|g|/h) = 3.4 times the pendulum's. Walking at 0.8 m/s and turning at 0.4 rad/s, its feet
// landed 9 cm outwards, the inner one under the pelvis, and the robot fell within 7 s.
// Straight walking (ω_des = 0) is the paper's.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "gait/terrain_query.hpp"

namespace ballast::gait {

/// The commanded base motion, in the heading frame (yaw-rotated world frame).
struct VelocityCommand {
  double vx = 0.0;       ///< forward, m/s
  double vy = 0.0;       ///< left, m/s
  double yawRate = 0.0;  ///< rad/s
};

/// Base position and yaw after `dt` s of constant command from (position, yaw) (exact for a
/// constant body velocity and yaw rate: an arc).
struct PlanarPose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0.0;

  PlanarPose predicted(const VelocityCommand& cmd, double dt) const {
    const double w = cmd.yawRate;
    double fx, fy;  // displacement in the heading frame at the start
    if (std::abs(w * dt) < 1e-9) {
      fx = cmd.vx * dt;
      fy = cmd.vy * dt;
    } else {
      const double s = std::sin(w * dt), c = std::cos(w * dt);
      fx = (cmd.vx * s - cmd.vy * (1.0 - c)) / w;
      fy = (cmd.vx * (1.0 - c) + cmd.vy * s) / w;
    }
    const double cy = std::cos(yaw), sy = std::sin(yaw);
    PlanarPose out;
    out.position = position + Eigen::Vector3d(cy * fx - sy * fy, sy * fx + cy * fy, 0.0);
    out.yaw = yaw + w * dt;
    return out;
  }
};

struct FootholdParameters {
  double feedbackGain;          ///< k (the profile's gait.foothold_gain)
  /// h: the pendulum's height, the centre of mass above the soles in the nominal posture, m
  /// (set by the locomotion planner; the capture point's ω = sqrt(g/h) uses it too)
  double comHeight = 0.8;
  double gravity = 9.81;        ///< |g|
};

/// Eq. (desired_swing_traj) for one contact point. `baseAtTouchDown` is the predicted base pose
/// at touch-down, `nominalOffset` the contact point's position under its hip in the heading
/// frame (x forward, y left, z ignored), `v` the measured base velocity (world).
inline Eigen::Vector3d raibertFoothold(const PlanarPose& baseAtTouchDown,
                                       const Eigen::Vector3d& nominalOffset,
                                       const Eigen::Vector3d& v, const Eigen::Vector3d& vDesired,
                                       double yawRateDesired, double stanceDuration,
                                       const FootholdParameters& params,
                                       const TerrainQuery& terrain) {
  const double cy = std::cos(baseAtTouchDown.yaw), sy = std::sin(baseAtTouchDown.yaw);
  const Eigen::Vector3d hip =
      baseAtTouchDown.position +
      Eigen::Vector3d(cy * nominalOffset.x() - sy * nominalOffset.y(),
                      sy * nominalOffset.x() + cy * nominalOffset.y(), 0.0);
  const Eigen::Vector3d capture = 0.5 * stanceDuration * vDesired + params.feedbackGain * (v - vDesired);
  const Eigen::Vector3d centrifugal =
      (params.comHeight / params.gravity) * v.cross(Eigen::Vector3d(0.0, 0.0, yawRateDesired));
  Eigen::Vector3d p = hip + capture + centrifugal;
  p.z() = terrain.height(p.x(), p.y());
  return p;
}

}  // namespace ballast::gait
