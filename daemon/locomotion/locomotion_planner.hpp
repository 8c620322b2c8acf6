// The planner pipeline of the paper's Fig. 4, up to the whole-body controller:
//   operator command + estimated state -> gait (contact schedule, footholds, swing
//   trajectories) -> references per MPC node -> one SQP iteration -> Plan
// and PlanSampler, which reads a Plan at the controller's rate.
//
// References per node t_k = t + k·dt:
//   contact mode from the schedule; swing points follow their swing trajectories;
//   base: walking, the commanded velocity integrated since walking began, as a position and a
//   heading that advance with the command (so speed and heading errors show as position
//   errors and are corrected, not inherited), held within `maxPositionLead` of the measured
//   base so a push is not followed by a sprint; then an arc over the horizon. Standing: over
//   the feet, facing their heading plus the pose yaw. Height above the terrain under the base,
//   roll and pitch from the pose command;
//   momentum: m·v_des linear, I_zz·ω_des about z; joints: the nominal posture;
//   forces: the weight shared by the stance points; joint velocities: zero.
// Cost weights are given per physical quantity (CostWeights) and turned into Q and R here.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "gait/footholds.hpp"
#include "gait/terrain_query.hpp"
#include "locomotion/plan.hpp"
#include "model/data.hpp"
#include "mpc/kinodynamic_problem.hpp"
#include "mpc/sqp_solver.hpp"

namespace ballast::locomotion {

/// Weights of the squared tracking errors, per second of horizon.
struct CostWeights {
  double linearVelocity = 40.0;       ///< on (h_lin/m − v_ref), (m/s)⁻²
  double angularMomentum = 1.0;       ///< on h_ang/m, (m²/s)⁻²
  Eigen::Vector3d basePosition{200.0, 200.0, 800.0};     ///< x, y, z, m⁻²
  Eigen::Vector3d baseOrientation{300.0, 800.0, 800.0};  ///< yaw, pitch, roll, rad⁻²
  double legJoint = 5.0;              ///< rad⁻²
  double armJoint = 5.0;              ///< rad⁻²
  double force = 1e-3;                ///< N⁻²
  double legJointVelocity = 0.05;     ///< (rad/s)⁻²
  double armJointVelocity = 0.2;      ///< (rad/s)⁻²
};

struct LocomotionSettings {
  std::array<std::string, kNumContacts> contactFrames{"left_toe", "left_heel", "right_toe",
                                                      "right_heel"};
  Eigen::VectorXd nominalJoints;        ///< nj; nominal posture (legs bent, arms hanging)
  std::vector<bool> armJoint;           ///< nj; true for arm joints (their own weights)
  double nominalHeight = 0.85;          ///< base above the terrain, m
  double maxPositionLead = 0.15;        ///< commanded base position kept this close, m
  gait::Gait walkGait{true, 0.8, 0.2, 0.0};
  gait::SwingPlannerParameters swing;
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

  const mpc::SqpStatistics& statistics() const { return sqp_->statistics(); }
  const LocomotionSettings& settings() const { return settings_; }
  /// The contact points' positions in the nominal stance, relative to the base (heading frame).
  const std::array<Eigen::Vector3d, kNumContacts>& nominalStance() const { return stance_; }
  /// The MPC state for (q, v): h = A(q)v, base position, ZYX angles (yaw continued from the
  /// previous call), joints.
  Eigen::VectorXd measuredState(const Eigen::VectorXd& q, const Eigen::VectorXd& v);

 private:
  /// The base reference at t (see the header comment); advances the commanded pose.
  gait::PlanarPose referenceStart(double t, const Eigen::VectorXd& x,
                                  const LocomotionCommand& command, double feetYaw);
  void fillReferences(double t, const gait::PlanarPose& start, const LocomotionCommand& command);

  const model::Model& model_;
  LocomotionSettings settings_;
  const gait::TerrainQuery& terrain_;
  std::array<int, kNumContacts> frames_{};
  std::array<Eigen::Vector3d, kNumContacts> stance_{};
  model::Data<double> data_;
  std::unique_ptr<mpc::KinodynamicProblem> problem_;
  std::unique_ptr<mpc::SqpSolver> sqp_;
  gait::ContactSchedule schedule_;
  gait::SwingPlanner swings_;
  double lastYaw_ = 0.0;
  bool haveYaw_ = false;
  double heading_ = 0.0;      ///< commanded heading while walking: integrates the yaw rate
  Eigen::Vector2d position_ = Eigen::Vector2d::Zero();  ///< commanded base x, y while walking
  double commandTime_ = 0.0;
  bool walking_ = false;
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
