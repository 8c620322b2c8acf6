// Balance with heavy limbs (issue 4 §3): the humanoid stands on flat ground in the Simbody
// backend under the whole-body controller alone while both arms swing ±60° at the shoulder
// (pitch) at 1 Hz, out of phase, for 10 s. The base reference is the initial pose, held; the
// force reference is m·g shared equally by the four contact points. The swing amplitude rises
// from 0 to ±60° over the first second (a C² quintic envelope): a sinusoid switched on at full
// amplitude asks for a 6.3 rad/s velocity step, a start no real arm makes. Errors are measured
// over all 10 s.
//
// The controller runs on the simulator's ground-truth base state (Sensors::truth) and the exact
// encoders: the state estimator is a later issue. The backend is loaded as ballastd loads it
// (backend::Plugin, lockstep at 1 kHz) and used only through plugins/backend_abi.hpp.
//
// Motor commands: τ_ff = the controller's torque, plus the motors' own PD (continuous, inside the
// simulated motor driver) with modest gains (kp 20 N·m/rad, kd 2 N·m·s/rad; legged_control sends
// kd 3) around the controller's targets, the mean of its predicted motion over the coming tick.
// The PD acts within the tick, where the controller cannot (the torque is held while the state
// moves), which is what makes it worth having on hardware. The second test runs pure torque
// (kp = kd = 0) to the same bar: the balance is the controller's torques, not the PD.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "backend/plugin_loader.hpp"
#include "control/walking_controller.hpp"
#include "model/algorithms.hpp"
#include "test/integration/simulation_support.hpp"
#include "test/unit/settings_support.hpp"
#include "wbc/whole_body_controller.hpp"

namespace ballast::test {
namespace {

using backend::Status;
using namespace wbc;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kRamp = 1.0;  // s, amplitude envelope

const model::Model& humanoid() {
  static const model::Model m = model::loadUrdfFile(std::string(BALLAST_SOURCE_DIR) + "/urdf/humanoid.urdf");
  return m;
}

struct BalanceFigures {
  bool fell = false;
  double fallTime = -1.0;
  double basePositionRms = 0.0;    // m
  double basePositionMax = 0.0;    // m
  double baseOrientationRms = 0.0; // rad
  double baseOrientationMax = 0.0; // rad
  double swingShoulderRms = 0.0;   // rad, the two swinging shoulder pitch joints
  double armJointRms = 0.0;        // rad, all twelve arm joints
  int relaxedTicks = 0, failedTicks = 0;
  std::string summary(const char* name) const {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: fell %s, base position error RMS %.2f mm (max %.2f mm), base orientation "
                  "error RMS %.3f deg (max %.3f deg), swinging shoulders RMS %.3f deg, all arm "
                  "joints RMS %.3f deg, relaxed ticks %d, failed ticks %d",
                  name, fell ? "yes" : "no", 1e3 * basePositionRms, 1e3 * basePositionMax,
                  baseOrientationRms / kDeg, baseOrientationMax / kDeg, swingShoulderRms / kDeg,
                  armJointRms / kDeg, relaxedTicks, failedTicks);
    return buf;
  }
};

/// Runs the experiment; motorKp/motorKd are the motors' PD gains on every joint (0: pure torque).
BalanceFigures balanceRun(WbcVariant variant, double seconds, double motorKp, double motorKd) {
  const model::Model& m = humanoid();
  static const std::shared_ptr<backend::Plugin> plugin = backend::Plugin::load("simbody");
  backend::BackendPtr sim = test::startHumanoidSimulation(*plugin, "lidar: {enabled: false}\n",
                                                          "balance_test:1", 4);
  const backend::Capabilities& caps = sim->capabilities();
  EXPECT_TRUE(caps.ground_truth);

  // Backend joint k <-> model joint modelJoint[k].
  const std::vector<int> modelJoint = test::modelJointOfBackendJoint(m, caps);
  EXPECT_EQ(caps.num_joints, m.nj());

  WbcSettings settings = wbcSettings();
  settings.variant = variant;
  settings.period = 0.001;  // the simulation's tick (startHumanoidSimulation)
  WholeBodyController wbc(m, settings);
  WbcState state = wbc.makeState();
  WbcReference ref = wbc.makeReference();
  WbcOutput out = wbc.makeOutput();
  for (int i = 0; i < 4; ++i) ref.contactForce[3 * i + 2] = m.totalMass() * 9.81 / 4;

  const int leftShoulder = m.jointId("left_shoulder_pitch");
  const int rightShoulder = m.jointId("right_shoulder_pitch");
  std::vector<int> armJoints;
  for (const auto& name : settings.jointSpaceJoints) armJoints.push_back(m.jointId(name));
  const double amplitude = 60.0 * kDeg, omega = 2.0 * kPi * 1.0;

  backend::Sensors s;
  backend::Commands cmd;
  cmd.num_joints = caps.num_joints;
  BalanceFigures fig;
  double sumPos = 0, sumRot = 0, sumShoulder = 0, sumArm = 0;
  const int ticks = static_cast<int>(std::lround(seconds / settings.period));
  EXPECT_EQ(sim->read(s), Status::kOk);
  Eigen::Vector3d basePosition0(s.truth.base_position);
  Eigen::Quaterniond baseOrientation0(s.truth.base_orientation[3], s.truth.base_orientation[0],
                                      s.truth.base_orientation[1], s.truth.base_orientation[2]);
  for (int k = 0; k < s.num_joints; ++k) ref.jointPosition[modelJoint[k]] = s.q[k];
  ref.basePosition = basePosition0;
  ref.baseOrientation = baseOrientation0;

  for (int tick = 0; tick < ticks; ++tick) {
    // State from ground truth: base velocities into the base frame (model.hpp).
    const Eigen::Quaterniond quat(s.truth.base_orientation[3], s.truth.base_orientation[0],
                                  s.truth.base_orientation[1], s.truth.base_orientation[2]);
    const Eigen::Matrix3d R = quat.normalized().toRotationMatrix();
    state.q.head<3>() = Eigen::Vector3d(s.truth.base_position);
    state.q.segment<4>(3) << quat.x(), quat.y(), quat.z(), quat.w();
    state.v.head<3>() = R.transpose() * Eigen::Vector3d(s.truth.base_linear_velocity);
    state.v.segment<3>(3) = R.transpose() * Eigen::Vector3d(s.truth.base_angular_velocity);
    for (int k = 0; k < s.num_joints; ++k) {
      state.q[model::Model::qIndexOfJoint(modelJoint[k])] = s.q[k];
      state.v[model::Model::vIndexOfJoint(modelJoint[k])] = s.dq[k];
    }
    // Arm references: shoulder pitch ±60° at 1 Hz, out of phase; other arm joints held.
    const double t = s.time;
    // Envelope e(t) = 10τ³ − 15τ⁴ + 6τ⁵, τ = t / ramp, and its derivatives.
    const double tau = std::min(t / kRamp, 1.0);
    const double e = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
    const double de = 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau) / kRamp;
    const double dde = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) / (kRamp * kRamp);
    const double sn = std::sin(omega * t), cs = std::cos(omega * t);
    for (auto [j, sign] : {std::pair{leftShoulder, 1.0}, std::pair{rightShoulder, -1.0}}) {
      ref.jointPosition[j] = sign * amplitude * e * sn;
      ref.jointVelocity[j] = sign * amplitude * (de * sn + e * omega * cs);
      ref.jointAcceleration[j] =
          sign * amplitude * (dde * sn + 2.0 * de * omega * cs - e * omega * omega * sn);
    }
    // Errors of this sample against the references.
    const double posErr = (state.q.head<3>() - basePosition0).norm();
    const double rotErr = Eigen::AngleAxisd(baseOrientation0.toRotationMatrix() * R.transpose()).angle();
    sumPos += posErr * posErr;
    sumRot += rotErr * rotErr;
    fig.basePositionMax = std::max(fig.basePositionMax, posErr);
    fig.baseOrientationMax = std::max(fig.baseOrientationMax, rotErr);
    for (int j : {leftShoulder, rightShoulder}) {
      const double e = state.q[model::Model::qIndexOfJoint(j)] - ref.jointPosition[j];
      sumShoulder += e * e;
    }
    for (int j : armJoints) {
      const double e = state.q[model::Model::qIndexOfJoint(j)] - ref.jointPosition[j];
      sumArm += e * e;
    }
    if (posErr > 0.2 || rotErr > 30 * kDeg || s.truth.non_foot_contact) {
      fig.fell = true;
      fig.fallTime = t;
      break;
    }

    const WbcStatus status = wbc.update(state, ref, out);
    fig.relaxedTicks += status == WbcStatus::kRelaxed;
    fig.failedTicks += status == WbcStatus::kDegraded || status == WbcStatus::kInvalidInput;
    cmd.time = t;
    for (int k = 0; k < caps.num_joints; ++k) {
      cmd.joint[k] = control::motorCommand(out, modelJoint[k], motorKp, motorKd);
    }
    EXPECT_EQ(sim->write(cmd), Status::kOk);
    const Status advanced = sim->advance();
    EXPECT_EQ(advanced, Status::kOk) << sim->lastError().message;
    if (advanced != Status::kOk) break;
    EXPECT_EQ(sim->read(s), Status::kOk);
  }
  const int samples = std::max(1, ticks);
  fig.basePositionRms = std::sqrt(sumPos / samples);
  fig.baseOrientationRms = std::sqrt(sumRot / samples);
  fig.swingShoulderRms = std::sqrt(sumShoulder / (2.0 * samples));
  fig.armJointRms = std::sqrt(sumArm / (static_cast<double>(armJoints.size()) * samples));
  sim->stop();
  return fig;
}

constexpr double kMotorKp = 20.0;  // N·m/rad
constexpr double kMotorKd = 2.0;   // N·m·s/rad

void expectIssueBar(const BalanceFigures& fig) {
  EXPECT_FALSE(fig.fell) << "fell at t = " << fig.fallTime << " s";
  EXPECT_LE(fig.basePositionRms, 0.01);
  EXPECT_LE(fig.baseOrientationMax, 2.0 * kDeg);
  EXPECT_LE(fig.swingShoulderRms, 2.0 * kDeg);
  EXPECT_LE(fig.armJointRms, 2.0 * kDeg);
  EXPECT_EQ(fig.failedTicks, 0);
}

TEST(WbcBalance, HierarchicalKeepsTheBaseStillWhileTheHeavyArmsSwing) {
  const BalanceFigures fig = balanceRun(WbcVariant::kHierarchical, 10.0, kMotorKp, kMotorKd);
  std::printf("%s\n", fig.summary("hierarchical (cH), torque + PD").c_str());
  RecordProperty("summary", fig.summary("cH, torque + PD"));
  expectIssueBar(fig);
}

TEST(WbcBalance, HierarchicalUnderPureTorque) {
  const BalanceFigures fig = balanceRun(WbcVariant::kHierarchical, 10.0, 0.0, 0.0);
  std::printf("%s\n", fig.summary("hierarchical (cH), pure torque").c_str());
  RecordProperty("summary", fig.summary("cH, pure torque"));
  expectIssueBar(fig);
}

TEST(WbcBalance, WeightedVariantOnTheSameMotion) {
  // The paper's cNH for comparison: its figures are reported, not held to cH's bar; it must
  // still stand.
  const BalanceFigures fig = balanceRun(WbcVariant::kWeighted, 10.0, kMotorKp, kMotorKd);
  std::printf("%s\n", fig.summary("weighted (cNH), torque + PD").c_str());
  RecordProperty("summary", fig.summary("cNH, torque + PD"));
  EXPECT_FALSE(fig.fell) << "fell at t = " << fig.fallTime << " s";
  EXPECT_EQ(fig.failedTicks, 0);
}

}  // namespace
}  // namespace ballast::test
