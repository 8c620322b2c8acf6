// The external force on the robot (a push, a load, a tether) from the rate of its linear
// momentum and the estimated contact forces: Newton for the whole robot,
//     ṗ = Σ_i F_i + m g + f_ext,        p = m ċ  (linear momentum, world frame),
// as a momentum observer, so that ṗ is never formed by differencing:
//     r_k = (1 − K·dt)·r_{k−1} + K·(p_k − p_{k−1}) − K·dt·(Σ_i F_i + m g)_k
// is f_ext through a first-order low-pass of time constant 1/K. The contact forces come from the
// contact force observer (contact_force_observer.hpp), itself a low-pass of a faster bandwidth:
// what it misses of a load changing hands within a step has no mean and K (slower) smooths it
// out. p is the first three rows of M(q)·v turned into the world (with the free-flyer's base
// velocity in the base frame, (M v)[0:3] is the robot's linear momentum in base axes).
// What the estimate carries besides a push: the model's errors (a mass or a centre of mass off,
// an actuator's inertia the model lacks) and the contact forces' own errors. A force under
// `deadband` (N, horizontal magnitude) reads as none, and the reported force is the excess over
// it, so model errors do not lean the robot.
// Allocates nothing.
#pragma once

#include <Eigen/Core>

namespace ballast::estimation {

class ExternalForceObserver {
 public:
  /// The next update() starts from rest (f = 0, momentum taken as it is).
  void reset() { started_ = false; }

  /// momentum: m ċ (world, N·s); contactForceSum: Σ F_i on the robot (world, N); weight: m g
  /// (world, N, pointing down); bandwidth: K (1/s).
  void update(const Eigen::Vector3d& momentum, const Eigen::Vector3d& contactForceSum,
              const Eigen::Vector3d& weight, double dt, double bandwidth);

  /// f_ext low-passed (world, N), before the deadband.
  const Eigen::Vector3d& raw() const { return force_; }
  /// The horizontal part of f_ext beyond `deadband` N (z = 0).
  Eigen::Vector3d horizontal(double deadband) const;

 private:
  bool started_ = false;
  Eigen::Vector3d momentum_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_ = Eigen::Vector3d::Zero();
};

}  // namespace ballast::estimation
