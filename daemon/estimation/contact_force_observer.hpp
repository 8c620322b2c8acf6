// Contact forces from the measured joint torques: a generalised-momentum observer on the joint
// rows of the dynamics, then a least-squares split over the contact points of each foot.
//
// The actuated rows of  M v̇ + n = Sᵀτ + Σ_i J_iᵀ F_i  give, for joint j,
//     e_j := (Σ_i J_iᵀ F_i)_j = (M v̇)_j + n_j − τ_j
// (F_i: force on the robot at contact point i, world frame). e needs v̇, which differencing
// noisy joint velocities does not give. The observer
//     r_k = (1 − K·dt)·r_{k−1} + K·dt·(n − τ)_k + K·M_k·(v_k − v_{k−1})
// is e through a first-order low-pass of time constant 1/K without ever forming v̇: the
// discrete generalised-momentum observer of De Luca et al. (M_k·Δv = Δ(M v) − ΔM·v_k, the same
// to first order in dt). Why not the static least squares J_cᵀF = n − τ: with heavy limbs the
// leg's own inertia term M v̇ is large — a 10 kg swing leg accelerating its foot at 20 m/s²
// reads as a ~100 N contact force without it, three times the stance threshold.
// The low-pass is on the forces, not on r: each tick's increment of r (α·(n − τ)_k + K·M_k·Δv)
// goes through that tick's least squares (below) and the forces decay by (1 − K·dt), so F̂ is F
// low-passed in world axes. The low-passed r through the Jacobian of the moment would solve a
// lagged J(t − 1/K)ᵀF with J(t): a stance leg turning at v/L about its foot turns the weight by
// (v/L)/K, a forward force of m·g·(v/L)/K on the stance foot (23-25 N walking at 1.5 m/s,
// 62 kg, K 50/s), which the external force observer reads as a push against the walk.
// A joint past its position limit rests on its stop, whose torque the motor does not measure:
// its row would read that torque as a contact force (an ankle 0.17 rad into its stop at the
// simulation's 1000 N·m/rad: 170 N·m, several hundred N on a swing foot, which the external
// force observer then reports as a push). Its row is left out of its foot's least squares while
// it is past the limit; the foot's other joints still carry the force.
// Cost: the rows of M and n on the legs' joints (the caller runs crba and nonLinearEffects)
// and one small regularised least squares per foot.
//
// Per foot (the contact points on one body): the joints on the chain from that body to the base
// carry its forces only, r_chain = A·F_foot with A = J_chainᵀ. F_foot = argmin ‖A F − r_chain‖² +
// λ‖F‖² (λ: estimator.contact_force_regularization). With toe and heel on one foot the force
// along the toe–heel line is internal (A's null space, which λ keeps out of the answer); the
// normal forces, what the contact decision needs, are observable. Along an eigenvector of AᵀA of
// eigenvalue μ the least squares keeps μ/(μ + λ) of the force and turns a torque error of ε N·m
// into up to ε/(2√λ) N. The smallest μ (but the internal one) is 0.018 m² with the knee bent
// 0.8 rad and 1e-4 m² at 0.05 rad, along the leg: a stretched leg cannot sense its load, and with
// the knee on its stop (its row left out) the force along the line from hip to ankle reaches no
// joint at all. At λ = 1e-6 such a leg read a few N·m of error as kN (traced at 1.0 m/s: the feet's
// vertical forces summed to −1900 N as a stance knee reached its stop, and a push of (−150, +210) N
// was read under a true (0, 60)). λ = 3e-4 bounds 3 N·m to 90 N. Larger, it leaves out more of a
// bent leg's load (3 % at 1e-3), and the standing robot's recovery steps under a 60 N sideways
// push on profiles/sim-flat-push.yaml fell in one direction at 1e-3 and in both at 3e-3. What λ
// leaves out is measured:
// W = (λ/p)·S (AᵀA + λI)⁻¹ Sᵀ (3 × 3, world; S sums the foot's p points' forces) is the part of an
// evenly split foot force F that the answer misses, F̂ = (I − W)·F; its eigenvalues are the
// fractions missed by direction (0.01 along the leg with the knee bent 0.8 rad, 0.8 with the knee
// on its stop).
// The external force observer takes that part of the load from the vertical momentum balance
// (external_force_observer.hpp).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "estimation/settings.hpp"
#include "model/data.hpp"

namespace ballast::estimation {

class ContactForceObserver {
 public:
  /// Longest joint chain from a contact body to the base, and most contact points on one body.
  static constexpr int kMaxChain = 12;
  static constexpr int kMaxPointsPerFoot = kContactPoints;

  /// contactFrames: model frame indices. Throws model::ModelError when a contact body's chain
  /// is longer than kMaxChain or a contact point is on the base.
  ContactForceObserver(const model::Model& model, const std::array<int, kContactPoints>& contactFrames);

  /// The next update() starts the observer from rest (v̇ = 0).
  void reset() { started_ = false; }

  /// One step. `data` holds crba(q) (M) and nonLinearEffects(q, v) (nle) for the same q and v,
  /// with the base at any position and its true orientation (forces come out in world axes).
  /// v: generalised velocity (nv); jointPositions, tau: measured joint positions and torques
  /// (nj, model order); bandwidth: K; regularization: λ (m², header).
  void update(const model::Data<double>& data, const Eigen::VectorXd& v,
              const Eigen::VectorXd& jointPositions, const Eigen::VectorXd& tau, double dt,
              double bandwidth, double regularization);

  /// Estimated force on the robot at contact point i, world frame, N.
  const Eigen::Vector3d& force(int i) const { return force_[i]; }
  /// Estimated total force on the body that carries contact point i (all its contact points),
  /// world frame, N. Whether a foot is down is this, not force(i): how the load splits between
  /// toe and heel is where the centre of pressure is (a robot standing with its weight on its
  /// heels has a toe on the ground carrying little).
  const Eigen::Vector3d& footForce(int i) const { return footForce_[i]; }
  /// W of the body that carries contact point i (header): the fraction of a force on it, by
  /// direction, that this tick's least squares could not sense (world, symmetric, eigenvalues in
  /// [0, 1]).
  const Eigen::Matrix3d& unsensedLoad(int i) const { return unsensed_[i]; }
  /// The sum of W over the feet with a point in `stance` (each foot once).
  Eigen::Matrix3d unsensedLoad(const std::array<bool, kContactPoints>& stance) const;

 private:
  struct Foot {
    std::vector<int> chain;   // velocity indices of the joints from the base to the body
    std::vector<int> points;  // contact point indices on the body
  };
  static constexpr int kMaxForces = 3 * kMaxPointsPerFoot;
  // Stack storage with dynamic sizes up to these bounds: the per-foot solve allocates nothing.
  using ChainMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxChain, kMaxForces>;
  using ChainVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxChain, 1>;
  using ForceMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxForces, kMaxForces>;
  using ForceVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxForces, 1>;

  const model::Model& model_;
  std::array<int, kContactPoints> frames_;
  std::vector<Foot> feet_;
  std::vector<int> rows_;  // union of the chains
  Eigen::VectorXd increment_;  // this tick's increment of r on the feet's chains (header), nv
  Eigen::VectorXd vPrevious_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> J_;  // one contact point's Jacobian
  std::array<Eigen::Matrix<double, 3, Eigen::Dynamic>, kContactPoints> Jc_;
  std::array<Eigen::Vector3d, kContactPoints> force_, footForce_;
  std::array<Eigen::Matrix3d, kContactPoints> unsensed_;
  bool started_ = false;
};

}  // namespace ballast::estimation
