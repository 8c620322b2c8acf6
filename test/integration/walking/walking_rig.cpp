#include "test/integration/walking/walking_rig.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "control/walking_controller.hpp"
#include "model/base_conventions.hpp"
#include "test/integration/simulation_support.hpp"
#include "test/unit/settings_support.hpp"

namespace ballast::test {


locomotion::LocomotionSettings humanoidLocomotionSettings(const model::Model& m) {
  locomotion::LocomotionSettings s = test::controlDefaults().locomotion;
  Eigen::VectorXd q = model::neutralConfiguration(m);
  for (const char* side : {"left_", "right_"}) {
    q[model::Model::qIndexOfJoint(m.jointId(std::string(side) + "hip_pitch"))] = -0.4;
    q[model::Model::qIndexOfJoint(m.jointId(std::string(side) + "knee"))] = 0.8;
    q[model::Model::qIndexOfJoint(m.jointId(std::string(side) + "ankle_pitch"))] = -0.4;
  }
  model::Data<double> d(m);
  model::forwardKinematics(m, d, q);
  double lowest = 1e9;
  for (const char* f : test::kContactFrames)
    lowest = std::min(lowest, model::framePlacement(m, d, m.frameId(f)).p.z());
  s.nominalJoints = q.tail(m.nj());
  s.nominalHeight = -lowest;
  s.armJoint.assign(m.nj(), false);
  for (int j = 0; j < m.nj(); ++j) {
    const std::string& n = m.jointName[j + 1];
    s.armJoint[j] = n.find("shoulder") != std::string::npos ||
                    n.find("elbow") != std::string::npos || n.find("wrist") != std::string::npos;
  }
  return s;
}

WalkingRig::WalkingRig(const WalkingRigOptions& options)
    : options_(options), model_(humanoid()), settings_(humanoidLocomotionSettings(model_)) {
  plugin_ = backend::Plugin::load("simbody");
  sim_ = test::startHumanoidSimulation(*plugin_, options.simSection, "walking_rig:1", options.seed);
  const backend::Capabilities& caps = sim_->capabilities();
  modelJoint_ = test::modelJointOfBackendJoint(model_, caps);
  commands_.num_joints = caps.num_joints;

  planner_ = std::make_unique<locomotion::LocomotionPlanner>(model_, settings_, ground_);
  sampler_ = std::make_unique<locomotion::PlanSampler>(model_,
                                                       locomotion::contactFrameIds(model_, settings_));
  wbc::WbcSettings ws = test::wbcSettings();
  ws.period = 0.001;  // the simulation's tick (startHumanoidSimulation)
  wbc_ = std::make_unique<wbc::WholeBodyController>(model_, ws);
  state_ = wbc_->makeState();
  reference_ = wbc_->makeReference();
  output_ = wbc_->makeOutput();
  q_ = model::neutralConfiguration(model_);
  v_ = Eigen::VectorXd::Zero(model_.nv);
  if (sim_->read(sensors_) != backend::Status::kOk)
    throw std::runtime_error("simbody backend: first read failed");
  readState();
}

WalkingRig::~WalkingRig() { sim_->stop(); }

Eigen::Matrix3d WalkingRig::baseRotation() const {
  const double* o = sensors_.truth.base_orientation;
  return Eigen::Quaterniond(o[3], o[0], o[1], o[2]).normalized().toRotationMatrix();
}

void WalkingRig::readState() {
  const Eigen::Matrix3d R = baseRotation();
  const Eigen::Quaterniond quat(R);
  q_.head<3>() = Eigen::Vector3d(sensors_.truth.base_position);
  q_.segment<4>(3) << quat.x(), quat.y(), quat.z(), quat.w();
  v_.head<3>() = R.transpose() * Eigen::Vector3d(sensors_.truth.base_linear_velocity);
  v_.segment<3>(3) = R.transpose() * Eigen::Vector3d(sensors_.truth.base_angular_velocity);
  for (std::size_t k = 0; k < modelJoint_.size(); ++k) {
    q_[model::Model::qIndexOfJoint(modelJoint_[k])] = sensors_.q[k];
    v_[model::Model::vIndexOfJoint(modelJoint_[k])] = sensors_.dq[k];
  }
}

void WalkingRig::tick(const locomotion::LocomotionCommand& command) {
  const double t = sensors_.time;
  if (t >= nextPlan_ - 1e-9) {
    if (!planner_->update(t, q_, v_, command, plan_)) ++failedPlans_;
    nextPlan_ = t + options_.plannerPeriod;
  }
  constexpr double kLookAhead = 0.005;  // s, the base and joint accelerations' difference step
  sampler_->sample(plan_, t, now_);
  sampler_->sample(plan_, t + kLookAhead, ahead_);
  control::planToWbcReference(now_, ahead_, kLookAhead, model_.nj(), reference_);
  state_.q = q_;
  state_.v = v_;
  const wbc::WbcStatus status = wbc_->update(state_, reference_, output_);
  degraded_ += status == wbc::WbcStatus::kDegraded || status == wbc::WbcStatus::kInvalidInput;
  static const bool trace = std::getenv("BALLAST_RIG_TRACE") != nullptr;
  if (trace && std::lround(t * 1000) % 10 == 0) {
    const Eigen::Matrix3d R = baseRotation();
    const Eigen::Vector3d rpy = model::rpyFromRotation(R);
    const Eigen::Vector3d vb = R * v_.head<3>(), wb = R * v_.segment<3>(3);
    double planFz = 0, wbcFz = 0, simFz = 0, slip = 0;
    model::forwardKinematics(model_, traceData_, q_, v_);
    for (int c = 0; c < 4; ++c) {
      planFz += now_.contactForce[c].z();
      wbcFz += output_.contactForce[3 * c + 2];
      simFz += sensors_.truth.contact_force[c][2];
      if (now_.stance[c])
        slip = std::max(slip, model::frameVelocity(model_, traceData_, model_.frameId(test::kContactFrames[c])).linear.norm());
    }
    std::fprintf(stderr,
                 "t %.3f st %d%d%d%d z %.3f rpy %6.3f %6.3f %6.3f prpy %6.3f %6.3f | v %5.2f %5.2f %5.2f pv %5.2f %5.2f %5.2f "
                 "| w %5.2f %5.2f %5.2f pw %5.2f %5.2f %5.2f | slip %.2f acc %5.1f %5.1f | wbc %s err %.2g %.2g %.2g %.3g "
                 "fz plan %4.0f wbc %4.0f sim %4.0f (%3.0f %3.0f %3.0f %3.0f) sqp %.2f %.2g %.4g\n",
                 t, int(now_.stance[0]), int(now_.stance[1]), int(now_.stance[2]), int(now_.stance[3]),
                 q_[2], rpy[0], rpy[1], rpy[2], now_.baseZyx[2], now_.baseZyx[1], vb.x(), vb.y(), vb.z(),
                 now_.baseLinearVelocity.x(), now_.baseLinearVelocity.y(), now_.baseLinearVelocity.z(),
                 wb.x(), wb.y(), wb.z(), now_.baseAngularVelocity.x(), now_.baseAngularVelocity.y(),
                 now_.baseAngularVelocity.z(), slip, reference_.baseLinearAcceleration.norm(),
                 reference_.baseAngularAcceleration.norm(), wbc::toString(status), output_.taskError[0],
                 output_.taskError[1], output_.taskError[2], output_.taskError[3], planFz, wbcFz, simFz,
                 sensors_.truth.contact_force[0][2], sensors_.truth.contact_force[1][2],
                 sensors_.truth.contact_force[2][2], sensors_.truth.contact_force[3][2],
                 planner_->statistics().step, planner_->statistics().violation,
                 planner_->statistics().cost);
  }
  commands_.time = t;
  for (std::size_t k = 0; k < modelJoint_.size(); ++k) {
    commands_.joint[k] =
        control::motorCommand(output_, modelJoint_[k], options_.motorKp, options_.motorKd);
  }
}

bool WalkingRig::run(const locomotion::LocomotionCommand& command, double seconds) {
  const int ticks = static_cast<int>(std::lround(seconds / 0.001));
  for (int i = 0; i < ticks && !fallen_; ++i) {
    tick(command);
    if (sim_->write(commands_) != backend::Status::kOk || sim_->advance() != backend::Status::kOk ||
        sim_->read(sensors_) != backend::Status::kOk) {
      fallen_ = true;
      why_ = std::string("backend: ") + sim_->lastError().message;
      break;
    }
    readState();
    const double tilt = std::acos(std::clamp(baseRotation()(2, 2), -1.0, 1.0));
    if (sensors_.truth.non_foot_contact || tilt > 0.6 ||
        sensors_.truth.base_position[2] < 0.5 * settings_.nominalHeight) {
      fallen_ = true;
      why_ = "fell at t = " + std::to_string(sensors_.time) + " s (tilt " + std::to_string(tilt) +
             " rad, base height " + std::to_string(sensors_.truth.base_position[2]) + " m)";
    }
  }
  return !fallen_;
}

bool WalkingRig::push(const char* body, const Eigen::Vector3d& force, double duration) {
  backend::Push p;
  for (int i = 0; i < 3; ++i) p.force[i] = force[i];
  p.duration = duration;
  std::snprintf(p.body, sizeof(p.body), "%s", body);
  backend::Error e;
  return sim_->push(p, e);
}

}  // namespace ballast::test
