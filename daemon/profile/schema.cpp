// The profile schema's table (schema.hpp): one row per key, Redis config.c-style, each with the
// field of Settings it fills; rules across keys beside the rows they relate; aliases for the
// fields the settings derive from a key (problems about them are reported at that key). The
// helpers of plugins/common/settings_schema.hpp keep a row on one line or two.
#include "profile/schema.hpp"

#include <cmath>
#include <string>

#include "model/contact_points.hpp"
#include "profile/settings.hpp"

namespace ballast::profile {

namespace {

using namespace schema;  // the row declarations
using S = Settings;
using B = BackendSettings;
using J = JointSettings;
using C = control::ControlSettings;
using E = estimation::EstimatorSettings;
using L = locomotion::LocomotionSettings;
using G = gait::Gait;
using SW = gait::SwingPlannerParameters;
using F = gait::FootholdParameters;
using Q = locomotion::CostWeights;
using P = mpc::ProblemSettings;
using SQ = mpc::SqpSettings;
using W = wbc::WbcSettings;
using SV = server::ServerConfig;
using R = Rule<Settings>;
using MS = control::MappingSettings;
using LM = terrain::LiveMapSettings;

constexpr double kPi = 3.14159265358979323846;

/// [weight, delta] -> a relaxed barrier.
void toBarrier(mpc::RelaxedBarrier& b, const Value& v) {
  b.weight = v.numbers[0];
  b.delta = v.numbers[1];
}

/// [weight, delta, reach] -> a relaxed barrier acting only within reach of its bound.
void toReachingBarrier(mpc::RelaxedBarrier& b, const Value& v) {
  toBarrier(b, v);
  b.reach = v.numbers[2];
}

/// [ahead, behind] -> the step limits' reach along the heading.
void toStepLength(gait::StepLimits& l, const Value& v) {
  l.maxForward = v.numbers[0];
  l.maxBackward = v.numbers[1];
}

/// "[left_toe, left_heel, right_toe, right_heel]": the humanoid's frames, named in one place.
std::string contactFramesDefault() {
  std::string list;
  for (const char* name : model::kContactFrameNames) list += (list.empty() ? "[" : ", ") + std::string(name);
  return list + "]";
}
const std::string kContactFramesDefault = contactFramesDefault();

// clang-format off
const Schema<Settings> kTable({
  // ---- the profile itself
  text("extends", "", "base profile: a file (relative to this one) or a profile name; maps merge, scalars and lists replace").into<&S::extends>(),
  text("description", "", "one line about the profile, shown by `ballast profile list`").into<&S::description>(),

  // ---- robot: the model and its standing posture
  path("robot.urdf", "", "robot model (URDF); required").needsRestart().into<&S::urdf>(),
  frames("robot.contact_frames", kContactFramesDefault.c_str(), false, "the four contact points, left toe, left heel, right toe, right heel: each a URDF link, or {link: NAME, offset: [x, y, z]} (m, in that link's frame) for a vendor's URDF that has no such links; the simulation's foot contact is on them too").ofLength(model::kNumContacts).needsRestart().into<&S::contact_points>(),
  frame("robot.imu_frame", "imu", true, "the IMU: a URDF link, or {link: NAME, offset: [x, y, z], rpy: [r, p, y]} (m and rad, in that link's frame); it must be fixed to the floating base").needsRestart().into<&S::imu>(),
  groupMap("robot.joint_groups", "{}", "joint groups, name: [URDF joints]; every actuated joint belongs to exactly one").needsRestart().into<&S::joints, &J::groups>(),
  numberMap("robot.armature", "{}", 0, 10, "kg·m²", "reflected rotor inertia (rotor inertia times the gear ratio squared) per joint group or joint (a joint's entry wins over its group's), in the controller's model and the simulation; joints not listed: 0").needsRestart().into<&S::joints, &J::armature>(),
  numberMap("robot.locked_joints", "{}", -2 * kPi, 2 * kPi, "rad", "joints fixed at an angle, joint: angle (m for a prismatic one): merged into their parent body in the controller's model and the simulation, in no joint group and never commanded; the socketcan backend holds a locked joint that has a motor with the motor's own PD (backend.socketcan.hold.kp)").needsRestart().into<&S::joints, &J::locked>(),
  numberMap("robot.nominal_posture", "{}", -2 * kPi, 2 * kPi, "rad", "standing posture, joint: angle; joints not listed stand at 0").into<&S::joints, &J::posture>(),

  // ---- control: the loop and the standing controller
  number("control.rate", "1000", 100, 5000, "Hz", "control loop rate").needsRestart().into<&S::control, &C::rate>(),
  choice("control.initial_mode", "passive", "passive|stand-up", "mode at start: passive, or stand-up at once (a simulated robot that starts on its feet)").needsRestart().into<&S::control, &C::initial_mode>(),
  number("control.stand_up_duration", "2", 0.1, 30, "s", "stand-up: from the posture at its start to the standing posture").into<&S::control, &C::stand_up_duration>(),
  numberMap("control.joint_kp", "{}", 0, 5000, "N·m/rad", "joint stiffness per joint group (motor PD)").into<&S::joints, &J::kp>(),
  numberMap("control.joint_kd", "{}", 0, 500, "N·m·s/rad", "joint damping per joint group (motor PD)").into<&S::joints, &J::kd>(),
  flag("control.gravity_compensation", "true", "add the model's gravity torques (least-norm contact forces) to the joint PD").into<&S::control, &C::gravity_compensation>(),
  number("control.gain_blend_time", "0.5", 0, 10, "s", "profile switch: gains blend from the old to the new over this time").into<&S::control, &C::gain_blend_time>(),
  number("control.pose_speed", "0.1", 0.01, 1, "m/s", "standing height changes at most this fast").into<&S::control, &C::pose_speed>(),
  number("control.pose_angular_speed", "0.3", 0.01, 3, "rad/s", "standing orientation changes at most this fast").into<&S::control, &C::pose_angular_speed>(),

  // ---- backend: the plugin and its own section
  text("backend.name", "simbody", "backend plugin: libballast_backend_<name>.so").needsRestart().into<&S::backend, &B::name>(),
  paths("backend.plugin_dirs", "[]", "directories searched first for the plugin; then $BALLAST_PLUGIN_PATH, the build tree, the install tree").needsRestart().into<&S::backend, &B::plugin_dirs>(),
  integer("backend.seed", "0", 0, 9007199254740992.0, "", "seed for sensor noise and anything random in the backend").needsRestart().into<&S::backend, &B::seed>(),

  // ---- gait (daemon/gait; locomotion/locomotion_planner.hpp LocomotionSettings)
  number("gait.period", "0.8", 0.2, 2, "s", "gait cycle: one step of each leg").into<&S::control, &C::locomotion, &L::walkGait, &G::period>(),
  number("gait.double_support", "0.2", 0, 0.8, "", "fraction of the cycle with both feet on the ground").into<&S::control, &C::locomotion, &L::walkGait, &G::doubleSupport>(),
  number("gait.toe_off_lead", "0", 0, 0.5, "s", "toe-off and heel-strike: a heel lifts and lands this much before its toe (0: together)").into<&S::control, &C::locomotion, &L::walkGait, &G::toeOffLead>(),
  number("gait.swing_apex", "0.08", 0.01, 0.3, "m", "swing-foot clearance at mid-swing, above the terrain").into<&S::control, &C::locomotion, &L::swing, &SW::apexClearance>(),
  choice("gait.footholds", "paper", "paper|capture_point", "foothold rule: the paper's hip + T/2 v_des + k (v - v_des) + (h/g) v x w_des (its centrifugal term as the inverted pendulum's, daemon/gait/footholds.hpp), or step adjustment from the capture point of the measured centre of mass with the estimated push in the MPC's dynamics (daemon/gait/step_adjustment.hpp; experimental)").into<&S::control, &C::locomotion, &L::swing, &SW::rule>(),
  number("gait.foothold_gain", "0.15", 0, 1, "", "gait.footholds paper: k of the foothold rule hip + T/2 v_des + k (v - v_des), v the centre of mass's velocity").into<&S::control, &C::locomotion, &L::swing, &SW::foothold, &F::feedbackGain>(),
  numbers("gait.max_step_length", "[0.5, 0.35]", 0, 2, "m", "farthest a foot lands [ahead of, behind] the stance foot: the capture point's footholds (gait.footholds capture_point, recovery steps) are held to it, and walking faster than 2 ahead/gait.period shortens the cycle to keep the steps within it (daemon/gait/cadence.hpp)").ofLength(2).into<&S::control, &C::locomotion, &L::swing, &SW::limits>(&toStepLength),
  number("gait.max_step_width", "0.45", 0, 2, "m", "gait.footholds capture_point: farthest a foot lands sideways from the stance foot (the closest: gait.min_foot_distance)").into<&S::control, &C::locomotion, &L::swing, &SW::limits, &gait::StepLimits::maxWidth>(),
  flag("gait.recovery_steps", "true", "standing: step when a push carries the capture point (with the push's offset f/(m w^2)) out of the support polygon, back to stand when it is inside and the body slow (daemon/gait/recovery.hpp); the steps take the capture point's footholds and gait.max_step_length/width").into<&S::control, &C::locomotion, &L::recovery, &gait::RecoveryParameters::enabled>(),
  number("gait.recovery_margin", "0", 0, 0.2, "m", "gait.recovery_steps: the capture point this far outside the support polygon starts steps, this far inside it (with gait.recovery_settle_speed) ends them").into<&S::control, &C::locomotion, &L::recovery, &gait::RecoveryParameters::margin>(),
  number("gait.recovery_settle_speed", "0.1", 0.01, 1, "m/s", "gait.recovery_steps: the centre of mass slower than this (and the capture point inside) ends the steps").into<&S::control, &C::locomotion, &L::recovery, &gait::RecoveryParameters::settleSpeed>(),
  number("gait.recovery_min_period", "0.6", 0.2, 2, "s", "gait.recovery_steps: the steps walk the gait of gait.period, shortened (down to this, or gait.period if shorter) when their first step would land too late to catch the capture point: the longest period at whose touch-down the capture point, carried away from the stance foot's nearest contact point, is still within gait.max_step_length and gait.max_step_width (daemon/gait/recovery.hpp); walking on the capture point's footholds (gait.footholds capture_point, or a push past gait.recovery_walking_force), while one of the next two steps is held to those limits the gait walks the longest period down to this at which they are not, from the next double support, and no shorter than its swings keep within gait.max_swing_speed").into<&S::control, &C::locomotion, &L::recovery, &gait::RecoveryParameters::minPeriod>(),
  number("gait.recovery_walking_force", "0.32", 0, 10, "N/kg", "walking on the paper's footholds (gait.footholds paper): an estimated push (horizontal, past estimator.external_force_deadband) stronger than this times the robot's mass (19.8 N on the 62 kg humanoid) hands the footholds to the capture point's (as gait.footholds capture_point, the push in the MPC's dynamics, the step timing of gait.recovery_min_period) until it has stayed under half this for a gait cycle, then back at a double support; 0: never").into<&S::control, &C::locomotion, &L::recovery, &gait::RecoveryParameters::walkingPushForcePerKg>(),
  number("gait.step_height", "0.03", 0, 1, "m", "a swing over terrain that rises or falls more than this is a step: the foot lifts before it moves and moves before it lands").into<&S::control, &C::locomotion, &L::swing, &SW::stepHeight>(),
  number("gait.step_lift", "0.1", 0, 0.45, "", "stepping: fraction of the swing at each end spent lifting (lowering) without moving horizontally; the horizontal motion takes the rest, its peak acceleration 1/(1 - 2 step_lift)^2 times a flat swing's").into<&S::control, &C::locomotion, &L::swing, &SW::stepLift>(),
  number("gait.replan_until", "0.7", 0, 1, "", "fraction of a swing after which its touch-down point is held").into<&S::control, &C::locomotion, &L::swing, &SW::replanUntil>(),
  number("gait.min_foot_distance", "0.12", 0, 1, "m", "closest the left and right contact points may come (swing planning and the MPC's collision constraint)").into<&S::control, &C::locomotion, &L::swing, &SW::minFeetDistance>(),
  number("gait.max_swing_speed", "3.1", 0, 20, "m/s", "fastest mean speed of a swing foot (its stride over its swing time, 2 v/(1 - gait.double_support) walking at v): walking faster, the double support shortens, down to none, to keep the swing within it (daemon/gait/cadence.hpp); with gait.max_step_length, what lets the gait walk faster than 1.25 m/s; the step timing of the capture point's footholds (gait.recovery_min_period) shortens a cycle only as far as its next two swings keep within it, the double support shortened first; 0: no limit").into<&S::control, &C::locomotion, &L::maxSwingSpeed>(),
  // With none, the first swing left 80 ms after the command, over a centre of mass still between
  // the feet, and the robot fell sideways into its first step.
  number("gait.walk_start_delay", "0.3", 0, 2, "s", "walking from standing starts this much after the command: the weight shifts onto the first stance foot meanwhile").into<&S::control, &C::locomotion, &L::walkStartDelay>(),
  number("gait.stop_delay", "0.1", 0, 2, "s", "stepping goes on this long after the commanded velocity reached zero (then the feet come together at the next double support)").into<&S::control, &C::locomotion, &L::stopDelay>(),
  number("gait.foothold_lead", "0.05", 0, 0.5, "m", "footholds are planned from the measured base moved toward the commanded one by at most this").into<&S::control, &C::locomotion, &L::footholdLead>(),

  // ---- planner: the kino-dynamic MPC (daemon/mpc, daemon/locomotion)
  choice("planner.model", "kinodynamic", "kinodynamic|single_rigid_body", "what the MPC predicts with: centroidal dynamics with full kinematics (the paper's), or the robot as one rigid body at the nominal posture, a convex MPC (the paper's cI; daemon/mpc/single_rigid_body_problem.hpp)").into<&S::control, &C::locomotion, &L::model>(),
  number("planner.rate", "100", 10, 1000, "Hz", "planner rate, controller time").needsRestart().into<&S::control, &C::planner_rate>(),
  number("planner.latency", "0.005", 0, 0.1, "s", "lockstep: a plan is used this long (controller time) after the state it starts from, as a real-time solve's delay (at most 1 / planner.rate); real time uses each plan when it arrives").needsRestart().into<&S::control, &C::planner_latency>(),
  number("planner.injected_stall", "0", 0, 5, "s", "testing, real time: the planner's thread sleeps this long in its first solve from planner.injected_stall_at on, as a planner that a busy host does not run (the loop tracks the plan in force until safety.max_plan_age); 0: never").needsRestart().into<&S::control, &C::planner_injected_stall>(),
  number("planner.injected_stall_at", "0", 0, 1e6, "s", "testing: the controller time from which planner.injected_stall is injected").needsRestart().into<&S::control, &C::planner_injected_stall_at>(),
  R{"planner.latency", [](const S& s) -> std::string {
      return s.control.planner_latency > 1.0 / s.control.planner_rate + 1e-9
                 ? "must be at most one planner period (1 / planner.rate)"
                 : "";
    }},
  number("planner.horizon", "1", 0.1, 5, "s", "MPC horizon (at most 100 nodes)").into<&S::planner_horizon>(),
  R{"planner.horizon", [](const S& s) -> std::string {
      const double dt = s.control.locomotion.sqp.dt, horizon = s.planner_horizon;
      const long nodes = std::lround(horizon / dt);
      if (dt >= horizon || horizon / dt > locomotion::kMaxNodes + 0.5 || (nodes >= 2 && nodes <= locomotion::kMaxNodes))
        return "";  // planner.dt's rule says what is wrong, or nothing is
      return "planner.horizon / planner.dt must give 2.." + std::to_string(locomotion::kMaxNodes) + " nodes";
    }},
  number("planner.dt", "0.02", 0.002, 0.2, "s", "MPC node spacing").into<&S::control, &C::locomotion, &L::sqp, &SQ::dt>(),
  R{"planner.dt", [](const S& s) -> std::string {
      const double dt = s.control.locomotion.sqp.dt, horizon = s.planner_horizon;
      if (dt >= horizon) return "must be shorter than planner.horizon";
      if (horizon / dt > locomotion::kMaxNodes + 0.5)
        return "planner.horizon / planner.dt is more than " + std::to_string(locomotion::kMaxNodes) +
               " nodes: make dt longer";
      return "";
    }},
  integer("planner.threads", "2", 1, 16, "", "threads that linearise the MPC's nodes").into<&S::control, &C::locomotion, &L::sqp, &SQ::threads>(),
  integer("planner.max_iterations", "3", 1, 20, "", "SQP iterations per plan at most: past the first (the real-time iteration), only while the plan is far from feasible, its violation over planner.violation_tolerance (mpc/sqp_solver.hpp, solve): a push's moved footholds left one iteration's plan with base accelerations that jumped by tens of m/s² from plan to plan; each iteration costs a plan's time again; 1: the real-time iteration alone").into<&S::control, &C::locomotion, &L::sqp, &SQ::maxIterations>(),
  number("planner.violation_tolerance", "0.3", 0, 1e6, "", "the plan's violation, sqrt(sum of its dynamics defects² and equality residuals²) over the horizon in SI units, above which it takes another SQP iteration (planner.max_iterations): ten times what walking undisturbed leaves (about 0.025)").into<&S::control, &C::locomotion, &L::sqp, &SQ::violationTolerance>(),
  number("planner.max_acceleration", "1", 0.05, 10, "m/s^2", "the commanded velocity slews toward the operator's at this rate").into<&S::control, &C::locomotion, &L::maxAcceleration>(),
  number("planner.max_yaw_acceleration", "1.5", 0.05, 20, "rad/s^2", "the commanded yaw rate slews toward the operator's at this rate").into<&S::control, &C::locomotion, &L::maxYawAcceleration>(),
  number("planner.max_position_lead", "0.15", 0.01, 1, "m", "walking: the commanded base position is kept this close to the measured one").into<&S::control, &C::locomotion, &L::maxPositionLead>(),
  number("planner.q_linear_velocity", "40", 0, 1e6, "(m/s)^-2", "Q: centroidal linear momentum / mass against the commanded velocity").into<&S::control, &C::locomotion, &L::weights, &Q::linearVelocity>(),
  number("planner.q_angular_momentum", "1", 0, 1e6, "(m^2/s)^-2", "Q: centroidal angular momentum / mass").into<&S::control, &C::locomotion, &L::weights, &Q::angularMomentum>(),
  numbers("planner.q_base_position", "[200, 200, 800]", 0, 1e6, "m^-2", "Q: base position, [x y z]").ofLength(3).into<&S::control, &C::locomotion, &L::weights, &Q::basePosition>(),
  numbers("planner.q_base_orientation", "[300, 800, 800]", 0, 1e6, "rad^-2", "Q: base orientation, [yaw pitch roll]").ofLength(3).into<&S::control, &C::locomotion, &L::weights, &Q::baseOrientation>(),
  number("planner.q_leg_joints", "5", 0, 1e6, "rad^-2", "Q: joint positions against the nominal posture, joints other than wbc.joint_space_joints").into<&S::control, &C::locomotion, &L::weights, &Q::legJoint>(),
  number("planner.q_arm_joints", "5", 0, 1e6, "rad^-2", "Q: joint positions against the nominal posture, wbc.joint_space_joints (the arms)").into<&S::control, &C::locomotion, &L::weights, &Q::armJoint>(),
  number("planner.r_forces", "0.001", 0, 1e6, "N^-2", "R: contact forces against the weight shared by the stance points").into<&S::control, &C::locomotion, &L::weights, &Q::force>(),
  // Kept small: every leg joint velocity a walking step needs is penalised, and a crouched
  // posture needs smaller ones, so a large weight buys lower joint speeds with base height (at 10
  // the plan walked 8 cm low on its own model). The plan used to chatter at small weights because
  // explicit Euler let alternating joint velocities steer the base; the discretisation no longer
  // allows that (mpc/kinodynamic_problem.hpp).
  number("planner.r_leg_joint_velocities", "0.5", 0, 1e6, "(rad/s)^-2", "R: joint velocities, joints other than wbc.joint_space_joints (small values let the plan chatter)").into<&S::control, &C::locomotion, &L::weights, &Q::legJointVelocity>(),
  // The arms are the plan's cheapest way to change the base velocity the momentum implies, so
  // the first node also uses them to absorb a measured state that does not quite fit the
  // contacts (a rolling or sliding foot): at 0.5 that turns into arm accelerations of hundreds of
  // rad/s² at lift-off. 1 keeps the arm swing (the momentum balance of the legs) and damps that;
  // ≥ 2 nearly freezes the arms at 0.5 m/s.
  number("planner.r_arm_joint_velocities", "1", 0, 1e6, "(rad/s)^-2", "R: joint velocities, wbc.joint_space_joints (larger values freeze the arm swing)").into<&S::control, &C::locomotion, &L::weights, &Q::armJointVelocity>(),
  number("planner.terminal_weight_scale", "5", 0, 1e6, "", "Q at the last node = this times Q").into<&S::control, &C::locomotion, &L::problem, &P::terminalWeightScale>(),
  numbers("planner.friction_barrier", "[0.1, 5]", 1e-9, 1e6, "", "relaxed log barrier of the friction cone and normal force bounds, [weight (paper: xi), delta in N]").ofLength(2).into<&S::control, &C::locomotion, &L::problem, &P::frictionBarrier>(&toBarrier),
  numbers("planner.limit_barrier", "[0.1, 0.02]", 1e-9, 1e6, "", "relaxed log barrier of the joint position and velocity limits, [weight, delta in rad or rad/s]").ofLength(2).into<&S::control, &C::locomotion, &L::problem, &P::limitBarrier>(&toBarrier),
  numbers("planner.joint_limit_stop", "[10, 0.02, 0.15]", 0, 1e6, "", "relaxed log barrier on the joint position limits (within planner.joint_limit_margin) that acts only within reach of them and is zero, with zero slope, farther away: [weight, delta in rad, reach in rad]; 0 weight: none").ofLength(3).into<&S::control, &C::locomotion, &L::problem, &P::jointStop>(&toReachingBarrier),
  R{"planner.joint_limit_stop", [](const S& s) -> std::string {
      const mpc::RelaxedBarrier& b = s.control.locomotion.problem.jointStop;
      // The barrier's log turns quadratic at delta: 0 divides by zero at the margin.
      return b.weight > 0.0 && !(b.delta > 0.0) ? "delta (the second number) must be positive when the weight is" : "";
    }},
  number("planner.friction_coefficient", "0.6", 0.05, 2, "", "friction cone coefficient").into<&S::control, &C::locomotion, &L::problem, &P::frictionCoefficient>(),
  number("planner.min_normal_force", "0", 0, 1e4, "N", "lower bound of a stance contact's normal force").into<&S::control, &C::locomotion, &L::problem, &P::minNormalForce>(),
  number("planner.max_normal_force", "1000", 1, 1e5, "N", "upper bound of a contact's normal force").into<&S::control, &C::locomotion, &L::problem, &P::maxNormalForce>(),
  R{"planner.min_normal_force", [](const S& s) -> std::string {
      const mpc::ProblemSettings& p = s.control.locomotion.problem;
      return p.minNormalForce >= p.maxNormalForce ? "must be below planner.max_normal_force" : "";
    }},
  number("planner.sole_width", "0", 0, 1, "m", "width across each sole over which its centre of pressure moves: the MPC's feet resist a roll about their toe-heel line up to half this times their normal force (mpc/kinodynamic_problem.hpp); 0: line feet, as the paper's four contact points").into<&S::control, &C::locomotion, &L::problem, &P::soleWidth>(),
  number("planner.joint_limit_margin", "0.05", 0, 0.5, "rad", "kept from each URDF joint limit").into<&S::control, &C::locomotion, &L::problem, &P::jointLimitMargin>(),
  number("planner.swing_position_gain", "20", 0, 1e3, "1/s", "swing contact points: velocity = reference velocity + this gain times the position error").into<&S::control, &C::locomotion, &L::problem, &P::swingPositionGain>(),

  // ---- wbc: the whole-body controller (daemon/wbc; wbc/settings.hpp)
  choice("wbc.variant", "hierarchical", "hierarchical|weighted|inverse_dynamics", "strict priorities (the paper's cH), one weighted QP (cNH), or that QP holding the limbs at the plan's joint positions without its limb velocities and accelerations (cI's inverse dynamics; with planner.model single_rigid_body, whose plans have no limb motion, the same as weighted; with the kino-dynamic planner, an ablation)").into<&S::control, &C::wbc, &W::variant>(),
  text("wbc.base_frame", "pelvis", "URDF link whose pose and twist the base task tracks; on the floating base").into<&S::control, &C::wbc, &W::baseFrame>(),
  strings("wbc.joint_space_joints", "[arms]", "joints tracked in joint space at priority 2 (the legs follow their feet): URDF joints or joint group names").into<&S::joints, &J::joint_space>(),
  number("wbc.swing_kp", "400", 0, 1e5, "1/s^2", "priority 2: swing contact point tracking stiffness (world frame)").into<&S::control, &C::wbc, &W::swingKp>(),
  number("wbc.swing_kd", "40", 0, 1e4, "1/s", "priority 2: swing contact point tracking damping").into<&S::control, &C::wbc, &W::swingKd>(),
  flag("wbc.level_swing_feet", "true", "priority 2: a swinging foot is held level about the line through its contact points (with wbc.swing_kp/kd), which their paths leave free, so that it lands flat").into<&S::control, &C::wbc, &W::levelSwingFeet>(),
  flag("wbc.joint_limits", "false", "priority 1: every joint's acceleration keeps it within its URDF position limits (wbc.joint_kp (limit - q) - wbc.joint_kd q' bounds it on each side): a limb target beyond a joint's range is missed at the limit instead of driving the joint into its stop").into<&S::control, &C::wbc, &W::jointLimits>(),
  number("wbc.joint_kp", "400", 0, 1e5, "1/s^2", "priority 2: joint-space tracking stiffness").into<&S::control, &C::wbc, &W::jointKp>(),
  number("wbc.joint_kd", "40", 0, 1e4, "1/s", "priority 2: joint-space tracking damping").into<&S::control, &C::wbc, &W::jointKd>(),
  numbers("wbc.base_kp", "[400, 400, 400, 400, 400, 400]", 0, 1e5, "1/s^2", "priority 3: base tracking stiffness, [x y z position; x y z orientation] (world)").ofLength(6).into<&S::control, &C::wbc, &W::baseKp>(),
  numbers("wbc.base_kd", "[40, 40, 40, 40, 40, 40]", 0, 1e4, "1/s", "priority 3: base tracking damping, [x y z linear; x y z angular] (world)").ofLength(6).into<&S::control, &C::wbc, &W::baseKd>(),
  flag("wbc.push_base_first", "true", "priority 3 above priority 2 while the plan steps out a push (the capture point's footholds: gait.recovery_walking_force walking, a standing recovery; hierarchical variant): a push's long, quick swing then falls short of its path instead of taking its acceleration from the base through the stance leg, which launched the robot; false: the paper's order always").into<&S::control, &C::wbc, &W::pushBaseFirst>(),
  number("wbc.friction_coefficient", "0.6", 0.01, 10, "", "priority 1: friction pyramid coefficient").into<&S::control, &C::wbc, &W::frictionCoefficient>(),
  number("wbc.torque_limit_scale", "1", 0.1, 1, "", "priority 1: fraction of the URDF effort limits the controller may command").into<&S::joints, &J::torque_limit_scale>(),
  number("wbc.limb_weight", "100", 0, 1e9, "", "weighted and inverse_dynamics variants: weight of the limb tasks").into<&S::control, &C::wbc, &W::limbWeight>(),
  number("wbc.base_weight", "10", 0, 1e9, "", "weighted and inverse_dynamics variants: weight of the base task").into<&S::control, &C::wbc, &W::baseWeight>(),
  number("wbc.contact_force_weight", "0.001", 0, 1e9, "", "weighted and inverse_dynamics variants: weight of the contact-force task").into<&S::control, &C::wbc, &W::contactForceWeight>(),
  number("wbc.regularization", "1e-8", 1e-15, 0.01, "", "added to the diagonal of every level's Hessian (scaled units)").into<&S::control, &C::wbc, &W::regularization>(),
  integer("wbc.max_qp_iterations", "200", 1, 100000, "", "active-set iterations per QP before it gives up").into<&S::control, &C::wbc, &W::maxQpIterations>(),
  number("wbc.motor_kp", "20", 0, 5000, "N·m/rad", "stand and walk under the whole-body controller: the motors' PD stiffness around its joint targets (its torques do the work)").into<&S::control, &C::wbc_motor_kp>(),
  number("wbc.motor_kd", "2", 0, 500, "N·m·s/rad", "the motors' PD damping under the whole-body controller").into<&S::control, &C::wbc_motor_kd>(),

  // ---- estimator (daemon/estimation)
  choice("estimator.source", "estimate", "estimate|truth", "what the controllers run on: the estimate, or the simulator's ground truth (diagnostics)").needsRestart().into<&S::control, &C::use_truth>(),
  number("estimator.gyro_noise_density", "0.00024", 1e-7, 1, "rad/s/√Hz", "gyro white noise").into<&S::control, &C::estimator, &E::gyroNoiseDensity>(),
  number("estimator.gyro_bias_random_walk", "1e-05", 0, 1, "rad/s/√s", "how fast the gyro bias may wander").into<&S::control, &C::estimator, &E::gyroBiasRandomWalk>(),
  number("estimator.gyro_bias_initial", "0.01", 0, 1, "rad/s", "σ of the gyro bias before any measurement").into<&S::control, &C::estimator, &E::gyroBiasInitial>(),
  number("estimator.orientation_noise", "0.005", 1e-6, 0.5, "rad", "σ of the IMU's orientation output per sample").into<&S::control, &C::estimator, &E::orientationNoise>(),
  number("estimator.accelerometer_noise_density", "0.02", 1e-6, 100, "m/s²/√Hz", "accelerometer white noise plus unmodelled accelerations (bias, vibration)").into<&S::control, &C::estimator, &E::accelerometerNoiseDensity>(),
  number("estimator.kinematics_position_noise", "0.003", 1e-6, 1, "m", "σ of a contact point's position relative to the base from the joint encoders").into<&S::control, &C::estimator, &E::kinematicsPositionNoise>(),
  // Not the encoders' noise alone: a stance foot rolls and creeps under load, most when a push
  // loads it sideways. At 0.05 the filter followed that creep and its velocity error during a
  // 40 N push rose from 4 to 23 mm/s RMS (162 mm/s peak) and the walk sometimes fell where on
  // ground truth it never did; at 0.2 the IMU carries the velocity over it (6 mm/s RMS, 19 mm/s
  // peak).
  number("estimator.kinematics_velocity_noise", "0.2", 1e-6, 10, "m/s", "σ of a contact point's velocity relative to the base from the joint encoders").into<&S::control, &C::estimator, &E::kinematicsVelocityNoise>(),
  number("estimator.kinematics_velocity_gate", "5", 0, 100, "σ", "a stance point whose leg velocity is further from the prediction is slipping: swing for that tick (0: off)").into<&S::control, &C::estimator, &E::kinematicsVelocityGate>(),
  number("estimator.foot_height_noise", "0.005", 1e-6, 1, "m", "σ of a stance contact point's height above the terrain").into<&S::control, &C::estimator, &E::footHeightNoise>(),
  number("estimator.contact_drift_noise", "0.002", 1e-6, 1, "m/√s", "how fast a stance contact point may slip").into<&S::control, &C::estimator, &E::contactDriftNoise>(),
  number("estimator.swing_noise_scale", "10000", 1, 1e9, "", "variance multiplier for contact points in swing").into<&S::control, &C::estimator, &E::swingNoiseScale>(),
  number("estimator.initial_position_noise", "0.01", 1e-6, 100, "m", "σ of the base position at start").into<&S::control, &C::estimator, &E::initialPositionNoise>(),
  number("estimator.initial_velocity_noise", "0.1", 1e-6, 100, "m/s", "σ of the base velocity at start").into<&S::control, &C::estimator, &E::initialVelocityNoise>(),
  number("estimator.contact_force_threshold", "30", 0, 1e4, "N", "estimated normal force on the foot (all its contact points) that confirms a scheduled contact").into<&S::control, &C::estimator, &E::contactForceThreshold>(),
  number("estimator.contact_force_release", "0.5", 0, 1, "", "fraction of the threshold below which a confirmed contact is released").into<&S::control, &C::estimator, &E::contactForceRelease>(),
  number("estimator.contact_force_release_time", "0.05", 0, 1, "s", "a confirmed contact the plan has in stance is released only after its force has stayed under the release level this long (a landing's bounce is not a lift-off); in swing, at once").into<&S::control, &C::estimator, &E::contactForceReleaseTime>(),
  number("estimator.contact_force_bandwidth", "50", 0.1, 1e4, "1/s", "gain of the momentum observer that estimates the contact forces").into<&S::control, &C::estimator, &E::contactForceBandwidth>(),
  number("estimator.contact_force_regularization", "0.0003", 1e-9, 1, "m²", "λ of each foot's least squares of the contact forces: a joint torque error of ε N·m reads as at most ε/(2√λ) N of force; what λ leaves out of a nearly straight leg's load (most of it, against 1 % with the knee bent 0.8 rad) is taken from the vertical momentum balance").into<&S::control, &C::estimator, &E::contactForceRegularization>(),
  number("estimator.external_force_bandwidth", "10", 0.1, 1e4, "1/s", "gain of the momentum observer that estimates the external force (a push): its time constant is the inverse").into<&S::control, &C::estimator, &E::externalForceBandwidth>(),
  number("estimator.external_force_deadband", "0.16", 0.0, 10, "N/kg", "a horizontal external force (a push) estimated under this times the robot's mass (9.9 N on the 62 kg humanoid) reads as none; larger ones less that. Per kilogram: the model's errors it hides grow with the robot").into<&S::control, &C::estimator, &E::externalForceDeadbandPerKg>(),
  flag("estimator.position_fix", "true", "fuse the backend's position fixes (a localisation source: lidar against the map, motion capture) into the base position, when it has them").into<&S::control, &C::use_position_fix>(),
  flag("estimator.contact_force_check", "true", "a scheduled contact counts only once the estimated normal force confirms it (estimator.contact_force_threshold)").into<&S::control, &C::estimator, &E::contactForceCheck>(),

  // ---- terrain
  path("terrain.map", "", "OctoMap file (.bt or .ot) of the terrain for the planner; the simulation builds its world from it at start (a profile switch changes the planner's map only); empty: a flat floor").into<&S::terrain_map>(),
  number("terrain.ground_height", "0", -100, 100, "m", "height of the floor under the robot at start").into<&S::control, &C::ground_height>(),
  number("terrain.map_tolerance", "0.03", 0, 1, "m", "the terrain map agrees with the robot when the ground it has under each stance contact point is within this plus one of its cells of the point; a map that does not (a wrong map loaded, seeded, or scanned under the feet) is a warning in the status and the log, and until it agrees again the planner plans on the plane the feet stood on and gives the estimator those heights, so that a wrong map never lifts the estimated base; 0: never checked").into<&S::control, &C::map_tolerance>(),
  number("terrain.clearance", "0.5", 0.05, 5, "m", "ground is what a foot can stand on: occupied cells whose bottom is more than this above the stance feet (a ceiling, a table top) are not ground").needsRestart().into<&S::mapping, &MS::map, &LM::rule, &terrain::GroundRule::clearance>(),

  // ---- mapping: the live map from the robot's lidar
  flag("mapping.enabled", "true", "insert the backend's lidar scans into the terrain map (when it has a lidar), placed by the estimated pose; off: the map is only what `map load` gives").needsRestart().into<&S::mapping, &MS::enabled>(),
  number("mapping.resolution", "0.04", 0.01, 0.5, "m", "cell size of the live map (a map loaded or seeded from a file keeps its own)").needsRestart().into<&S::mapping, &MS::map, &LM::resolution>(),
  number("mapping.max_range", "6", 0.2, 100, "m", "lidar hits farther than this from the sensor are not inserted").needsRestart().into<&S::mapping, &MS::map, &LM::maxRange>(),
  number("mapping.clear_distance", "1", 0, 100, "m", "the last part of each ray, before its hit, that is cleared (free space); whole rays cost far more").needsRestart().into<&S::mapping, &MS::map, &LM::clearDistance>(),
  number("mapping.rate", "10", 0.1, 100, "Hz", "at most this many scans inserted per second (the others are skipped)").needsRestart().into<&S::mapping, &MS::rate>(),
  number("mapping.latency", "0.05", 0.001, 1, "s", "lockstep: controller time from a scan to the planner having its map (the loop waits for the mapping thread then); real time takes maps as they come").needsRestart().into<&S::mapping, &MS::latency>(),
  number("mapping.prob_hit", "0.7", 0.501, 0.999, "", "OctoMap sensor model: probability that a cell a ray ends in is occupied").needsRestart().into<&S::mapping, &MS::map, &LM::probHit>(),
  number("mapping.prob_miss", "0.4", 0.001, 0.499, "", "OctoMap sensor model: probability that a cell a ray crosses is occupied").needsRestart().into<&S::mapping, &MS::map, &LM::probMiss>(),
  number("mapping.clamp_min", "0.12", 0.001, 0.999, "", "OctoMap clamping: lowest occupancy probability a cell keeps (a map that keeps up with a changing world)").needsRestart().into<&S::mapping, &MS::map, &LM::clampMin>(),
  number("mapping.clamp_max", "0.97", 0.001, 0.999, "", "OctoMap clamping: highest occupancy probability a cell keeps").needsRestart().into<&S::mapping, &MS::map, &LM::clampMax>(),
  R{"mapping.clamp_min", [](const S& s) -> std::string {
      return s.mapping.map.clampMin >= s.mapping.map.clampMax ? "must be below mapping.clamp_max" : "";
    }},
  R{"mapping.latency", [](const S& s) -> std::string {
      return s.mapping.latency > 0.75 / s.mapping.rate ? "is longer than the time between two scans inserted (0.75 / mapping.rate)" : "";
    }},

  // ---- safety
  number("safety.max_tilt", "0.8", 0.05, 3.14, "rad", "fall: the base tilts beyond this").into<&S::control, &C::max_tilt>(),
  number("safety.min_base_height", "0.45", 0, 5, "m", "fall: the base is lower than this above terrain.ground_height").into<&S::control, &C::min_base_height>(),
  flag("safety.fall_on_non_foot_contact", "true", "fall: a body other than the feet touches the ground (simulation ground truth)").into<&S::control, &C::fall_on_non_foot_contact>(),
  number("safety.damping", "4", 0, 500, "N·m·s/rad", "joint damping in damp mode").into<&S::control, &C::damping>(),
  number("safety.command_ttl", "10", 0.01, 3600, "s", "a walk command without a ttl lasts this long (controller time)").into<&S::control, &C::command_ttl>(),
  number("safety.max_command_ttl", "600", 0.01, 86400, "s", "longest ttl a walk command may ask for").into<&S::control, &C::max_command_ttl>(),
  R{"safety.command_ttl", [](const S& s) -> std::string {
      return s.control.command_ttl > s.control.max_command_ttl ? "is larger than safety.max_command_ttl" : "";
    }},
  number("safety.max_vx", "1.5", 0, 5, "m/s", "largest forward/backward velocity command").into<&S::control, &C::max_vx>(),
  number("safety.max_vy", "0.5", 0, 5, "m/s", "largest sideways velocity command").into<&S::control, &C::max_vy>(),
  number("safety.max_yaw_rate", "1", 0, 10, "rad/s", "largest turning rate command").into<&S::control, &C::max_yaw_rate>(),
  number("safety.min_pose_height", "0.7", 0, 5, "m", "lowest standing height `pose` may ask for").into<&S::control, &C::min_pose_height>(),
  number("safety.max_pose_height", "0.95", 0, 5, "m", "highest standing height `pose` may ask for").into<&S::control, &C::max_pose_height>(),
  R{"safety.min_pose_height", [](const S& s) -> std::string {
      return s.control.min_pose_height >= s.control.max_pose_height ? "must be below safety.max_pose_height" : "";
    }},
  number("safety.max_pose_tilt", "0.35", 0, 1.5, "rad", "largest standing roll or pitch `pose` may ask for").into<&S::control, &C::max_pose_tilt>(),
  number("safety.max_pose_yaw", "0.35", 0, 1.5, "rad", "largest standing yaw `pose` may ask for").into<&S::control, &C::max_pose_yaw>(),
  number("safety.max_plan_age", "0.2", 0.01, 1, "s", "while no new plan comes (a failed solve, a late planner) the loop tracks the plan in force, said in the log at half this age; stand or walk on a plan older than this is a fault (damp). The humanoid in simulation walked through 350 ms without plans at 1.0 m/s on flat ground and 200 ms at 0.5 m/s on rough ground (one fall in 14 at 250 ms there)").into<&S::control, &C::max_plan_age>(),
  R{"safety.max_plan_age", [](const S& s) -> std::string {
      return s.control.max_plan_age >= s.planner_horizon ? "must be shorter than planner.horizon: a plan covers no more" : "";
    }},
  number("safety.max_command_gap", "0.01", 0.002, 1, "s", "real time: the motors going longer than this without a command (on the backend clock: the wall for hardware, the world for a simulation) is a fault (damp); a late tick alone is not").into<&S::control, &C::max_command_gap>(),
  number("safety.max_late_fraction", "0.2", 0, 1, "", "real time: more than this fraction of the last second's ticks late (their predecessor ran past the deadline) is a fault (damp)").into<&S::control, &C::max_late_fraction>(),
  number("safety.max_push_force", "300", 0, 1e4, "N", "largest push (simulation)").into<&S::control, &C::max_push_force>(),
  number("safety.max_push_duration", "5", 0, 60, "s", "longest push (simulation)").into<&S::control, &C::max_push_duration>(),

  // ---- telemetry
  integer("telemetry.decimation", "1", 1, 1000, "", "record every Nth control tick").into<&S::control, &C::telemetry_decimation>(),
  integer("telemetry.ring_frames", "4096", 64, 1048576, "", "frames buffered between the loop and the writer thread").needsRestart().into<&S::telemetry_ring_frames>(),
  path("telemetry.record_on_start", "", "record from the start into this file (empty: only on `ballast record start`)").needsRestart().into<&S::record_on_start>(),

  // ---- server: socket, clients, lease
  path("server.socket", "", "socket path; empty: $XDG_RUNTIME_DIR/ballast/ballastd.sock").needsRestart().into<&S::server, &SV::socket_path>(),
  integers("server.allowed_uids", "[]", 0, 4294967295.0, "uids allowed to connect besides the daemon's own").into<&S::server, &SV::allowed_uids>(),
  number("server.lease_timeout", "300", 0, 86400, "s", "a lease unused this long (wall time) lapses; 0: never").into<&S::server, &SV::lease_timeout>(),
  integer("server.max_message_bytes", "65536", 256, 16777216, "bytes", "longest request line").into<&S::server, &SV::max_message_bytes>(),
  integer("server.max_clients", "32", 1, 1024, "", "most clients connected at once").into<&S::server, &SV::max_clients>(),
  number("server.max_watch_rate", "100", 1, 1000, "Hz", "fastest status stream `watch` may ask for").into<&S::server, &SV::max_watch_rate>(),
  number("server.reply_timeout", "2", 0.1, 60, "s", "wall time a request waits for the control loop before a timeout error").into<&S::server, &SV::reply_timeout>(),

  // ---- fields derived from a key: problems about them are reported at it
  alias<&S::control, &C::contact_frames>("robot.contact_frames"),
  alias<&S::control, &C::imu_frame>("robot.imu_frame"),
  alias<&S::control, &C::estimator, &E::imuFrame>("robot.imu_frame"),
  alias<&S::control, &C::estimator, &E::contactFrames>("robot.contact_frames"),
  alias<&S::control, &C::estimator, &E::period>("control.rate"),
  alias<&S::control, &C::wbc, &W::contactFrames>("robot.contact_frames"),
  alias<&S::control, &C::wbc, &W::jointSpaceJoints>("wbc.joint_space_joints"),
  alias<&S::control, &C::wbc, &W::torqueLimit>("wbc.torque_limit_scale"),
  alias<&S::control, &C::wbc, &W::period>("control.rate"),
  alias<&S::control, &C::locomotion, &L::contactFrames>("robot.contact_frames"),
  alias<&S::control, &C::locomotion, &L::problem, &P::minFeetDistance>("gait.min_foot_distance"),
  alias<&S::control, &C::locomotion, &L::sqp, &SQ::nodes>("planner.horizon"),
  alias<&S::control, &C::kp>("control.joint_kp"),
  alias<&S::control, &C::kd>("control.joint_kd"),
  alias<&S::control, &C::nominal_q>("robot.nominal_posture"),
}, "; ballast-profile(5) lists every key");
// clang-format on

}  // namespace

const Schema<Settings>& table() { return kTable; }

const std::vector<Row<Settings>>& schema() { return kTable.rows(); }

const Key* findKey(const std::string& name) { return kTable.find(name); }

bool isSection(const std::string& name) { return kTable.isGroup(name); }

bool isBackendSection(const std::string& name) {
  const std::string prefix = Key{backendKey()}.section() + ".";
  if (name.rfind(prefix, 0) != 0 || findKey(name)) return false;
  const std::string rest = name.substr(prefix.size());
  return !rest.empty() && rest.find('.') == std::string::npos;
}

std::string closestKey(const std::string& name) { return kTable.closestKey(name); }

const char* extendsKey() { return kTable.keyOf<&S::extends>(); }
const char* backendKey() { return kTable.keyOf<&S::backend, &B::name>(); }
const char* urdfKey() { return kTable.keyOf<&S::urdf>(); }

std::string schemaManPage(const std::vector<BackendSectionDoc>& backends) {
  std::string sections;
  for (const BackendSectionDoc& b : backends) sections += b.text;
  return R"(.\" Generated by `ballastd --dump-schema=man` from daemon/profile/schema.cpp: edit the
.\" schema, then regenerate this file (a test compares them).
.TH BALLAST-PROFILE 5 "" "ballast" "File formats"
.SH NAME
ballast-profile \- ballastd profiles: robot, backend, gait, planner, controller, estimator, safety
.SH SYNOPSIS
.B ballastd \-\-profile
.I FILE.yaml
.SH DESCRIPTION
A profile is a YAML map of sections. Every key is declared in one schema (listed below with
its type, default, bounds and meaning). A key that is not in the schema, a value of the wrong
type and a value out of bounds are errors reported as
.IP
.I file:line:column: key: what is wrong
.PP
and
.BR ballastd (8)
refuses to start; at run time
.RB ( "ballast profile use" ,
SIGHUP) the running profile stays in force.
.PP
.B extends:
names a base profile, a file relative to this one or a profile name looked up beside it and
in the profile directories. The base is loaded first, then this file on top of it: maps merge
key by key, scalars and lists replace. Paths are relative to the file that sets them. Angles
(unit rad) also take degrees with a
.B deg
suffix, e.g.
.BR "left_knee: 35deg" .
.PP
The backend's own keys live in a map named after the backend,
.BR backend.simbody ,
.BR backend.mujoco ,
.BR backend.socketcan ;
ballastd passes that map, as YAML text with its file and line, to the plugin, which checks
it. A backend section other than the one of
.B backend.name
is an error in the file that names the backend, and ignored when inherited.
.PP
Keys marked
.I restart
cannot change on a running daemon: a profile switch that changes one is refused.
.SH KEYS
)" + manEntries(kTable.keys()) +
         R"(.TP
.B backend.<name>
(section; restart)
the backend's own keys, those of the plugin backend.name loads: below, for the plugins built
with this ballastd
)" + sections + R"(.SH BRINGING UP A NEW ROBOT
.B ballastd \-\-describe\-robot
.I robot.urdf
prints a starter profile for the robot (contact points from the feet's collision geometry,
joint groups from the tree, a standing posture), its description in comments above it: a first
step, to check and edit. By hand: a vendor's URDF is used as it comes; the profile says what it
lacks. Extend a shipped profile,
set
.B robot.urdf
and list every movable joint in
.BR robot.joint_groups ,
with gains per group. The contact points (toe and heel of each foot), the IMU and the
simulation's lidar need no links of their own: each takes a link and a place on it,
.IP
.nf
robot:
  contact_frames:
    \- {link: left_ankle_roll_link, offset: [0.12, 0, \-0.04]}
    \- {link: left_ankle_roll_link, offset: [\-0.05, 0, \-0.04]}
    \- {link: right_ankle_roll_link, offset: [0.12, 0, \-0.04]}
    \- {link: right_ankle_roll_link, offset: [\-0.05, 0, \-0.04]}
  imu_frame: {link: pelvis, offset: [0, 0, 0.05], rpy: [0, 0, 0]}
.fi
.PP
(metres and radians in that link's frame; a contact point has no
.BR rpy ).
The simulations put their IMU at
.B robot.imu_frame
too, unless their own
.B imu.frame
places it elsewhere (a mounting error to simulate).
In the controller's model such a frame is named after its role and link, e.g.
.BR left_toe@left_ankle_roll_link ,
the name status and telemetry show. A foot whose URDF has no collision box (meshes, or spheres
of millimetres) touches the simulated ground at these points; ballastd says at start which
contact the simulation built. Then
.IP
.B ballastd \-\-check \-\-profile
.I my\-robot.yaml
.PP
checks everything a start checks, the backend's own section included (through its plugin,
starting nothing): a name the URDF lacks is reported at its place in the profile with the
closest link names.
.PP
Joints the controller should not move (a waist, a head, a wrist) are fixed at an angle by
.BR "robot.locked_joints: {joint: angle}" :
they are merged into their parent body in the controller's model and welded in the simulation,
and they belong to no joint group. ballast controls at most 32 joints; a URDF with more is
refused until enough of them are locked. On hardware a locked joint's motor, if
.B backend.socketcan.motors
lists one, holds it at its angle with the motor's own PD
.RB ( hold_kp ,
.BR hold_kd ,
no feed\-forward), in every mode: damped, the robot keeps the joint rigid as its model and the
simulation have it; only a fault that motor reports turns its hold into damping. A locked joint
without a motor entry is left unpowered.
.PP
The URDF is read as vendors write it: CRLF line endings, mesh geometry, and
.BR <gazebo> ,
.B <transmission>
and
.B <mujoco>
elements are ignored. Two kinds of joint are locked by the URDF itself and said at start (and by
.BR \-\-check ),
one line each, "robot: joint NAME held at ANGLE: why": a mimic joint (no actuator of its own:
held where its leader's locked angle, else zero, puts it) and a joint that moves no inertia (a
link without
.B <inertial>
or of zero mass, and all below it: a camera, a sensor; held at zero). A massless link that
carries moving links (two hip joints meeting in a point) is a body of zero inertia. Inertias that
no rigid body has (negative mass, not positive semi\-definite, principal moments against the
triangle inequality) are refused, naming the link and line.
.SH FILES
.TP
.I profiles/sim\-flat.yaml
the default: Simbody simulation, flat floor
.TP
.I profiles/sim\-stage.yaml, profiles/sim\-rough.yaml
simulation with a stage to step onto, and on rough ground
.TP
.I profiles/sim\-flat\-mujoco.yaml, profiles/sim\-stage\-mujoco.yaml, profiles/sim\-rough\-mujoco.yaml
sim\-flat, sim\-stage and sim\-rough on the MuJoCo simulation: only the backend differs
.TP
.I profiles/hardware\-example.yaml
a SocketCAN robot: a template to adapt
.PP
Installed profiles are in
.IR <prefix>/share/ballast/profiles .
.SH EXAMPLE
.nf
extends: sim\-flat
description: softer arms
control:
  joint_kp: {arms: 60}
robot:
  nominal_posture: {left_elbow: \-20deg, right_elbow: \-20deg}
.fi
.SH SEE ALSO
.BR ballastd (8),
.BR ballast (1)
)";
}

std::string schemaYaml(const std::vector<BackendSectionDoc>& backends) {
  std::string y = "# Every profile key with its default (ballastd --dump-schema=yaml).\n" +
                  yamlDefaults(kTable.keys());
  for (const BackendSectionDoc& b : backends)
    y += "\n# The " + b.name + " backend's section (backend.name: " + b.name + "):\n" + b.text;
  return y;
}

}  // namespace ballast::profile
