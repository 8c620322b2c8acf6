#include "estimation/state_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "model/base_conventions.hpp"
#include "model/crba.hpp"
#include "model/frames.hpp"
#include "model/rnea.hpp"

namespace ballast::estimation {

using Eigen::Matrix3d;
using Eigen::Vector3d;

const char* toString(EstimatorStatus status) {
  switch (status) {
    case EstimatorStatus::kOk: return "ok";
    case EstimatorStatus::kNoStance: return "no_stance";
    case EstimatorStatus::kImuInvalid: return "imu_invalid";
    case EstimatorStatus::kWaitingForImu: return "waiting_for_imu";
    case EstimatorStatus::kInvalidInput: return "invalid_input";
  }
  return "unknown";
}

namespace {
std::array<int, kContactPoints> contactFrames(const model::Model& model, const EstimatorSettings& s) {
  if (const model::SettingsProblem problem = validateSettings(s, model))
    throw std::invalid_argument(problem.message);
  std::array<int, kContactPoints> frames{};
  for (int c = 0; c < kContactPoints; ++c) frames[c] = model.frameId(s.contactFrames[c]);
  return frames;
}

bool finite(const Eigen::VectorXd& x) { return x.allFinite(); }
}  // namespace

StateEstimator::StateEstimator(const model::Model& model, const EstimatorSettings& settings)
    : model_(model),
      settings_(settings),
      contactFrame_(contactFrames(model, settings)),
      observer_(model, contactFrame_),
      data_(model),
      q_(Eigen::VectorXd::Zero(model.nq)),
      v_(Eigen::VectorXd::Zero(model.nv)) {
  const model::Frame& imu = model.frames[model.frameId(settings.imuFrame)];
  imuRotationInBase_ = imu.placement.R;
  imuPositionInBase_ = imu.placement.p;
  q_[6] = 1.0;
}

EstimatorInput StateEstimator::makeInput() const {
  EstimatorInput in;
  in.q = Eigen::VectorXd::Zero(model_.nj());
  in.dq = Eigen::VectorXd::Zero(model_.nj());
  in.tau = Eigen::VectorXd::Zero(model_.nj());
  return in;
}

bool StateEstimator::setSettings(const EstimatorSettings& settings) {
  if (settings.imuFrame != settings_.imuFrame || settings.contactFrames != settings_.contactFrames)
    return false;
  settings_ = settings;  // equal strings: assigning them allocates nothing
  return true;
}

void StateEstimator::reset(double x, double y) {
  resetPosition_ = Vector3d(x, y, 0.0);
  started_ = false;
  attitude_ = AttitudeFilter();
  observer_.reset();
  external_.reset();
  confirmed_.fill(false);
  stance_.fill(false);
  unloaded_.fill(0.0);
}

AttitudeFilter::Noise StateEstimator::attitudeNoise() const {
  AttitudeFilter::Noise n;
  n.gyroNoiseDensity = settings_.gyroNoiseDensity;
  n.gyroBiasRandomWalk = settings_.gyroBiasRandomWalk;
  n.gyroBiasInitial = settings_.gyroBiasInitial;
  n.orientationNoise = settings_.orientationNoise;
  return n;
}

bool StateEstimator::inputValid(const EstimatorInput& in) const {
  const int nj = model_.nj();
  if (in.q.size() != nj || in.dq.size() != nj || in.tau.size() != nj) return false;
  if (!std::isfinite(in.time) || !finite(in.q) || !finite(in.dq) || !finite(in.tau)) return false;
  for (double h : in.terrainHeight)
    if (!std::isfinite(h)) return false;
  if (in.imu.valid &&
      !(in.imu.orientation.coeffs().allFinite() && in.imu.orientation.norm() > 0.5 &&
        in.imu.angularVelocity.allFinite() && in.imu.linearAcceleration.allFinite()))
    return false;
  return true;
}

void StateEstimator::initialiseFilter(const EstimatorInput& in) {
  // The base height that puts the lowest scheduled contact point on its terrain: those higher
  // are lifted (h_i − d_i,z < p_z for them), so p_z is the largest h_i − d_i,z.
  const bool anyScheduled =
      std::any_of(in.scheduledStance.begin(), in.scheduledStance.end(), [](bool b) { return b; });
  double z = -1e300;
  for (int c = 0; c < kContactPoints; ++c)
    if (in.scheduledStance[c] || !anyScheduled) z = std::max(z, in.terrainHeight[c] - d_[c].z());
  const Vector3d leverArm = data_.oMi[0].R * imuPositionInBase_;

  BaseKalmanFilter::Vector x = BaseKalmanFilter::Vector::Zero();
  BaseKalmanFilter::Vector variance = BaseKalmanFilter::Vector::Zero();
  x.segment<3>(BaseKalmanFilter::kPosition) = Vector3d(resetPosition_.x(), resetPosition_.y(), z);
  // z put the contact points relative to the IMU's point on the ground: d_ is relative to it.
  x.segment<3>(BaseKalmanFilter::kPosition).head<2>() += leverArm.head<2>();
  variance.segment<3>(BaseKalmanFilter::kPosition).setConstant(
      settings_.initialPositionNoise * settings_.initialPositionNoise);
  variance.segment<3>(BaseKalmanFilter::kVelocity).setConstant(
      settings_.initialVelocityNoise * settings_.initialVelocityNoise);
  filter_.reset(x, variance);
  const double r = settings_.kinematicsPositionNoise * settings_.kinematicsPositionNoise;
  for (int c = 0; c < kContactPoints; ++c) filter_.anchorContact(c, d_[c], r);
  started_ = true;
}

EstimatorStatus StateEstimator::update(const EstimatorInput& in, EstimatorOutput& out) {
  const EstimatorSettings& s = settings_;
  if (!inputValid(in)) return EstimatorStatus::kInvalidInput;
  double dt = in.time - lastTime_;
  if (!started_ || !(dt > 0.0) || dt > 10.0 * s.period) dt = s.period;
  lastTime_ = in.time;

  // 1. Orientation and angular velocity from the IMU.
  const AttitudeFilter::Noise noise = attitudeNoise();
  const bool imu = in.imu.valid;
  if (imu) {
    const Matrix3d measured = in.imu.orientation.normalized().toRotationMatrix();
    if (!attitude_.initialised()) {
      attitude_.reset(measured, noise);
    } else {
      attitude_.predict(in.imu.angularVelocity, dt, noise);
      attitude_.correct(measured, noise);
    }
  }
  if (!attitude_.initialised()) {
    out.valid = false;
    out.time = in.time;
    return EstimatorStatus::kWaitingForImu;
  }
  const Matrix3d& Rwi = attitude_.orientation();
  const Matrix3d Rwb = Rwi * imuRotationInBase_.transpose();
  const Vector3d omega = imu ? Vector3d(Rwi * (in.imu.angularVelocity - attitude_.gyroBias()))
                             : Vector3d::Zero();
  const Vector3d acceleration =
      imu ? Vector3d(Rwi * in.imu.linearAcceleration + model_.gravity) : Vector3d::Zero();
  const Vector3d leverArm = Rwb * imuPositionInBase_;  // IMU point from the base origin, world

  // 2. Leg kinematics, M and n: base at the origin with the estimated orientation and the
  //    velocity the IMU predicts (n depends on it; translation does not matter).
  const Vector3d imuVelocity =
      started_ ? Vector3d(filter_.velocity() + acceleration * dt) : Vector3d::Zero();
  const Vector3d baseVelocity = imuVelocity - omega.cross(leverArm);
  const Eigen::Quaterniond quat(Rwb);
  q_.head<3>().setZero();
  q_.segment<4>(3) << quat.x(), quat.y(), quat.z(), quat.w();
  q_.tail(model_.nj()) = in.q;
  v_.head<3>() = Rwb.transpose() * baseVelocity;
  v_.segment<3>(3) = Rwb.transpose() * omega;
  v_.tail(model_.nj()) = in.dq;
  model::crba(model_, data_, q_);
  model::nonLinearEffects(model_, data_, q_, v_);  // leaves data_.oMi and data_.v for the frames
  const Vector3d leverArmVelocity = omega.cross(leverArm);
  for (int c = 0; c < kContactPoints; ++c) {
    const Vector3d p = model::framePlacement(model_, data_, contactFrame_[c]).p;
    const Vector3d pdot = model::frameVelocity(model_, data_, contactFrame_[c]).linear - baseVelocity;
    d_[c] = p - leverArm;
    dDot_[c] = pdot - leverArmVelocity;
  }
  if (!started_) initialiseFilter(in);

  // 3. Contact: the schedule, confirmed by the estimated normal force on the point's foot.
  observer_.update(data_, v_, in.q, in.tau, dt, s.contactForceBandwidth,
                   s.contactForceRegularization);
  const double mass = model_.totalMass();  // kg
  {
    // The robot's linear momentum: (M v)[0:3] is it in base axes.
    Vector3d forces = Vector3d::Zero();
    for (int c = 0; c < kContactPoints; ++c) forces += observer_.force(c);
    const Vector3d momentum = Rwb * (data_.M.topRows<3>() * v_);
    // The unsensed load of the feet in stance as of the last tick (this tick's decision reads
    // these forces).
    external_.update(momentum, forces, mass * model_.gravity, dt, s.externalForceBandwidth,
                     s.contactForceBandwidth, observer_.unsensedLoad(stance_));
  }
  // A landed foot that the plan keeps in stance is not dropped by a transient: after a step
  // down the landing bounces and the leg stretches, the estimated force flickers under the
  // release level for tens of ms while the foot carries the robot, and a point counted out of
  // stance there leaves the filter to the IMU alone. Only low force held for
  // contactForceReleaseTime (or the plan's swing) releases it.
  bool anyStance = false;
  for (int c = 0; c < kContactPoints; ++c) {
    const double fz = observer_.footForce(c).z();
    if (!confirmed_[c]) {
      confirmed_[c] = fz >= s.contactForceThreshold;
      unloaded_[c] = 0.0;
    } else if (fz >= s.contactForceRelease * s.contactForceThreshold) {
      unloaded_[c] = 0.0;
    } else {
      unloaded_[c] += dt;
      confirmed_[c] = in.scheduledStance[c] && unloaded_[c] < s.contactForceReleaseTime;
    }
    stance_[c] = in.scheduledStance[c] && (!s.contactForceCheck || confirmed_[c]);
    anyStance = anyStance || stance_[c];
  }

  // 4. Predict with the IMU acceleration.
  std::array<double, kContactPoints> drift{};
  const double swingScale = std::sqrt(s.swingNoiseScale);
  for (int c = 0; c < kContactPoints; ++c)
    drift[c] = s.contactDriftNoise * (stance_[c] ? 1.0 : swingScale);
  filter_.predict(acceleration, dt, s.accelerometerNoiseDensity, drift);

  // 5. Correct from the legs.
  const double rPosition = s.kinematicsPositionNoise * s.kinematicsPositionNoise;
  const double rVelocity = s.kinematicsVelocityNoise * s.kinematicsVelocityNoise;
  const double rHeight = s.footHeightNoise * s.footHeightNoise;
  // Velocity gate: a stance point whose leg velocity disagrees with the prediction by more than
  // kinematicsVelocityGate standard deviations is slipping or lifting: it is treated as swing
  // this tick, unless every stance point disagrees (then the prediction is what is wrong).
  std::array<bool, kContactPoints> slipping{};
  if (s.kinematicsVelocityGate > 0.0) {
    Matrix3d S = filter_.covariance().block<3, 3>(BaseKalmanFilter::kVelocity,
                                                  BaseKalmanFilter::kVelocity);
    S.diagonal().array() += rVelocity;
    const Eigen::LLT<Matrix3d> llt(S);
    int stanceCount = 0, slipCount = 0;
    for (int c = 0; c < kContactPoints; ++c) {
      if (!stance_[c]) continue;
      ++stanceCount;
      const Vector3d y = -dDot_[c] - filter_.velocity();
      slipping[c] = y.dot(llt.solve(y)) > s.kinematicsVelocityGate * s.kinematicsVelocityGate;
      slipCount += slipping[c];
    }
    if (slipCount == stanceCount) slipping.fill(false);
  }
  for (int c = 0; c < kContactPoints; ++c) {
    if (!stance_[c] || slipping[c]) {
      filter_.anchorContact(c, d_[c], rPosition * s.swingNoiseScale);
      continue;
    }
    filter_.updateRelativePosition(c, d_[c], rPosition);
    filter_.updateVelocity(-dDot_[c], rVelocity);
    filter_.updateContactHeight(c, in.terrainHeight[c], rHeight);
  }

  // 6. Output at the base origin.
  out.time = in.time;
  out.valid = true;
  out.baseRotation = Rwb;
  out.baseOrientation = quat;
  out.rpy = model::rpyFromRotation(Rwb);
  out.basePosition = filter_.position() - leverArm;
  out.baseLinearVelocity = filter_.velocity() - leverArmVelocity;
  out.baseAngularVelocity = omega;
  for (int c = 0; c < kContactPoints; ++c) {
    out.contactPosition[c] = filter_.contactPosition(c);
    out.stance[c] = stance_[c] && !slipping[c];
    out.slipping[c] = slipping[c];
    out.contactForce[c] = observer_.force(c);
  }
  out.externalForce = external_.horizontal(s.externalForceDeadbandPerKg * mass);
  out.externalForceRaw = external_.raw();
  out.gyroBias = attitude_.gyroBias();
  out.covarianceDiagonal = filter_.covariance().diagonal();
  out.orientationVariance = attitude_.covariance().diagonal().head<3>();
  if (!imu) return EstimatorStatus::kImuInvalid;
  return anyStance ? EstimatorStatus::kOk : EstimatorStatus::kNoStance;
}

bool StateEstimator::correctPosition(const Vector3d& basePosition, const Matrix3d& covariance) {
  if (!started_ || !basePosition.allFinite() || !covariance.allFinite()) return false;
  if (!covariance.isApprox(covariance.transpose(), 1e-9)) return false;
  const Matrix3d Rwb = attitude_.orientation() * imuRotationInBase_.transpose();
  return filter_.updatePosition(basePosition + Rwb * imuPositionInBase_, covariance);
}

void modelState(const EstimatorOutput& e, const Eigen::VectorXd& qj, const Eigen::VectorXd& dqj,
                Eigen::VectorXd& q, Eigen::VectorXd& v) {
  const int nj = static_cast<int>(qj.size());
  if (q.size() != 7 + nj) q.resize(7 + nj);
  if (v.size() != 6 + nj) v.resize(6 + nj);
  q.head<3>() = e.basePosition;
  q.segment<4>(3) = e.baseOrientation.coeffs();  // Eigen stores (x, y, z, w), as the model does
  q.tail(nj) = qj;
  v.head<3>() = e.baseRotation.transpose() * e.baseLinearVelocity;
  v.segment<3>(3) = e.baseRotation.transpose() * e.baseAngularVelocity;
  v.tail(nj) = dqj;
}

}  // namespace ballast::estimation
