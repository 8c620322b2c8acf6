// The kino-dynamic optimal control problem of the paper's Sec. II-A, one node at a time.
//
// State and input (model/centroidal_dynamics.hpp, and the soles' moments):
//   x = [h_com (6), p_b (3), zyx_b (3), q_j (nj)],
//   u = [f_c1..f_c4 (12, world), v_j (nj)(, m_left, m_right: soles with width)]
// Contact points, in this order: left toe, left heel, right toe, right heel.
//
// Soles with width: toe and heel lie on a line along the sole, so their forces exert no moment
// about it, and a foot standing alone could not resist a roll (a sideways push in single support:
// the plan had to hop, unloading the foot, to keep the body from rolling over it). A real sole
// has a width w (ProblemSettings::soleWidth), over which its centre of pressure moves: m_foot is
// the moment about its toe-heel line, along a = (p_toe − p_heel)/‖p_toe − p_heel‖ (world, at
// x_mid), added to the angular momentum's rate, ḣ_ang += m_left a_left + m_right a_right,
// and bounded by the sole's normal force, |m| ≤ (w/2)(f_z,toe + f_z,heel), as a relaxed barrier
// (in force units: f_z,toe + f_z,heel ∓ 2m/w ≥ 0); a foot not standing on both points has
// m = 0 as an equality. With w = 0 (the four-point model's line feet, the paper's) the inputs
// are not there: u is the layout's, and the problem is the paper's. The whole-body
// controller needs no such input: its stance feet do not roll (whole_body_controller.hpp), and
// the ankle roll torque that takes is the moment.
//
// Equalities (projected out by the solver), per foot:
//   stance point:  contact velocity = 0
//   swing point:   force = 0, and velocity = ṗ*(t) + k_p (p*(t) − p)   — the paper's
//                  p = p*, ṗ = ṗ* as one velocity-level condition, so that it can be projected
//                  out like the stance one and still pulls the point onto its trajectory.
//   Toe and heel of one foot are one rigid body: (v_toe − v_heel)·d = 0 always holds along the
//   toe-heel direction d, so the heel's condition keeps only two components: it drops the world
//   axis along which d is largest (the rows stay independent, the Jacobian exact).
//   Feet that cannot yaw relative to the base (ProblemSettings::feetFollowBaseYaw: no hip yaw,
//   or both locked) have the base's yaw, which the legs reach only through the pitch axes the hip
//   roll tilts. Rows asking for it were nearly dependent (sines 1e-3..1e-2, above the projection's
//   cut) and met with joint velocities of 10-900 rad/s: the robot fell within 1 s of walking.
//   There a swinging foot's conditions are its middle (the mean of toe and heel, 3 rows) and its
//   pitch (their difference along z, 1 row), and with both feet standing the second heel keeps
//   only its vertical row: the first foot holds the yaw.
// Inequalities, as relaxed-barrier costs (eq. rbf): friction cone μ f_z ≥ sqrt(f_x² + f_y² + ε²)
// and f_min ≤ f_z ≤ f_max on stance points, joint position and velocity limits, and the feet
// distance ‖p_left − p_right‖² ≥ d_min² for toe–toe and heel–heel (eq. collsion). The joint
// position limits have a second, stiff barrier that acts only near them (jointStop, zero farther
// than its reach): the paper's weight (0.1) is a slope of 5 per rad at δ, against tracking costs
// of hundreds, and plans for a sideways push rolled the pelvis 0.4 rad, through both hip roll
// limits (the swing leg then stopped by its joint, the robot fell); the log barrier made stiff
// everywhere would pull every joint towards the middle of its range (ξ/h) and walk differently.
// Cost: ½‖x − x_ref‖²_Q + ½‖u − u_ref‖²_R + barriers (Gauss-Newton Hessians), the yaw error
// wrapped to (−π, π].
//
// Discretisation: x⁺ = x + dt f(x_mid, u), with x_mid = x + (dt/2)·[0; 0; v_j] the configuration
// at the middle of the interval (joints advanced half a step; momentum and base as at its
// start). The contact-point equalities and the feet distance are evaluated at x_mid too. Plain
// explicit Euler (f at x) lets the optimiser gain base motion from nothing: joint velocities
// that alternate sign node to node return the joints where they were but move the base by
// dt²·v²·∂(A_b⁻¹A_j)/∂q_j per pair of nodes, because each step uses the momentum map of the
// configuration it starts from — a free actuator for the base (its underactuated roll in
// particular) that the robot does not have, and one the plans that chattered at the joint
// velocity limits with small velocity weights could use. At the midpoint the two half-cycles
// use the same map and the O(dt²·v²) term cancels (test/unit/mpc: what is left is third order
// in dt·v, 4–300 times smaller at dt·v = 0.2 rad), and the contact points drift at O(dt³) per
// node instead of O(dt²). Same cost per node as Euler: one derivative evaluation, at x_mid.
#pragma once

#include <array>
#include <vector>

#include "model/data.hpp"
#include "model/frame_derivatives_zyx.hpp"
#include "mpc/optimal_control_problem.hpp"
#include "mpc/relaxed_barrier.hpp"

namespace ballast::mpc {

/// The weights, bounds and barriers the profile tunes come from it (planner.*, gait.*); the
/// cone's regularisation and the collision barrier are the problem's own.
struct ProblemSettings {
  Eigen::VectorXd stateWeights;      ///< diag(Q), nx
  Eigen::VectorXd inputWeights;      ///< diag(R), nu
  double terminalWeightScale;        ///< Q_N = scale · Q
  double frictionCoefficient;        ///< μ
  double frictionRegularization = 1.0;  ///< ε² in the cone, N²
  double minNormalForce;             ///< N
  double maxNormalForce;             ///< N
  double minFeetDistance;            ///< m
  double jointLimitMargin;           ///< rad kept from each URDF limit
  double swingPositionGain;          ///< k_p of the swing velocity condition, 1/s
  /// No leg turns its foot about the vertical relative to the base (no hip yaw, or locked): a
  /// foot's yaw is then the base's, which a standing foot holds: a swinging foot's conditions
  /// are its middle and its pitch, and a second standing foot leaves its yaw to the first (see
  /// the header).
  bool feetFollowBaseYaw = false;
  RelaxedBarrier frictionBarrier;    ///< on force terms (N)
  RelaxedBarrier limitBarrier;       ///< on joint limits (rad, rad/s)
  RelaxedBarrier jointStop{10.0, 0.02, 0.15};  ///< on joint position limits, near them only (rad)
  RelaxedBarrier collisionBarrier{0.1, 0.005};  ///< on squared distance (m²)
  /// Width (m) across a sole over which its centre of pressure moves (see the header); 0: line
  /// feet, no moment about the toe-heel line.
  double soleWidth = 0.0;
};

class KinodynamicProblem;

/// Per-thread scratch for evaluating nodes.
struct NodeWorkspace : ProblemWorkspace {
  explicit NodeWorkspace(const KinodynamicProblem& problem);
  model::Data<double> data;
  Eigen::VectorXd xdot;
  Eigen::MatrixXd Ax, Bu;  ///< ∂f/∂x at x_mid; ∂f/∂u including the path through x_mid
  Eigen::VectorXd xMid;
  std::vector<model::FrameKinematicsZyx> contacts;  ///< at x_mid; du including x_mid's path
  std::vector<model::Mat3X<double>> dPosition_du;   ///< contact positions through x_mid
  model::Mat3X<double> rowDx, rowDu;                ///< scratch: one point's equality rows
  /// Scratch: a swinging foot's toe and heel conditions, combined into the foot's rows when
  /// its yaw is not the legs' to choose (ProblemSettings::feetFollowBaseYaw).
  std::array<model::Mat3X<double>, 2> pointDx, pointDu;
  std::array<Eigen::Vector3d, 2> pointResidual;
  Eigen::Vector3d rowResidual;
  Eigen::VectorXd gradX, gradU;                     ///< scratch: a barrier's gradient
  model::Mat3X<double> axisDx;                      ///< scratch: ∂(a sole's toe-heel line)/∂x
  Eigen::RowVectorXd axisRow;                       ///< scratch: aᵀ axisDx
  Eigen::VectorXd xError, uError;                   ///< scratch: x − x_ref (yaw wrapped), u − u_ref
  /// The point (x, u, dt) at which xdot (without the external force), Ax, Bu, contacts and
  /// dPosition_du hold their derivatives (linearize()); forgotten when evaluate() overwrites them.
  Eigen::VectorXd derivativesX, derivativesU;
  double derivativesDt = 0.0;
  bool haveDerivatives = false;
  /// The node linearize() wrote its matrices into last, with which contact mode and settings.
  const LqNode* matricesNode = nullptr;
  StanceFlags matricesStance{};
  unsigned matricesSettings = 0;
};

class KinodynamicProblem final : public OptimalControlProblem {
 public:
  /// contactFrames: model frame indices of left toe, left heel, right toe, right heel. Throws as
  /// setSettings().
  KinodynamicProblem(const model::Model& model, const std::array<int, kNumContacts>& contactFrames,
                     const ProblemSettings& settings);

  /// Inputs after the kino-dynamic layout's for soles with width (ProblemSettings::soleWidth
  /// > 0): their moments (left, right), N·m. Line feet have none, and the layout's nu.
  static int soleMoments(const ProblemSettings& s) { return s.soleWidth > 0.0 ? 2 : 0; }

  int nx() const override { return nx_; }
  int nu() const override { return nu_; }
  int maxEqualities() const override { return 2 * 5 + 3 * kNumContacts + soles_; }
  /// Index in u of the moment of foot 0 (left) or 1 (right) about its toe-heel line (soles with
  /// width only).
  int soleMoment(int foot) const { return nu_ - soles_ + foot; }
  std::unique_ptr<ProblemWorkspace> makeWorkspace() const override {
    return std::make_unique<NodeWorkspace>(*this);
  }
  const model::Model& model() const { return model_; }
  const std::vector<int>& contactFrames() const { return contactFrames_; }
  const ProblemSettings& settings() const { return settings_; }
  /// Throws std::invalid_argument for weights of the wrong sizes (nx, nu), a negative sole width,
  /// or one that would change nu (line feet against soles with width: a new problem).
  void setSettings(const ProblemSettings& s);

  void evaluate(ProblemWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
                const Eigen::VectorXd& u, double dt, NodeValue& value) const override;
  void linearize(ProblemWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
                 const Eigen::VectorXd& u, double dt, LqNode& node, NodeValue& value) const override;
  /// Its node matrices depend on x, u, dt, the contact mode and the settings alone.
  bool keepsMatrices() const override { return true; }
  double terminalCost(ProblemWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
                      LqNode* node) const override;
  /// Zero force on a point that became a swing, the reference force on a new stance.
  void adaptInputToMode(const NodeReference& ref, const StanceFlags& before,
                        Eigen::VectorXd& u) const override;

 private:
  /// ws.xdot = f(x_mid, u) without the external force, and ws.contacts' positions and
  /// velocities; with derivatives also Ax, Bu, the contacts' Jacobians and dPosition_du, through
  /// x_mid (see the header), and ws remembers the point.
  void dynamics(NodeWorkspace& ws, const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                bool derivatives) const;
  void compute(NodeWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
               const Eigen::VectorXd& u, double dt, LqNode* node, NodeValue& value) const;
  /// A foot stands on its sole (both its points in stance) and the sole has width.
  bool standsOnSole(const NodeReference& ref, int foot) const;
  /// The soles' moments in ẋ (and, with derivatives, in ∂f/∂u and ∂f/∂x), from ws.contacts.
  void addSoleMoments(NodeWorkspace& ws, const Eigen::VectorXd& u, bool derivatives) const;

  const model::Model& model_;
  std::vector<int> contactFrames_;
  ProblemSettings settings_;
  Eigen::VectorXd terminalWeights_;  ///< diag(Q_N) = terminalWeightScale · stateWeights
  int nx_, nu_;
  int soles_;  ///< soleMoments(): inputs of the soles' moments, 0 or 2
  unsigned settingsVersion_ = 0;  ///< counts setSettings(): a node's matrices are of one
};

}  // namespace ballast::mpc
