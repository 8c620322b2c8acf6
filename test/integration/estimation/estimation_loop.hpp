// The estimator in a closed loop with the Simbody backend (lockstep, 1 kHz) and the whole-body
// controller: what every closed-loop estimation test shares, so that a new scenario (the
// balance test here; the 20 s walk of issue 7 when the daemon walks) only writes its references.
//
// Per tick:
//     loop.sense();            // backend read -> estimator update -> score against the truth
//     ... the test sets loop.reference (and input().scheduledStance from its contact plan) ...
//     loop.act();              // WBC on the estimate (or the truth) -> write -> advance
//
// The backend is loaded as ballastd loads it (backend::Plugin) and used only through
// plugins/backend_abi.hpp. Sensors are realistic (kRealisticSensors): IMU white noise and a
// per-axis gyro and accelerometer bias, a noisy orientation output, 14-bit joint encoders,
// joint velocity and torque noise. The estimator gets the readings in model joint order, the
// controller gets the estimate (Options::controlOnTruth for a comparison on ground truth).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "backend/plugin_loader.hpp"
#include "control/walking_controller.hpp"
#include "estimation/state_estimator.hpp"
#include "model/algorithms.hpp"
#include "test/integration/simulation_support.hpp"
#include "test/unit/settings_support.hpp"
#include "wbc/whole_body_controller.hpp"

namespace ballast::test {

/// The simbody backend's sensor keys for a realistic robot: a BMI088-class IMU (gyro 2.4e-4
/// rad/s/√Hz with a 5 mrad/s bias, accelerometer 1.5e-3 m/s²/√Hz with a 0.03 m/s² bias, an
/// orientation output with 5 mrad of noise), 14-bit joint encoders, 0.02 rad/s of joint velocity
/// noise and 0.5 N·m of torque noise.
inline constexpr const char* kRealisticSensors =
    "encoder_resolution: 3.835e-4\n"
    "joint_velocity_noise: 0.02\n"
    "torque_noise: 0.5\n"
    "imu:\n"
    "  gyro_noise_density: 2.4e-4\n"
    "  gyro_bias: 0.005\n"
    "  accel_noise_density: 1.5e-3\n"
    "  accel_bias: 0.03\n"
    "  orientation_noise: 0.005\n"
    "lidar: {enabled: false}\n";

inline const model::Model& loopModel() {
  static const model::Model m =
      model::loadUrdfFile(std::string(BALLAST_SOURCE_DIR) + "/urdf/humanoid.urdf");
  return m;
}

/// Estimate against ground truth, accumulated tick by tick from `settle` s on (the attitude
/// filter starts from one raw IMU orientation sample, σ = 5 mrad per axis, and needs a few
/// tens of samples to average it down).
struct EstimationScore {
  double settle = 0.1;      // s
  int samples = 0;
  double distance = 0;       // m, horizontal path length of the true base
  double drift = 0;          // m, horizontal position error at the last sample
  double driftMax = 0;       // m
  double velocityRms = 0;    // m/s, of the 3-D base velocity error
  double heightMax = 0;      // m, |z error|
  double tiltMax = 0;        // rad, max |roll|, |pitch| of the orientation error
  double yaw = 0;            // rad, yaw error at the last sample
  double contactAgreement = 0;  // fraction of (tick, point) where stance == truth contact
  /// m: how far a contact point moved in the world while the simulator had it in contact (from
  /// touch-down, or from the start): slip and pivoting, which leg odometry cannot see.
  double footSlipMax = 0;
  double sumV2 = 0;
  int agree = 0;
  Eigen::Vector3d lastTruth = Eigen::Vector3d::Zero();
  std::array<Eigen::Vector3d, estimation::kContactPoints> anchor{};
  std::array<bool, estimation::kContactPoints> anchored{};

  /// truthContact: the contact points' true positions (world).
  void add(double t, const estimation::EstimatorOutput& e, const backend::Truth& truth,
           const std::array<Eigen::Vector3d, estimation::kContactPoints>& truthContact) {
    for (int c = 0; c < estimation::kContactPoints; ++c) {
      if (!truth.contact[c]) {
        anchored[c] = false;
      } else if (!anchored[c]) {
        anchor[c] = truthContact[c];
        anchored[c] = true;
      } else {
        footSlipMax = std::max(footSlipMax, (truthContact[c] - anchor[c]).head<2>().norm());
      }
    }
    if (t < settle) return;
    const Eigen::Vector3d p(truth.base_position), v(truth.base_linear_velocity);
    const Eigen::Quaterniond qt(truth.base_orientation[3], truth.base_orientation[0],
                                truth.base_orientation[1], truth.base_orientation[2]);
    if (samples > 0) distance += (p - lastTruth).head<2>().norm();
    lastTruth = p;
    const Eigen::Vector3d ep = e.basePosition - p;
    drift = ep.head<2>().norm();
    driftMax = std::max(driftMax, drift);
    heightMax = std::max(heightMax, std::abs(ep.z()));
    sumV2 += (e.baseLinearVelocity - v).squaredNorm();
    const Eigen::Vector3d tilt =
        model::rpyFromRotation(qt.normalized().toRotationMatrix().transpose() * e.baseRotation);
    tiltMax = std::max({tiltMax, std::abs(tilt.x()), std::abs(tilt.y())});
    yaw = tilt.z();
    for (int c = 0; c < estimation::kContactPoints; ++c) agree += e.stance[c] == truth.contact[c];
    ++samples;
    velocityRms = std::sqrt(sumV2 / samples);
    contactAgreement = static_cast<double>(agree) / (samples * estimation::kContactPoints);
  }

  std::string summary(const char* name) const {
    char buf[700];
    std::snprintf(buf, sizeof buf,
                  "%s: %d ticks, base moved %.3f m; horizontal drift %.2f mm (max %.2f mm), "
                  "velocity error RMS %.1f mm/s, height error max %.2f mm, roll/pitch error max "
                  "%.3f deg, yaw error %.3f deg, stance agrees with the simulator's contacts "
                  "%.1f %%; the feet slipped or pivoted up to %.1f mm while in contact",
                  name, samples, distance, 1e3 * drift, 1e3 * driftMax, 1e3 * velocityRms,
                  1e3 * heightMax, tiltMax * 180 / M_PI, yaw * 180 / M_PI, 100 * contactAgreement,
                  1e3 * footSlipMax);
    return buf;
  }
};

class EstimationLoop {
 public:
  struct Options {
    std::string simYaml = kRealisticSensors;
    std::uint64_t seed = 7;
    bool controlOnTruth = false;  // the controller runs on the estimate unless this is set
    estimation::EstimatorSettings estimator = estimatorSettings();
    wbc::WbcSettings controller = wbcSettings();
    double motorKp = 20.0, motorKd = 2.0;  // the motors' own PD around the WBC's targets
  };

  explicit EstimationLoop(const Options& options)
      : options_(options),
        m_(loopModel()),
        estimator_(m_, options.estimator),
        wbc_(m_, [&] {
          wbc::WbcSettings s = options.controller;
          s.period = 0.001;
          return s;
        }()) {
    static const std::shared_ptr<backend::Plugin> plugin = backend::Plugin::load("simbody");
    plugin_ = plugin;
    try {
      sim_ = test::startHumanoidSimulation(*plugin, options_.simYaml, "estimation_loop:1",
                                           options.seed);
      ok_ = true;
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
      return;
    }
    modelJoint_ = test::modelJointOfBackendJoint(m_, sim_->capabilities());
    input_ = estimator_.makeInput();
    state_ = wbc_.makeState();
    reference = wbc_.makeReference();
    out_ = wbc_.makeOutput();
    commands_.num_joints = sim_->capabilities().num_joints;
  }
  ~EstimationLoop() {
    if (sim_) sim_->stop();
  }

  /// Reads the backend, runs the estimator, scores it. False when the backend failed.
  bool sense() {
    if (!ok_) return false;
    const backend::Status st = sim_->read(sensors_);
    EXPECT_EQ(st, backend::Status::kOk) << sim_->lastError().message;
    if (st != backend::Status::kOk) return ok_ = false;
    if (first_) estimator_.reset(sensors_.truth.base_position[0], sensors_.truth.base_position[1]);
    first_ = false;
    input_.time = sensors_.time;
    for (int k = 0; k < sensors_.num_joints; ++k) {
      const int j = modelJoint_[k];
      input_.q[j] = sensors_.q[k];
      input_.dq[j] = sensors_.dq[k];
      input_.tau[j] = sensors_.tau[k];
    }
    const backend::Imu& imu = sensors_.imu;
    input_.imu.orientation = Eigen::Quaterniond(imu.orientation[3], imu.orientation[0],
                                                imu.orientation[1], imu.orientation[2]);
    input_.imu.angularVelocity = Eigen::Vector3d(imu.angular_velocity);
    input_.imu.linearAcceleration = Eigen::Vector3d(imu.linear_acceleration);
    input_.imu.valid = sensors_.imu_valid;
    status_ = estimator_.update(input_, estimate_);
    EXPECT_TRUE(status_ == estimation::EstimatorStatus::kOk ||
                status_ == estimation::EstimatorStatus::kNoStance)
        << "t = " << sensors_.time << ": " << estimation::toString(status_);
    // The contact points' true positions: the simulator's base pose and the encoders.
    const backend::Truth& tr = sensors_.truth;
    truthQ_.head<3>() = Eigen::Vector3d(tr.base_position);
    truthQ_.segment<4>(3) = Eigen::Vector4d(tr.base_orientation).normalized();
    truthQ_.tail(m_.nj()) = input_.q;
    model::forwardKinematics(m_, truthData_, truthQ_);
    std::array<Eigen::Vector3d, estimation::kContactPoints> truthContact;
    for (int c = 0; c < estimation::kContactPoints; ++c)
      truthContact[c] = model::framePlacement(m_, truthData_, m_.frameId(test::kContactFrames[c])).p;
    score.add(sensors_.time, estimate_, tr, truthContact);
    // The controller's state: the estimate (base) and the encoders (joints), or ground truth.
    if (options_.controlOnTruth) {
      const Eigen::Quaterniond q(tr.base_orientation[3], tr.base_orientation[0],
                                 tr.base_orientation[1], tr.base_orientation[2]);
      const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
      state_.q.head<3>() = Eigen::Vector3d(tr.base_position);
      state_.q.segment<4>(3) = q.normalized().coeffs();
      state_.q.tail(m_.nj()) = input_.q;
      state_.v.head<3>() = R.transpose() * Eigen::Vector3d(tr.base_linear_velocity);
      state_.v.segment<3>(3) = R.transpose() * Eigen::Vector3d(tr.base_angular_velocity);
      state_.v.tail(m_.nj()) = input_.dq;
    } else {
      estimation::modelState(estimate_, input_.q, input_.dq, state_.q, state_.v);
    }
    return true;
  }

  /// The WBC on `reference`, the commands to the motors, one lockstep tick.
  bool act() {
    if (!ok_) return false;
    const wbc::WbcStatus status = wbc_.update(state_, reference, out_);
    failedTicks += status == wbc::WbcStatus::kDegraded || status == wbc::WbcStatus::kInvalidInput;
    commands_.time = sensors_.time;
    for (int k = 0; k < commands_.num_joints; ++k) {
      commands_.joint[k] =
          control::motorCommand(out_, modelJoint_[k], options_.motorKp, options_.motorKd);
    }
    EXPECT_EQ(sim_->write(commands_), backend::Status::kOk);
    const backend::Status advanced = sim_->advance();
    EXPECT_EQ(advanced, backend::Status::kOk) << sim_->lastError().message;
    return ok_ = advanced == backend::Status::kOk;
  }

  /// A push on the base (world force, N, for `duration` s).
  void push(double fx, double fy, double duration) {
    backend::Push p;
    p.force[0] = fx;
    p.force[1] = fy;
    p.duration = duration;
    backend::Error error;
    EXPECT_TRUE(sim_->push(p, error)) << error.message;
  }

  /// Fallen: the base far below its start, tilted over, or a body other than a foot on the ground.
  bool fallen(double startHeight) const {
    const backend::Truth& tr = sensors_.truth;
    const Eigen::Quaterniond q(tr.base_orientation[3], tr.base_orientation[0],
                               tr.base_orientation[1], tr.base_orientation[2]);
    const double tilt = std::acos(std::clamp(q.normalized().toRotationMatrix()(2, 2), -1.0, 1.0));
    return tr.non_foot_contact || tr.base_position[2] < startHeight - 0.2 || tilt > 0.5;
  }

  const model::Model& model() const { return m_; }
  const backend::Sensors& sensors() const { return sensors_; }
  const estimation::EstimatorOutput& estimate() const { return estimate_; }
  estimation::EstimatorInput& input() { return input_; }  // scheduledStance, terrainHeight
  const wbc::WbcState& state() const { return state_; }
  const wbc::WholeBodyController& controller() const { return wbc_; }

  wbc::WbcReference reference;
  EstimationScore score;
  int failedTicks = 0;

 private:

  Options options_;
  const model::Model& m_;
  estimation::StateEstimator estimator_;
  wbc::WholeBodyController wbc_;
  std::shared_ptr<backend::Plugin> plugin_;
  backend::BackendPtr sim_;
  std::vector<int> modelJoint_;
  bool ok_ = false, first_ = true;
  backend::Sensors sensors_;
  backend::Commands commands_;
  estimation::EstimatorInput input_;
  estimation::EstimatorOutput estimate_;
  estimation::EstimatorStatus status_ = estimation::EstimatorStatus::kOk;
  wbc::WbcState state_;
  wbc::WbcOutput out_;
  model::Data<double> truthData_{loopModel()};
  Eigen::VectorXd truthQ_ = Eigen::VectorXd::Zero(loopModel().nq);
};

}  // namespace ballast::test
