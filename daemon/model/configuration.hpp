// Configuration-space operations: neutral pose, integration of a velocity, random samples.
// q and v follow model.hpp. Double only: these run in estimation, simulation and tests, not
// under automatic differentiation.
#pragma once

#include <cmath>
#include <random>

#include "model/base_conventions.hpp"

namespace ballast::model {

/// Base at the origin, identity orientation, joints at 0 (or mid-range where 0 is outside).
inline VecX<double> neutralConfiguration(const Model& model) {
  VecX<double> q = VecX<double>::Zero(model.nq);
  q[6] = 1.0;
  for (int j = 0; j < model.nj(); ++j) {
    const double lo = model.lowerPositionLimit[j], hi = model.upperPositionLimit[j];
    if (lo > 0.0 || hi < 0.0) q[Model::qIndexOfJoint(j)] = 0.5 * (lo + hi);
  }
  return q;
}

/// q ⊕ v·dt: the base moves along the screw of its constant body twist (exact SE(3) exponential),
/// the joints by Euler steps. Writes into qOut (may alias q).
inline void integrate(const Model& model, const VecX<double>& q, const VecX<double>& v, double dt,
                      VecX<double>& qOut) {
  const Vec3<double> w = v.segment<3>(3) * dt;
  const Vec3<double> u = v.head<3>() * dt;
  const double theta = w.norm();
  Mat3<double> dR, V;
  const Mat3<double> W = skew<double>(w);
  if (theta < 1e-9) {
    dR = Mat3<double>::Identity() + W;
    V = Mat3<double>::Identity() + 0.5 * W;
  } else {
    const double t2 = theta * theta;
    dR = Mat3<double>::Identity() + std::sin(theta) / theta * W + (1 - std::cos(theta)) / t2 * W * W;
    V = Mat3<double>::Identity() + (1 - std::cos(theta)) / t2 * W +
        (theta - std::sin(theta)) / (t2 * theta) * W * W;
  }
  const Mat3<double> R = quaternionToRotation<double>(q.segment<4>(3));
  const Vec3<double> p = q.head<3>() + R * (V * u);
  Eigen::Quaterniond qt(R * dR);
  qt.normalize();
  qOut.head<3>() = p;
  qOut.segment<4>(3) << qt.x(), qt.y(), qt.z(), qt.w();
  qOut.tail(model.nj()) = q.tail(model.nj()) + v.tail(model.nj()) * dt;
}

/// A configuration with joints uniform within their limits (±π for unlimited joints), a random
/// base orientation and a base position in the unit box.
template <typename Rng>
VecX<double> randomConfiguration(const Model& model, Rng& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  VecX<double> q(model.nq);
  q.head<3>() << unit(rng), unit(rng), unit(rng);
  Eigen::Vector4d quat(unit(rng), unit(rng), unit(rng), unit(rng));
  q.segment<4>(3) = quat.normalized();
  for (int j = 0; j < model.nj(); ++j) {
    double lo = model.lowerPositionLimit[j], hi = model.upperPositionLimit[j];
    if (!std::isfinite(lo) || !std::isfinite(hi)) lo = -M_PI, hi = M_PI;
    q[Model::qIndexOfJoint(j)] = lo + (hi - lo) * 0.5 * (unit(rng) + 1.0);
  }
  return q;
}

}  // namespace ballast::model
