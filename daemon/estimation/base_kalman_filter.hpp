// Base position and velocity and the contact-point positions: a linear Kalman filter in the
// world frame, the IMU acceleration as input and leg kinematics as measurements (the filter of
// Bloesch et al. 2013 with the orientation taken out, as in MIT Cheetah's and legged_control's
// linear estimators).
//
//   state   x = [p (3), v (3), c_1 … c_4 (3 each)]  (18), world frame
//           p, v: position and velocity of the point whose acceleration is measured (the IMU's
//           point on the base; state_estimator.hpp moves them to the base origin);
//           c_i: contact point i
//   predict p' = p + v·dt + ½·a·dt²,  v' = v + a·dt,  c_i' = c_i;   a = R·f + g (the input)
//           Q: white acceleration noise of density σ_a on [p; v]: σ_a²·[dt³/3 dt²/2; dt²/2 dt] ⊗ I₃;
//              contact point i: σ_i²·dt·I₃ (σ_i: the caller's; large for a point in swing)
//   measure (each a scalar with its own variance, or a 3-vector with a full covariance)
//           relative position  c_i − p = d_i      leg kinematics
//           velocity           v = −ḋ_i          a stance point is at rest: c_i' = v + ḋ_i = 0
//           height             c_i,z = h_i        the terrain height under a stance point
//           position           p = z, Cov = Σ     lidar or another odometry
//   anchor  c_i = p + d_i: a point in swing is not measured; it is re-placed on the leg every tick
//           (anchorContact), so touch-down starts from where the foot is, whatever it did in swing.
//
// Scalar measurements are fused one after another (sequential processing). With independent
// noises that is the batch update exactly, it needs no matrix inverse, and each scalar costs one
// column of P and one rank-1 update (≈ 18² flops): the ≤ 28 scalars of a tick are cheaper than
// forming and factoring a 28 x 28 innovation covariance. predict() uses the sparsity of F
// (rows and columns of p gain dt times those of v) instead of two dense 18 x 18 products.
// Nothing allocates.
#pragma once

#include <array>

#include <Eigen/Core>

#include "estimation/settings.hpp"

namespace ballast::estimation {

class BaseKalmanFilter {
 public:
  static constexpr int kSize = 6 + 3 * kContactPoints;
  static constexpr int kPosition = 0;  ///< index of p in x
  static constexpr int kVelocity = 3;  ///< index of v in x
  static constexpr int contactIndex(int i) { return 6 + 3 * i; }

  using Vector = Eigen::Matrix<double, kSize, 1>;
  using Covariance = Eigen::Matrix<double, kSize, kSize>;

  /// x and a diagonal P.
  void reset(const Vector& state, const Vector& variance);
  /// x and a full P (symmetric positive definite).
  void reset(const Vector& state, const Covariance& covariance);

  /// One step of dt under the acceleration a (world, gravity removed). accelerationDensity:
  /// σ_a (m/s²/√Hz); contactDensity[i]: σ_i (m/√s) of contact point i's random walk.
  void predict(const Eigen::Vector3d& acceleration, double dt, double accelerationDensity,
               const std::array<double, kContactPoints>& contactDensity);

  /// The scalar measurement z = x[j] − x[i] (i < 0: z = x[j]) with variance r > 0. Returns the
  /// innovation z − (x[j] − x[i]) before the update.
  double updateScalar(int i, int j, double z, double r);
  /// c_i − p = d (world axes), each axis with variance r.
  void updateRelativePosition(int contact, const Eigen::Vector3d& d, double r);
  /// v = z, each axis with variance r.
  void updateVelocity(const Eigen::Vector3d& z, double r);
  /// c_i,z = h with variance r.
  void updateContactHeight(int contact, double h, double r);
  /// p = z with covariance Σ (symmetric positive definite). Returns false (and changes nothing)
  /// when P_pp + Σ is not positive definite.
  bool updatePosition(const Eigen::Vector3d& z, const Eigen::Matrix3d& covariance);

  /// Replaces contact point i by c_i = p + d + n, n ~ N(0, r·I): its old estimate is dropped and
  /// the new one is correlated with everything exactly as p is (P_c· = P_p·, P_cc = P_pp + r·I).
  /// For a point in swing, which the ground does not hold: it follows the leg, and p is unchanged.
  void anchorContact(int contact, const Eigen::Vector3d& d, double r);

  const Vector& state() const { return x_; }
  const Covariance& covariance() const { return P_; }
  Eigen::Vector3d position() const { return x_.segment<3>(kPosition); }
  Eigen::Vector3d velocity() const { return x_.segment<3>(kVelocity); }
  Eigen::Vector3d contactPosition(int i) const { return x_.segment<3>(contactIndex(i)); }

 private:
  Vector x_ = Vector::Zero();
  Covariance P_ = Covariance::Identity();
  Vector Ph_;  // scratch: P·h
};

}  // namespace ballast::estimation
