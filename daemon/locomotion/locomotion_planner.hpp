// The planner pipeline of the paper's Fig. 4, up to the whole-body controller:
//   operator command + estimated state -> gait (contact schedule, footholds, swing
//   trajectories) -> references per MPC node -> SQP iterations (SqpSolver::solve) -> Plan
// and PlanSampler, which reads a Plan at the controller's rate.
//
// The operator's velocity is slewed (maxAcceleration); walking from standing starts
// walkStartDelay later (weight shift first), and stepping goes on stopDelay after the slewed
// velocity reached zero. Footholds: eq. (desired_swing_traj) from the measured base, moved
// towards the reference base by at most footholdLead.
//
// References per node t_k = t + k·dt:
//   contact mode from the schedule; swing points follow their swing trajectories (sampled at
//   the middle of each node's interval, where the problem evaluates them);
//   base: walking, the commanded velocity integrated as a position and a heading that advance
//   with the command (so steady speed and heading errors show as position errors and are
//   corrected, not inherited) — restarted from the measured base while the commanded velocity
//   is still slewing, and its position kept at the measured base while a push has the
//   footholds on the capture point's (RecoveryParameters::walkingPushForcePerKg) — held within
//   `maxPositionLead` of the measured base so a push is not followed by a sprint; then an arc
//   over the horizon. Standing: over
//   the feet, facing their heading plus the pose yaw. Height above the ground the feet stand
//   on (the terrain under the contact points, a swinging point's where it lands, averaged),
//   roll and pitch from the pose command;
//   momentum: m·v_des linear, I_zz·ω_des about z; joints: the nominal posture;
//   forces: the weight shared by the stance points; joint velocities: zero.
// Standing recovery steps: standing, when the capture point (with the push's offset) leaves the
// support polygon, the planner steps on its own (gait/recovery.hpp) with zero commanded velocity,
// the capture point's footholds and the base reference where the base is, until the point is
// back inside and the body slow; Plan::recovering says so meanwhile.
// Cost weights are given per physical quantity (CostWeights) and turned into Q and R here.
//
// The MPC's model (LocomotionSettings::model): the paper's kino-dynamic problem, or the
// single-rigid-body one of its cI (mpc/single_rigid_body_problem.hpp: the robot at its nominal
// posture as one body). The latter's state and input are the kino-dynamic ones' first 12 entries,
// so the references, the measured state and the Plan keep one layout: its plans carry the
// nominal posture as the joints and zero joint velocities.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gait/footholds.hpp"
#include "gait/recovery.hpp"
#include "gait/terrain_query.hpp"
#include "locomotion/plan.hpp"
#include "model/data.hpp"
#include "mpc/kinodynamic_problem.hpp"
#include "mpc/single_rigid_body_problem.hpp"
#include "mpc/sqp_solver.hpp"

namespace ballast::locomotion {

/// Weights of the squared tracking errors, per second of horizon (the profile's planner.q_* and
/// planner.r_*; why the defaults are what they are is written beside their keys in
/// daemon/profile/schema.cpp).
struct CostWeights {
  double linearVelocity;            ///< on (h_lin/m − v_ref), (m/s)⁻²
  double angularMomentum;           ///< on h_ang/m, (m²/s)⁻²
  Eigen::Vector3d basePosition;     ///< x, y, z, m⁻²
  Eigen::Vector3d baseOrientation;  ///< yaw, pitch, roll, rad⁻²
  double legJoint;                  ///< rad⁻²
  double armJoint;                  ///< rad⁻²
  double force;                     ///< N⁻²
  double legJointVelocity;          ///< (rad/s)⁻²
  double armJointVelocity;          ///< (rad/s)⁻²
};

/// What the MPC predicts the robot with (planner.model).
enum class PlannerModel : std::uint8_t {
  kKinodynamic,     ///< centroidal dynamics with full kinematics (the paper's, cH and cNH)
  kSingleRigidBody, ///< one rigid body at the nominal posture, convex (the paper's cI)
};

/// Filled by the profile (gait.*, planner.*) and, for the robot's part, from the model.
struct LocomotionSettings {
  PlannerModel model = PlannerModel::kKinodynamic;
  std::array<std::string, kNumContacts> contactFrames;
  Eigen::VectorXd nominalJoints;        ///< nj; nominal posture (legs bent, arms hanging)
  std::vector<bool> armJoint;           ///< nj; true for arm joints (their own weights)
  double nominalHeight = 0.85;          ///< base above the terrain, m
  double maxPositionLead;               ///< commanded base position kept this close, m
  /// Footholds are placed from the measured base moved towards the commanded one by at most
  /// this (see update()): enough to walk a standing position error off, not a lead.
  double footholdLead;                  ///< m
  /// The commanded velocity slews towards the operator's at these rates (a step from standing
  /// to 1.2 m/s is not a motion a biped can make); stopping decelerates the same way and the
  /// gait stands once the slewed velocity is zero.
  double maxAcceleration;               ///< m/s², forward and lateral
  double maxYawAcceleration;            ///< rad/s²
  /// Stepping goes on this long after the commanded velocity reached zero: the steps that take
  /// out the velocity the body still carries (the slewed command stops before the robot does).
  double stopDelay;                     ///< s
  gait::Gait walkGait;                  ///< walking (the profile layer sets it so)
  /// Walking faster, the cycle and its double support shorten so that a swing foot's mean
  /// speed stays within this and a step within swing.limits.maxForward (gait/cadence.hpp).
  double maxSwingSpeed;                 ///< m/s; 0: no limit
  /// Walking from standing begins this long after it is asked for: the plan shifts the weight
  /// onto the first stance foot in double support meanwhile (the schema's default says why).
  /// The commanded velocity starts slewing then too.
  double walkStartDelay;                ///< s
  gait::SwingPlannerParameters swing;
  /// Standing: steps when a push carries the capture point out of the support polygon
  /// (gait/recovery.hpp), with the capture point's footholds whatever gait.footholds says.
  gait::RecoveryParameters recovery;
  CostWeights weights;
  mpc::ProblemSettings problem;         ///< weights are filled from `weights`
  mpc::SqpSettings sqp;
};

/// What the operator asks for, in the planner's terms.
struct LocomotionCommand {
  bool walk = false;
  double vx = 0.0, vy = 0.0, yawRate = 0.0;  ///< heading frame, m/s and rad/s
  double height = 0.0;                       ///< base above terrain, m; 0: nominal
  double roll = 0.0, pitch = 0.0, yaw = 0.0; ///< base orientation relative to the feet, rad
  /// Standing: the joint posture (nj) that realises the pose with the feet where they are, as
  /// the joints' reference (a pose the nominal posture contradicts is otherwise a compromise
  /// between the base and joint weights). Empty: the nominal posture.
  Eigen::VectorXd standingJoints;
};

class LocomotionPlanner {
 public:
  /// Throws model::ModelError for unknown contact frames, std::invalid_argument for settings
  /// of the wrong size. The terrain must outlive the planner.
  LocomotionPlanner(const model::Model& model, const LocomotionSettings& settings,
                    const gait::TerrainQuery& terrain);
  ~LocomotionPlanner();

  /// Plans from the estimated state (model q, v) at controller time t into `plan`. Returns
  /// false when the MPC iteration failed; `plan` then keeps the last good plan (valid stays
  /// as it was) and statistics().message says why.
  bool update(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
              const LocomotionCommand& command, Plan& plan);

  /// Between update()s: the SQP's preparation for the next one, at controller time t, on the
  /// contact schedule as it is (mpc::SqpSolver::prepare). Nothing changes but how soon that
  /// update() is done.
  void prepare(double t);

  /// The estimated external force on the robot (world, N) for the next update()s: the footholds
  /// lean into it (gait/step_adjustment.hpp).
  void setExternalForce(const Eigen::Vector3d& force) { externalForce_ = force; }
  /// Wall time (s) after which an update() starts no further SQP iteration
  /// (mpc::SqpSolver::solve); 0: none.
  void setIterationBudget(double seconds) { iterationBudget_ = seconds; }

  /// The single-rigid-body problem's body: the robot at the nominal posture.
  static mpc::RigidBody nominalBody(const model::Model& model, const Eigen::VectorXd& nominalJoints);

  const mpc::SqpStatistics& statistics() const { return sqp_->statistics(); }
  const LocomotionSettings& settings() const { return settings_; }
  /// The contact points' positions in the nominal stance, relative to the base (heading frame).
  const std::array<Eigen::Vector3d, kNumContacts>& nominalStance() const { return stance_; }
  /// The velocity the plan follows now: the operator's, slewed (see maxAcceleration).
  const gait::VelocityCommand& commandedVelocity() const { return velocity_; }
  /// The kino-dynamic MPC state for (q, v): h = A(q)v, base position, ZYX angles (yaw continued
  /// from the previous call), joints (the single-rigid-body MPC takes its first 12 entries).
  Eigen::VectorXd measuredState(const Eigen::VectorXd& q, const Eigen::VectorXd& v);

 private:
  /// The operator's command with its velocity slewed to time t (advances velocity_).
  LocomotionCommand slewed(double t, const LocomotionCommand& operatorCommand);
  /// Standing recovery steps: begins or ends them from the state (gait/recovery.hpp).
  void updateRecovery(double t, bool operatorWalks, const gait::GaitState& state, double yaw);
  /// Walking: whether a push hands the footholds to the capture point (pushStepping_).
  void updatePushSteps(double t, const gait::GaitState& state);
  /// The base reference at t (see the header comment); advances the commanded pose.
  gait::PlanarPose referenceStart(double t, const Eigen::VectorXd& x,
                                  const LocomotionCommand& command, double feetYaw);
  void fillReferences(double t, const gait::PlanarPose& start, const LocomotionCommand& command);
  /// u_ref: the weight shared by the stance points of `flags`, nothing else.
  void weightOnStance(const gait::ContactFlags& flags, Eigen::VectorXd& u) const;

  const model::Model& model_;
  LocomotionSettings settings_;
  const gait::TerrainQuery& terrain_;
  std::array<int, kNumContacts> frames_{};
  std::array<Eigen::Vector3d, kNumContacts> stance_{};
  model::Data<double> data_;
  std::unique_ptr<mpc::OptimalControlProblem> problem_;
  std::unique_ptr<mpc::SqpSolver> sqp_;
  gait::ContactSchedule schedule_;
  gait::SwingPlanner swings_;
  double lastYaw_ = 0.0;
  bool haveYaw_ = false;
  double heading_ = 0.0;      ///< commanded heading while walking: integrates the yaw rate
  Eigen::Vector2d position_ = Eigen::Vector2d::Zero();  ///< commanded base x, y while walking
  double commandTime_ = 0.0;
  bool walking_ = false;
  gait::VelocityCommand velocity_;  ///< the operator's, slewed
  double velocityTime_ = -1.0;      ///< when velocity_ was last slewed
  double walkStartsAt_ = 0.0;       ///< when the last start from standing takes its first step
  bool accelerating_ = false;       ///< velocity_ is still slewing towards the operator's
  double lastCommandedMotion_ = -1e9;  ///< last time velocity_ was not zero
  /// Standing recovery (gait/recovery.hpp): recovering_ while steps are asked for,
  /// recoveryActive_ until the schedule stands again after them.
  bool recovering_ = false;
  bool recoveryActive_ = false;
  /// Walking: a push hands the footholds to the capture point (RecoveryParameters::
  /// walkingPushForcePerKg) while pushStepping_; the push was last over half that force then.
  bool pushStepping_ = false;
  double lastPushTime_ = 0.0;
  /// The direction of the push (world, unit) when it was last over the switch's force.
  Eigen::Vector2d pushDirection_ = Eigen::Vector2d::UnitX();
  gait::Gait recoveryGait_;
  Eigen::Vector3d externalForce_ = Eigen::Vector3d::Zero();
  double iterationBudget_ = 0.0;  ///< s, setIterationBudget
};

/// Reads a Plan at the controller's rate (owns its scratch: one per reading thread).
class PlanSampler {
 public:
  PlanSampler(const model::Model& model, const std::array<int, kNumContacts>& contactFrames);
  /// The plan at time t (clamped to its horizon). No allocation.
  void sample(const Plan& plan, double t, PlanSample& out);

 private:
  const model::Model& model_;
  std::vector<int> frames_;
  model::Data<double> data_;
  Eigen::VectorXd x_, u_, xdot_;
};

/// The contact frame indices for the settings' names (throws model::ModelError).
std::array<int, kNumContacts> contactFrameIds(const model::Model& model,
                                              const LocomotionSettings& settings);

}  // namespace ballast::locomotion
