// Base coordinates: the model's quaternion/body-velocity convention and the paper's ZYX Euler.
//
// ZYX Euler angles are stored zyx = [yaw, pitch, roll] with R = Rz(yaw)·Ry(pitch)·Rx(roll)
// (OCS2's order, the planner's q_b = [p; zyx]). Status output uses rpy = [roll, pitch, yaw].
// Angular velocity in the world: ω = E(zyx)·d(zyx)/dt; E is singular at pitch = ±π/2.
// The model's base velocity is [Rᵀṗ; Rᵀω] (model.hpp).
#pragma once

#include <algorithm>
#include <cmath>

#include "model/model.hpp"

namespace ballast::model {

template <typename S>
Mat3<S> rotationFromZyx(const Vec3<S>& zyx) {
  using std::cos;
  using std::sin;
  const S cy = cos(zyx[0]), sy = sin(zyx[0]);
  const S cp = cos(zyx[1]), sp = sin(zyx[1]);
  const S cr = cos(zyx[2]), sr = sin(zyx[2]);
  Mat3<S> R;
  R << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return R;
}

/// [yaw, pitch, roll] of R, pitch in [-π/2, π/2].
inline Vec3<double> zyxFromRotation(const Mat3<double>& R) {
  const double sp = std::clamp(-R(2, 0), -1.0, 1.0);
  return {std::atan2(R(1, 0), R(0, 0)), std::asin(sp), std::atan2(R(2, 1), R(2, 2))};
}

/// [roll, pitch, yaw] of R, the order status and plots use.
inline Vec3<double> rpyFromRotation(const Mat3<double>& R) {
  const Vec3<double> zyx = zyxFromRotation(R);
  return {zyx[2], zyx[1], zyx[0]};
}

/// E(zyx): world angular velocity per ZYX-Euler rate, ω = E·d(zyx)/dt.
template <typename S>
Mat3<S> zyxRateToAngularVelocity(const Vec3<S>& zyx) {
  using std::cos;
  using std::sin;
  const S cy = cos(zyx[0]), sy = sin(zyx[0]);
  const S cp = cos(zyx[1]), sp = sin(zyx[1]);
  Mat3<S> E;
  E << S(0), -sy, cy * cp,  //
      S(0), cy, sy * cp,    //
      S(1), S(0), -sp;
  return E;
}

/// (∂E/∂zyx_k)·rate: how ω = E(zyx)·rate changes with the k-th angle at a fixed rate.
inline Vec3<double> zyxRateToAngularVelocityDerivative(const Vec3<double>& zyx, int k,
                                                       const Vec3<double>& rate) {
  const double cy = std::cos(zyx[0]), sy = std::sin(zyx[0]);
  const double cp = std::cos(zyx[1]), sp = std::sin(zyx[1]);
  if (k == 0) return {-cy * rate[1] - sy * cp * rate[2], -sy * rate[1] + cy * cp * rate[2], 0.0};
  if (k == 1) return {-cy * sp * rate[2], -sy * sp * rate[2], -cp * rate[2]};
  return Vec3<double>::Zero();  // E does not depend on roll
}

/// E(zyx)⁻¹·ω in closed form (cos(pitch) ≠ 0).
template <typename S>
Vec3<S> angularVelocityToZyxRate(const Vec3<S>& zyx, const Vec3<S>& omega) {
  using std::cos;
  using std::sin;
  const S cy = cos(zyx[0]), sy = sin(zyx[0]);
  const S cp = cos(zyx[1]), sp = sin(zyx[1]);
  const S rollRate = (cy * omega[0] + sy * omega[1]) / cp;
  const S pitchRate = -sy * omega[0] + cy * omega[1];
  const S yawRate = omega[2] + sp * rollRate;
  return {yawRate, pitchRate, rollRate};
}

/// Unit quaternion (x, y, z, w) of ZYX angles, scalar-generic: qz(yaw)·qy(pitch)·qx(roll).
template <typename S>
Eigen::Matrix<S, 4, 1> quaternionXyzwFromZyx(const Vec3<S>& zyx) {
  using std::cos;
  using std::sin;
  const S cy = cos(zyx[0] / S(2)), sy = sin(zyx[0] / S(2));
  const S cp = cos(zyx[1] / S(2)), sp = sin(zyx[1] / S(2));
  const S cr = cos(zyx[2] / S(2)), sr = sin(zyx[2] / S(2));
  Eigen::Matrix<S, 4, 1> q;
  q << sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
      cr * cp * cy + sr * sp * sy;
  return q;
}

/// Unit quaternion (x, y, z, w) of a rotation matrix.
inline Eigen::Vector4d quaternionXyzwFromRotation(const Mat3<double>& R) {
  const Eigen::Quaterniond qt(R);
  return {qt.x(), qt.y(), qt.z(), qt.w()};
}

/// q from the base position, ZYX angles and joint positions.
inline VecX<double> configurationFromZyx(const Model& model, const Vec3<double>& p,
                                         const Vec3<double>& zyx, const VecX<double>& qj) {
  VecX<double> q(model.nq);
  q << p, quaternionXyzwFromZyx(zyx), qj;
  return q;
}

/// Model base velocity [Rᵀṗ; Rᵀω] from world ṗ and ZYX rates.
template <typename S>
Vec6<S> baseVelocityFromZyxRates(const Vec3<S>& zyx, const Vec3<S>& pdot, const Vec3<S>& zyxRate) {
  const Mat3<S> Rt = rotationFromZyx(zyx).transpose();
  Vec6<S> vb;
  vb << Rt * pdot, Rt * (zyxRateToAngularVelocity(zyx) * zyxRate);
  return vb;
}

}  // namespace ballast::model
