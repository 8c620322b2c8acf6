// A synthetic walk of the humanoid and the sensor readings it would produce: the reference
// motion for the estimator's trajectory test and benchmark.
//
// Motion (all smooth, a function of time only):
//   - stands for `standStill` s, then walks forward; the speed rises to `speed` over 1 s (quintic);
//   - steps of `stepPeriod` s: double support for the first `doubleSupport` s, then one foot
//     swings (left first) from where it is to where the base will be at the middle of the next
//     step, along a minimum-jerk path with a `stepHeight` arc; feet stay flat;
//   - the base sways sideways over the stance foot (±2 cm), bobs (±1 cm), rolls, pitches and
//     yaws by a few degrees; the arms swing ±0.5 rad at the shoulders;
//   - the legs follow from inverse kinematics of each foot's pose (Newton on the 6 x 6 foot
//     Jacobian, to 1e-12), so stance feet do not move in the world.
// Velocities come from central differences of the configuration (h = 1e-6 s).
//
// Sensors, as the Simbody backend models them (plugins/simbody/sensor_model.hpp): the IMU's
// specific force is the mean acceleration of its point over the last tick (the backend
// differences velocities), plus a per-axis bias and white noise; the gyro is the angular velocity
// in the IMU frame plus bias and white noise; the orientation has a small random rotation; joint
// positions are quantised, joint velocities noisy.
#pragma once

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "estimation/state_estimator.hpp"
#include "model/algorithms.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {

struct SensorNoise {
  double encoderResolution = 2.0 * M_PI / 16384;  // 14-bit
  double jointVelocityNoise = 0.02;               // rad/s
  double gyroNoiseDensity = 2.4e-4;               // rad/s/√Hz
  double gyroBias = 0.005;                        // rad/s, σ of the per-axis bias
  double accelNoiseDensity = 1.5e-3;              // m/s²/√Hz
  double accelBias = 0.03;                        // m/s², σ of the per-axis bias
  double orientationNoise = 0.005;                // rad
};

class SyntheticWalk {
 public:
  double standStill = 0.5, speed = 0.4, stepPeriod = 0.5, doubleSupport = 0.1, stepHeight = 0.06;
  double period = 0.001;

  explicit SyntheticWalk(const model::Model& m) : m_(m), data_(m) {
    q0_ = standingConfiguration(m);
    const char* feet[2] = {"left_foot", "right_foot"};
    model::forwardKinematics(m, data_, q0_);
    for (int f = 0; f < 2; ++f) {
      footFrame_[f] = m.frameId(feet[f]);
      footStart_[f] = model::framePlacement(m, data_, footFrame_[f]);
      for (int i = m.frames[footFrame_[f]].body; i > 0; i = m.parent[i]) chain_[f].push_back(i - 1);
    }
    contactFoot_ = {0, 0, 1, 1};
    imuFrame_ = m.frameId("imu");
    base0_ = q0_.head<3>();
    qPrevious_ = q0_;
  }

  /// True configuration at time t (the legs by IK, warm-started from the last call).
  Eigen::VectorXd configuration(double t) {
    Eigen::VectorXd q = qPrevious_;
    const Eigen::Vector3d p = basePosition(t);
    const Eigen::Vector3d zyx = baseZyx(t);
    q.head<3>() = p;
    q.segment<4>(3) = model::quaternionXyzwFromZyx(zyx);
    const double ramp = walkRamp(t);
    const double arm = 0.5 * ramp * std::sin(M_PI * (t - standStill) / stepPeriod);
    q[model::Model::qIndexOfJoint(m_.jointId("left_shoulder_pitch"))] = arm;
    q[model::Model::qIndexOfJoint(m_.jointId("right_shoulder_pitch"))] = -arm;
    for (int f = 0; f < 2; ++f) solveLeg(f, footPose(f, t), q);
    qPrevious_ = q;
    return q;
  }

  /// Model velocity v (model.hpp) at t, by central differences.
  Eigen::VectorXd velocity(double t) {
    const double h = 1e-6;
    const Eigen::VectorXd keep = qPrevious_;
    const Eigen::VectorXd qp = configuration(t + h), qm = configuration(t - h);
    qPrevious_ = keep;
    Eigen::VectorXd v(m_.nv);
    const Eigen::Matrix3d R = model::quaternionToRotation<double>(configuration(t).segment<4>(3));
    const Eigen::Matrix3d Rp = model::quaternionToRotation<double>(qp.segment<4>(3));
    const Eigen::Matrix3d Rm = model::quaternionToRotation<double>(qm.segment<4>(3));
    v.head<3>() = R.transpose() * (qp.head<3>() - qm.head<3>()) / (2 * h);
    v.segment<3>(3) = estimation::rotationLog(Rm.transpose() * Rp) / (2 * h);  // body frame
    v.tail(m_.nj()) = (qp.tail(m_.nj()) - qm.tail(m_.nj())) / (2 * h);
    return v;
  }

  /// Contact point c is scheduled (and truly) in stance at t.
  bool stance(int c, double t) const { return !swinging(contactFoot_[c], t); }

  /// Velocity of the IMU's point (world) and the IMU rotation at state (q, v).
  void imuKinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::Vector3d& velocity,
                     Eigen::Matrix3d& Rwi, Eigen::Vector3d& omegaImu) const {
    const Eigen::Matrix3d Rwb = model::quaternionToRotation<double>(q.segment<4>(3));
    const model::Frame& imu = m_.frames[imuFrame_];
    const Eigen::Vector3d omegaBody = v.segment<3>(3);
    velocity = Rwb * (v.head<3>() + omegaBody.cross(imu.placement.p));
    Rwi = Rwb * imu.placement.R;
    omegaImu = imu.placement.R.transpose() * omegaBody;
  }

  const model::Model& model() const { return m_; }

 private:
  static double smoothstep(double s) {
    s = std::clamp(s, 0.0, 1.0);
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s);
  }
  double walkRamp(double t) const { return smoothstep(t - standStill); }
  /// ∫ speed·ramp: the ramp over [0, 1] s integrates to 1/2.
  double distance(double t) const {
    const double s = std::clamp(t - standStill, 0.0, 1.0);
    const double rampIntegral = s * s * s * s * (2.5 - 3.0 * s + s * s);  // ∫ smoothstep
    return speed * (rampIntegral + std::max(0.0, t - standStill - 1.0));
  }
  Eigen::Vector3d basePosition(double t) const {
    const double ramp = walkRamp(t), phase = M_PI * (t - standStill) / stepPeriod;
    return base0_ + Eigen::Vector3d(distance(t), -0.02 * ramp * std::sin(phase),
                                    0.01 * ramp * std::sin(2 * phase));
  }
  Eigen::Vector3d baseZyx(double t) const {
    const double ramp = walkRamp(t), phase = M_PI * (t - standStill) / stepPeriod;
    return Eigen::Vector3d(0.06 * ramp * std::sin(0.5 * phase), 0.03 * ramp * std::sin(2 * phase),
                           -0.03 * ramp * std::sin(phase));
  }
  /// Step index at t (−1 before walking) and the time into it.
  int step(double t, double& into) const {
    if (t < standStill) return -1;
    const int k = static_cast<int>(std::floor((t - standStill) / stepPeriod));
    into = t - standStill - k * stepPeriod;
    return k;
  }
  bool swinging(int foot, double t) const {
    double into = 0;
    const int k = step(t, into);
    return k >= 0 && k % 2 == foot && into >= doubleSupport;
  }
  /// Where foot f stands after its swing in step k: under the base at the middle of step k + 1.
  double landing(int k) const { return distance(standStill + (k + 1.5) * stepPeriod); }
  /// x of foot f at the start of step k (k ≥ 0).
  double footX(int f, int k) const {
    // The foot's last swing was step k' < k with k' % 2 == f.
    int last = k - 1;
    while (last >= 0 && last % 2 != f) --last;
    return last < 0 ? 0.0 : landing(last);
  }
  model::SE3<double> footPose(int f, double t) const {
    model::SE3<double> T = footStart_[f];
    double into = 0;
    const int k = step(t, into);
    if (k < 0) return T;
    const double start = footX(f, k);
    if (k % 2 != f || into < doubleSupport) {
      T.p.x() += start;
      return T;
    }
    const double s = (into - doubleSupport) / (stepPeriod - doubleSupport);
    T.p.x() += start + (landing(k) - start) * smoothstep(s);
    T.p.z() += stepHeight * 16.0 * s * s * (1 - s) * (1 - s);
    return T;
  }
  void solveLeg(int f, const model::SE3<double>& target, Eigen::VectorXd& q) {
    Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, m_.nv);
    for (int it = 0; it < 20; ++it) {
      model::forwardKinematics(m_, data_, q);
      const model::SE3<double> T = model::framePlacement(m_, data_, footFrame_[f]);
      Eigen::Matrix<double, 6, 1> e;
      e << target.p - T.p, estimation::rotationLog(target.R * T.R.transpose());
      if (e.norm() < 1e-13) return;
      model::frameJacobian(m_, data_, footFrame_[f], J);
      Eigen::Matrix<double, 6, 6> Jleg;
      for (int a = 0; a < 6; ++a) Jleg.col(a) = J.col(6 + chain_[f][a]);
      const Eigen::Matrix<double, 6, 1> dq = Jleg.partialPivLu().solve(e);
      for (int a = 0; a < 6; ++a) q[model::Model::qIndexOfJoint(chain_[f][a])] += dq[a];
    }
  }

  const model::Model& m_;
  model::Data<double> data_;
  Eigen::VectorXd q0_, qPrevious_;
  Eigen::Vector3d base0_;
  std::array<int, 2> footFrame_{};
  std::array<model::SE3<double>, 2> footStart_{};
  std::array<std::vector<int>, 2> chain_;
  std::array<int, 4> contactFoot_{};
  int imuFrame_ = 0;
};

/// Turns true states into sensor readings (the Simbody backend's sensor model).
class SyntheticSensors {
 public:
  SyntheticSensors(SyntheticWalk& walk, const SensorNoise& noise, unsigned seed)
      : walk_(walk), noise_(noise), rng_(seed) {
    for (int i = 0; i < 3; ++i) gyroBias_[i] = noise.gyroBias * normal_(rng_);
    for (int i = 0; i < 3; ++i) accelBias_[i] = noise.accelBias * normal_(rng_);
  }

  /// True state at t (qTrue, vTrue) and the readings, into an estimator input.
  void sample(double t, estimation::EstimatorInput& in, Eigen::VectorXd& qTrue,
              Eigen::VectorXd& vTrue) {
    const model::Model& m = walk_.model();
    const double dt = walk_.period;
    qTrue = walk_.configuration(t);
    vTrue = walk_.velocity(t);
    Eigen::Vector3d velocity, omegaImu;
    Eigen::Matrix3d Rwi;
    walk_.imuKinematics(qTrue, vTrue, velocity, Rwi, omegaImu);
    const Eigen::Vector3d accel = first_ ? Eigen::Vector3d::Zero() : Eigen::Vector3d((velocity - imuVelocity_) / dt);
    imuVelocity_ = velocity;
    first_ = false;

    in.time = t;
    const double gyroSigma = noise_.gyroNoiseDensity / std::sqrt(dt);
    const double accelSigma = noise_.accelNoiseDensity / std::sqrt(dt);
    Eigen::Vector3d tilt;
    for (int i = 0; i < 3; ++i) tilt[i] = noise_.orientationNoise * normal_(rng_);
    in.imu.orientation = Eigen::Quaterniond(Rwi * estimation::rotationExp(tilt));
    for (int i = 0; i < 3; ++i)
      in.imu.angularVelocity[i] = omegaImu[i] + gyroBias_[i] + gyroSigma * normal_(rng_);
    in.imu.linearAcceleration = Rwi.transpose() * (accel - m.gravity);
    for (int i = 0; i < 3; ++i)
      in.imu.linearAcceleration[i] += accelBias_[i] + accelSigma * normal_(rng_);
    in.imu.valid = true;
    for (int j = 0; j < m.nj(); ++j) {
      const double qj = qTrue[model::Model::qIndexOfJoint(j)];
      in.q[j] = noise_.encoderResolution > 0
                    ? noise_.encoderResolution * std::round(qj / noise_.encoderResolution)
                    : qj;
      in.dq[j] = vTrue[model::Model::vIndexOfJoint(j)] + noise_.jointVelocityNoise * normal_(rng_);
      in.tau[j] = 0.0;
    }
    for (int c = 0; c < estimation::kContactPoints; ++c) in.scheduledStance[c] = walk_.stance(c, t);
  }

  const Eigen::Vector3d& gyroBias() const { return gyroBias_; }

 private:
  SyntheticWalk& walk_;
  SensorNoise noise_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Eigen::Vector3d gyroBias_, accelBias_, imuVelocity_ = Eigen::Vector3d::Zero();
  bool first_ = true;
};

}  // namespace ballast::test
