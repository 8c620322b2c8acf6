#include "estimation/attitude_filter.hpp"

#include <cmath>

#include "model/spatial.hpp"

namespace ballast::estimation {

using Eigen::Matrix3d;
using Eigen::Vector3d;

Matrix3d rotationExp(const Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const Matrix3d W = model::skew<double>(phi);
  // Taylor series below 1e-4 rad: the closed form loses digits to cancellation there.
  double a, b;
  if (theta2 < 1e-8) {
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    const double theta = std::sqrt(theta2);
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / theta2;
  }
  return Matrix3d::Identity() + a * W + b * W * W;
}

Vector3d rotationLog(const Matrix3d& R) {
  Eigen::Quaterniond q(R);
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  // φ = 2·atan2(s, w)·v/s; for small s the factor tends to 2/w.
  const double factor = s < 1e-12 ? 2.0 / q.w() : 2.0 * std::atan2(s, q.w()) / s;
  return factor * q.vec();
}

void AttitudeFilter::reset(const Matrix3d& orientation, const Noise& noise) {
  R_ = orientation;
  bias_.setZero();
  P_.setZero();
  P_.topLeftCorner<3, 3>().diagonal().setConstant(noise.orientationNoise * noise.orientationNoise);
  P_.bottomRightCorner<3, 3>().diagonal().setConstant(noise.gyroBiasInitial * noise.gyroBiasInitial);
  initialised_ = true;
}

void AttitudeFilter::predict(const Vector3d& gyro, double dt, const Noise& noise) {
  const Matrix3d dR = rotationExp((gyro - bias_) * dt);
  // Through a unit quaternion: a product of rotation matrices drifts off SO(3) by round-off.
  R_ = Eigen::Quaterniond(R_ * dR).normalized().toRotationMatrix();
  // Φ = [dRᵀ  −dt·I; 0  I]. P' = Φ P Φᵀ + Q, written out by blocks.
  const Matrix3d Ptt = P_.topLeftCorner<3, 3>(), Ptb = P_.topRightCorner<3, 3>();
  const Matrix3d Pbb = P_.bottomRightCorner<3, 3>();
  const Matrix3d A = dR.transpose() * Ptt * dR;
  const Matrix3d B = dR.transpose() * Ptb;
  Matrix3d tt = A - dt * (B + B.transpose()) + dt * dt * Pbb;
  const Matrix3d tb = B - dt * Pbb;
  tt.diagonal().array() += noise.gyroNoiseDensity * noise.gyroNoiseDensity * dt;
  P_.topLeftCorner<3, 3>() = 0.5 * (tt + tt.transpose());
  P_.topRightCorner<3, 3>() = tb;
  P_.bottomLeftCorner<3, 3>() = tb.transpose();
  P_.bottomRightCorner<3, 3>().diagonal().array() +=
      noise.gyroBiasRandomWalk * noise.gyroBiasRandomWalk * dt;
}

Vector3d AttitudeFilter::correct(const Matrix3d& measured, const Noise& noise) {
  const Vector3d y = rotationLog(R_.transpose() * measured);
  Matrix3d S = P_.topLeftCorner<3, 3>();
  S.diagonal().array() += noise.orientationNoise * noise.orientationNoise;
  // K = P Hᵀ S⁻¹ (6 x 3); S is 3 x 3 symmetric positive definite.
  const Eigen::LLT<Matrix3d> llt(S);
  const Eigen::Matrix<double, 6, 3> PHt = P_.leftCols<3>();
  const Eigen::Matrix<double, 6, 3> K = llt.solve(PHt.transpose()).transpose();
  const Eigen::Matrix<double, 6, 1> dx = K * y;
  R_ = R_ * rotationExp(dx.head<3>());
  bias_ += dx.tail<3>();
  // P = (I − K H) P = P − K (H P); symmetrised against round-off.
  P_.noalias() -= K * PHt.transpose();
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  return y;
}

}  // namespace ballast::estimation
