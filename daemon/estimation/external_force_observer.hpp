// The external force on the robot (a push, a load, a tether) from the rate of its linear
// momentum and the estimated contact forces: Newton for the whole robot,
//     ṗ = Σ_i F_i + m g + f_ext,        p = m ċ  (linear momentum, world frame),
// as a momentum observer, so that ṗ is never formed by differencing:
//     r_k = (1 − K·dt)·r_{k−1} + K·(p_k − p_{k−1}) − K·dt·(Σ_i F_i + m g)_k
// is f_ext through a first-order low-pass of time constant 1/K. The contact forces come from the
// contact force observer (contact_force_observer.hpp), itself a first-order low-pass of a faster
// bandwidth K_c. The momentum goes through the same low-pass first (p_f, K_c) so that both sides
// of Newton's law are delayed alike: ṗ_f − F̂ − m g is then the external force low-passed by K_c
// alone. With the raw momentum the difference F − F̂ (the contact forces' high-pass) came
// through, and at every touch-down, where the load changes hands within a few ms, it read as a
// push of about K/K_c of the load step: 100-170 N for 1/5 of 600 N, spikes that made the step
// adjustment throw the feet 0.2 m and the MPC lean into a push that was not there. p is the first three rows of M(q)·v turned into the world (with the free-flyer's base
// velocity in the base frame, (M v)[0:3] is the robot's linear momentum in base axes).
// A stance leg that is straight, or has a joint on its stop, cannot sense the load along it
// (contact_force_observer.hpp): F̂ misses W·F of the foot's force F, W the fraction missed by
// direction, and without more that part reads as a push (traced at 1.0 m/s: (−150, +210) N under
// a true (0, 60) N while a stance knee sat on its stop). Pushes are taken as horizontal, so the
// vertical balance says how much is missing: with δ = ṗ_f − F̂ − m g at this tick (the contact
// forces' bandwidth), the missing force is y = W e_z · δ_z / (W_zz + ε): the one along W's
// response to a vertical load that closes the vertical balance. W is the stance feet's sum, so
// this takes each foot's load as vertical and the feet's loads as alike; during a weight transfer
// between a bent and a straight leg the horizontal part is shared out approximately. The
// correction runs through all of stance, not only on straight legs (a leg bent 0.8 rad has
// W_zz ≈ 0.01 at the profile's λ), and carries the model's vertical errors (a mass off) into the
// horizontal estimate through W's tilt; ε = 0.005 takes W_zz/(W_zz + ε) of δ_z there (0.67 for
// one such leg) and nearly all of it on a straight one (0.99). Under W_zz = 1e-3 (λ near the old
// 1e-6) nothing is added. W is low-passed like F̂ (K_c), as the part F̂ misses fades in and out at
// that rate. A vertical push on such a leg is taken for its load.
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
  /// (world, N, pointing down); bandwidth: K (1/s); contactBandwidth: K_c of the contact forces'
  /// low-pass (1/s; 0: the momentum unfiltered); unsensedLoad: W of the feet that stand (header;
  /// world; low-passed here like the momentum; zero: no correction).
  void update(const Eigen::Vector3d& momentum, const Eigen::Vector3d& contactForceSum,
              const Eigen::Vector3d& weight, double dt, double bandwidth,
              double contactBandwidth = 0.0,
              const Eigen::Matrix3d& unsensedLoad = Eigen::Matrix3d::Zero());

  /// f_ext low-passed (world, N), before the deadband.
  const Eigen::Vector3d& raw() const { return force_; }
  /// The horizontal part of f_ext beyond `deadband` N (z = 0).
  Eigen::Vector3d horizontal(double deadband) const;

 private:
  bool started_ = false;
  Eigen::Vector3d momentum_ = Eigen::Vector3d::Zero();  ///< p_f at the last update
  Eigen::Vector3d force_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d unsensed_ = Eigen::Matrix3d::Zero();  ///< W low-passed (header)
};

}  // namespace ballast::estimation
