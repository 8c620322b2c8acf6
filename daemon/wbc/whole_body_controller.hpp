// The whole-body controller of the paper (Sec. II-B, Table I): from the robot state and the
// planner's references to joint torques, at 1 kHz.
//
// Decision ξ = [v̇ (nv); F_c (3·nc)], v̇ in the model's velocity coordinates (base part in the base
// frame), F_c the forces on the robot at the contact points, world frame.
//
// Task stack (TaskStack levels; the paper's priority in brackets):
//   0 [1]  physics, equalities: floating-base rows of the dynamics [M_b  −J_bᵀ]ξ = −n_b; stance
//          contact points J_c v̇ = −J̇_c v; swing contact points f_c = 0; a body standing on two
//          contact points (a foot on toe and heel) does not roll about the line through them,
//          dᵀ(J_ω v̇ + J̇_ω v) = 0 — the four-point model leaves that roll free, the real foot has width
//   1 [1]  limits, inequalities: torque limits through the actuated rows
//          −τ_max − n_j ≤ [M_j  −J_jᵀ]ξ ≤ τ_max − n_j; friction pyramid C_fr f_c ≤ 0 on stance points;
//          with WbcSettings::jointLimits, joint position limits as acceleration bounds
//          k_p(q_min − q) − k_d q̇ ≤ q̈ ≤ k_p(q_max − q) − k_d q̇ (the joint-space gains): a swing
//          foot's target the leg cannot reach (a sideways push's step, the pelvis rolled) is
//          then missed at the limit, where the paper's stack drove the hip into its stop and the
//          stop's impulse threw the robot
//   2 [2]  limb motion: swing contact points J_c v̇ = p̈* + kp(p* − p) + kd(ṗ* − ṗ) − J̇_c v (world);
//          joint-space joints (arms) q̈_j = q̈*_j + kp(q*_j − q_j) + kd(q̇*_j − q̇_j)
//   3 [3]  base motion: J_b v̇ = a*_b + Kp (q*_b ⊟ q_b) + Kd (v*_b − v_b) − J̇_b v, world-aligned
//          [linear; angular], the orientation error as the rotation vector log(R* Rᵀ)
//   4 [4]  contact forces: F_c = F_c*
// On a robot whose feet cannot yaw relative to the base (WbcSettings::feetFollowBaseYaw: no hip
// yaw, or both locked) every foot's yaw is the base's, and the legs reach it only through the
// pitch axes the hip roll tilts (the sine of a few hundredths). Rows that ask for it are nearly
// dependent on the rows above them, above the hierarchical QP's thresholds, and were met with
// accelerations of their disagreement over that sine: the weight shift before the first step
// already stood the legs up and pitched the base (level 0 rank 18 where the robot has 17).
// So there: at level 0 with all points standing, the second foot's second point keeps only its
// row along the sole's normal (the first foot holds the yaw); at level 2 a swinging foot's two
// points become its middle (3 rows) and its pitch (toe height − heel height, 1 row); level 3
// has no yaw row.
// While the plan steps out a push (WbcReference::pushStep: the capture point's footholds, a
// walking push or a standing recovery), levels 2 and 3 change places (WbcSettings::pushBaseFirst,
// hierarchical variant). A push's steps are long and quick (a 1.1 m swing in 0.32 s at 1 m/s,
// its foot asked 95 m/s² at lift-off where walking asks 50): the swing hip reaches its torque
// limit, and with the limbs above the base the rest of the swing foot's acceleration came from
// the base — the stance leg, its knee at its own limit, put 2100 N under a plan of 960 N, the
// pelvis went up at 27 m/s² and the robot left the ground at the next touch-down (issue 13's
// "jump at a touch-down"). With the base above, the swing foot falls short of its path instead
// and lands later. Undisturbed walking keeps the paper's order.
// Priority 1 is split in two levels so the physics equalities are never traded for slack when
// the limits cannot be met (with feasible limits the answer is the same as one level).
// The weighted variant (cNH) keeps levels 0 and 1 and solves levels 2–4 as one least-squares
// level weighted by WbcSettings::limbWeight, baseWeight, contactForceWeight.
//
// Torques τ = M_j v̇ + n_j − J_jᵀF_c (actuated rows of the dynamics), clamped to the limits. Joint
// targets for the motors' PD: the mean of the predicted motion over the coming period T,
// q_j + (T/2) q̇_j + (T²/6) v̇_j and q̇_j + (T/2) v̇_j. The motor's PD runs continuously while the
// command is held; around the mean of the prediction it adds no bias when the prediction comes
// true (end-of-period targets push along the motion by kp·q̇·T/2 on average: in the balance test
// that doubled the arm tracking error), and it corrects what the prediction misses.
//
// The contact force columns are scaled by m·g/nc inside the solver (HierarchicalQp's variable
// scale) so that accelerations and forces have comparable magnitudes.
#pragma once

#include <utility>
#include <vector>

#include "model/data.hpp"
#include "model/model.hpp"
#include "wbc/hierarchical_qp.hpp"
#include "wbc/interface.hpp"
#include "wbc/settings.hpp"
#include "wbc/task_stack.hpp"

namespace ballast::wbc {

/// TaskStack level of each part of the task stack (see the header comment).
enum WbcStackLevel : int {
  kLevelPhysics = 0,
  kLevelLimits = 1,
  kLevelLimbs = 2,
  kLevelBase = 3,
  kLevelContactForces = 4,
  kStackLevels = 5,
};

class WholeBodyController {
 public:
  /// Throws std::invalid_argument with validateSettings()'s message. Keeps a reference to model.
  WholeBodyController(const model::Model& model, const WbcSettings& settings);

  WbcState makeState() const;          ///< neutral configuration, zero velocity
  WbcReference makeReference() const;  ///< all contact points in stance, everything else zero
  WbcOutput makeOutput() const;

  /// One control tick; allocates nothing. Returns output.status.
  WbcStatus update(const WbcState& state, const WbcReference& reference, WbcOutput& output);

  /// A profile switch: new gains, weights, limits, variant, base frame and joint-space joints,
  /// allocating nothing. The settings must have passed validateSettings() for this model; false
  /// (nothing changed) when their contact frames differ (those need a new controller).
  bool setSettings(const WbcSettings& settings);

  /// The numbers and contact frames in force (base frame, joint-space joints and torque limits
  /// are resolved: baseFrame(), torqueLimit()).
  const WbcSettings& settings() const { return settings_; }
  int baseFrame() const { return baseFrame_; }
  /// Model frame of each contact point, in the settings' order.
  const std::vector<int>& contactFrames() const { return contactFrames_; }
  int contactCount() const { return nc_; }
  int decisionSize() const { return nx_; }
  /// The last tick's hierarchical task stack (levels as WbcStackLevel, unweighted, in ξ units;
  /// levels 2 and 3 swapped while a push is stepped out: limbsLevel(), baseLevel()), the same
  /// for both variants, and the decision ξ found.
  const TaskStack& tasks() const { return tasks_; }
  const Eigen::VectorXd& decision() const { return xi_; }
  int limbsLevel() const { return limbsLevel_; }
  int baseLevel() const { return baseLevel_; }
  const HierarchicalQp& solver() const { return hqp_; }
  const model::Data<double>& data() const { return data_; }
  /// The contact points' positions (world, 3 × contactCount()) at the last update's state.
  const Eigen::Matrix3Xd& contactPositions() const { return contactPosition_; }
  /// |τ| limits in use (nj).
  const Eigen::VectorXd& torqueLimit() const { return torqueLimit_; }

 private:
  void resolve(const WbcSettings& settings);
  bool inputValid(const WbcState& state, const WbcReference& reference) const;
  void computeKinematics(const WbcState& state);
  void buildTasks(const WbcState& state, const WbcReference& reference);
  void buildWeightedStack();
  void fail(const WbcState& state, WbcOutput& output) const;

  const model::Model& model_;
  WbcSettings settings_;  // numbers only (numbersOf)
  int nv_, nj_, nc_, nx_;
  int baseFrame_;
  std::vector<int> contactFrames_;
  std::vector<std::pair<int, int>> footPairs_;  // contact points on one body (a foot's toe, heel)
  std::vector<int> jointSpaceJoints_;
  Eigen::VectorXd torqueLimit_;

  model::Data<double> data_;
  Eigen::VectorXd q_;            // state.q with a normalised quaternion
  Eigen::MatrixXd Jc_;           // 3·nc × nv contact Jacobians, world-aligned
  Eigen::VectorXd contactBias_;  // 3·nc, J̇_c v
  Eigen::Matrix3Xd contactPosition_, contactVelocity_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> Jb_;  // base frame Jacobian, world-aligned
  Eigen::Matrix<double, 6, Eigen::Dynamic> Jframe_;  // scratch: a contact frame's 6-row Jacobian
  Eigen::Matrix<double, 6, 1> baseBias_, baseVelocity_;
  Eigen::Vector3d basePosition_;
  Eigen::Matrix3d baseRotation_;

  Eigen::Matrix<double, 6, Eigen::Dynamic> pointRows_;  // scratch: a swinging foot's two points' rows
  Eigen::Matrix<double, 6, 1> pointTargets_;
  TaskStack tasks_;     // hierarchical layout, always built
  int limbsLevel_ = kLevelLimbs, baseLevel_ = kLevelBase;  // their levels in tasks_ this tick
  TaskStack weighted_;  // the weighted variant's stack
  HierarchicalQp hqp_;
  Eigen::VectorXd xi_;
};

}  // namespace ballast::wbc
