#include "control/loop_estimator.hpp"

#include "model/base_conventions.hpp"

namespace ballast::control {

void fillRpy(BaseState& base) {
  const model::Vec3<double> rpy =
      model::rpyFromRotation(model::quaternionToRotation<double>(base.orientation));
  for (int i = 0; i < 3; ++i) base.rpy[i] = rpy[i];
}

void baseStateFromTruth(const backend::Truth& truth, BaseState& base) {
  for (int i = 0; i < 3; ++i) {
    base.position[i] = truth.base_position[i];
    base.linear_velocity[i] = truth.base_linear_velocity[i];
    base.angular_velocity[i] = truth.base_angular_velocity[i];
  }
  for (int i = 0; i < 4; ++i) base.orientation[i] = truth.base_orientation[i];
  fillRpy(base);
}

LoopEstimator::LoopEstimator(const model::Model& model, const ControlSettings& settings)
    : model_(model),
      settings_(&settings),
      filter_(model, settings.estimator),
      input_(filter_.makeInput()) {}

bool LoopEstimator::setSettings(const ControlSettings& settings) {
  settings_ = &settings;
  return filter_.setSettings(settings.estimator);
}

bool LoopEstimator::update(const backend::Sensors& sensors, const double* q, const double* dq,
                           const double* tau, const std::array<bool, kNumContacts>& scheduled,
                           const std::array<double, kNumContacts>& terrain, EstimatedState& out) {
  const int nj = model_.nj();
  out.t = sensors.time;
  out.num_joints = nj;
  for (int j = 0; j < nj; ++j) {
    out.q[j] = input_.q[j] = q[j];
    out.dq[j] = input_.dq[j] = dq[j];
    out.tau[j] = input_.tau[j] = tau[j];
  }
  input_.time = sensors.time;
  const backend::Imu& imu = sensors.imu;
  input_.imu.valid = sensors.imu_valid;
  input_.imu.orientation =
      Eigen::Quaterniond(imu.orientation[3], imu.orientation[0], imu.orientation[1], imu.orientation[2]);
  input_.imu.angularVelocity = Eigen::Vector3d(imu.angular_velocity);
  input_.imu.linearAcceleration = Eigen::Vector3d(imu.linear_acceleration);
  for (int c = 0; c < kNumContacts; ++c) {
    input_.scheduledStance[c] = scheduled[c];
    input_.terrainHeight[c] = terrain[c];
  }
  status_ = filter_.update(input_, output_);

  for (int i = 0; i < 3; ++i) out.external_force[i] = output_.valid ? output_.externalForce[i] : 0.0;
  BaseState& b = out.base;
  if (settings_->use_truth && sensors.has_truth) {
    const backend::Truth& tr = sensors.truth;
    baseStateFromTruth(tr, b);
    for (int c = 0; c < kNumContacts; ++c) {
      out.contact[c] = tr.contact[c];
      for (int i = 0; i < 3; ++i) out.contact_position[c][i] = output_.contactPosition[c][i];
    }
    return true;
  }
  if (!output_.valid) return false;
  for (int i = 0; i < 3; ++i) {
    b.position[i] = output_.basePosition[i];
    b.linear_velocity[i] = output_.baseLinearVelocity[i];
    b.angular_velocity[i] = output_.baseAngularVelocity[i];
    b.rpy[i] = output_.rpy[i];
  }
  const Eigen::Vector4d& xyzw = output_.baseOrientation.coeffs();
  for (int i = 0; i < 4; ++i) b.orientation[i] = xyzw[i];
  for (int c = 0; c < kNumContacts; ++c) {
    out.contact[c] = output_.stance[c];
    for (int i = 0; i < 3; ++i) out.contact_position[c][i] = output_.contactPosition[c][i];
  }
  return true;
}

bool LoopEstimator::correctPosition(const backend::PositionFix& fix) {
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (!(fix.stddev[i] > 0.0)) return false;
    covariance(i, i) = fix.stddev[i] * fix.stddev[i];
  }
  return filter_.correctPosition(Eigen::Vector3d(fix.position), covariance);
}

}  // namespace ballast::control
