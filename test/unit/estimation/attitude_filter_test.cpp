// The attitude filter: SO(3) maps, its covariance algebra against dense matrices, and what it
// is for — the gyro bias found while the robot moves, and an orientation less noisy than the
// IMU's own output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/Dense>

#include "estimation/attitude_filter.hpp"

namespace ballast::test {
namespace {

using estimation::AttitudeFilter;
using estimation::rotationExp;
using estimation::rotationLog;
using Eigen::Matrix3d;
using Eigen::Vector3d;

TEST(RotationMaps, ExpMatchesAngleAxisAndLogInvertsIt) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale : {1e-9, 1e-5, 1e-3, 0.5, 3.0}) {
    for (int n = 0; n < 20; ++n) {
      Vector3d phi(u(rng), u(rng), u(rng));
      phi = phi.normalized() * scale * std::abs(u(rng));
      const Matrix3d R = rotationExp(phi);
      const Matrix3d Ref = phi.norm() > 0 ? Eigen::AngleAxisd(phi.norm(), phi.normalized()).toRotationMatrix()
                                           : Matrix3d::Identity();
      EXPECT_LT((R - Ref).norm(), 1e-14);
      EXPECT_LT((rotationLog(R) - phi).norm(), 1e-13 * std::max(1.0, phi.norm()));
    }
  }
  // Near π the log keeps the angle (the axis sign is free there).
  const Vector3d nearPi = Vector3d(1, 2, 2).normalized() * (M_PI - 1e-7);
  EXPECT_NEAR(rotationLog(rotationExp(nearPi)).norm(), M_PI - 1e-7, 1e-9);
}

TEST(AttitudeFilter, CovarianceMatchesDenseAlgebra) {
  AttitudeFilter::Noise noise;
  noise.gyroNoiseDensity = 0.01;
  noise.gyroBiasRandomWalk = 0.001;
  noise.gyroBiasInitial = 0.05;
  noise.orientationNoise = 0.02;
  AttitudeFilter f;
  f.reset(rotationExp(Vector3d(0.1, -0.2, 0.3)), noise);
  Eigen::Matrix<double, 6, 6> P = f.covariance();
  const Vector3d gyro(0.5, -1.0, 2.0);
  const double dt = 0.01;
  f.predict(gyro, dt, noise);
  // Φ = [Exp(ω dt)ᵀ  −dt I; 0  I], Q = diag(σg² dt, σb² dt).
  Eigen::Matrix<double, 6, 6> Phi = Eigen::Matrix<double, 6, 6>::Identity();
  Phi.topLeftCorner<3, 3>() = rotationExp(gyro * dt).transpose();
  Phi.topRightCorner<3, 3>() = -dt * Matrix3d::Identity();
  Eigen::Matrix<double, 6, 6> Q = Eigen::Matrix<double, 6, 6>::Zero();
  Q.topLeftCorner<3, 3>().diagonal().setConstant(1e-4 * dt);
  Q.bottomRightCorner<3, 3>().diagonal().setConstant(1e-6 * dt);
  P = Phi * P * Phi.transpose() + Q;
  EXPECT_LT((f.covariance() - P).norm(), 1e-15);

  // Correction: K = P Hᵀ (H P Hᵀ + σo² I)⁻¹, H = [I 0]; P' = (I − K H) P; the bias moves by K_b·y.
  const Matrix3d before = f.orientation();
  const Matrix3d measured = before * rotationExp(Vector3d(0.01, 0.0, -0.02));
  const Vector3d y = f.correct(measured, noise);
  EXPECT_LT((y - Vector3d(0.01, 0.0, -0.02)).norm(), 1e-12);
  Eigen::Matrix<double, 3, 6> H = Eigen::Matrix<double, 3, 6>::Zero();
  H.leftCols<3>().setIdentity();
  const Eigen::Matrix<double, 6, 3> K =
      P * H.transpose() * (H * P * H.transpose() + 4e-4 * Matrix3d::Identity()).inverse();
  const Eigen::Matrix<double, 6, 1> dx = K * y;
  EXPECT_LT((f.covariance() - (Eigen::Matrix<double, 6, 6>::Identity() - K * H) * P).norm(), 1e-14);
  EXPECT_LT((f.gyroBias() - dx.tail<3>()).norm(), 1e-14);
  EXPECT_LT((f.orientation() - before * rotationExp(dx.head<3>())).norm(), 1e-14);
}

TEST(AttitudeFilter, FindsTheGyroBiasWhileRotatingAndFiltersTheOrientation) {
  // A body tumbling at about 1 rad/s, gyro with a 0.01 rad/s bias per axis and white noise, the
  // orientation output with σ = 5 mrad white noise; 1 kHz.
  AttitudeFilter::Noise noise;  // the defaults: σg 2.4e-4, σo 5e-3
  const double dt = 0.001;
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  const Vector3d bias(0.01, -0.008, 0.012);
  Matrix3d R = rotationExp(Vector3d(0.2, 0.1, -0.3));
  AttitudeFilter f;
  f.reset(R * rotationExp(noise.orientationNoise * Vector3d(g(rng), g(rng), g(rng))), noise);
  double sumFiltered = 0, sumRaw = 0;
  int n = 0;
  for (int k = 1; k <= 10000; ++k) {
    const double t = k * dt;
    const Vector3d omega(std::sin(t), 0.8 * std::cos(0.7 * t), 0.5 + 0.3 * std::sin(2 * t));
    R = R * rotationExp(omega * dt);
    const Vector3d gyro = omega + bias + noise.gyroNoiseDensity / std::sqrt(dt) *
                                             Vector3d(g(rng), g(rng), g(rng));
    const Matrix3d measured =
        R * rotationExp(noise.orientationNoise * Vector3d(g(rng), g(rng), g(rng)));
    f.predict(gyro, dt, noise);
    f.correct(measured, noise);
    if (t > 5.0) {
      sumFiltered += rotationLog(R.transpose() * f.orientation()).squaredNorm();
      sumRaw += rotationLog(R.transpose() * measured).squaredNorm();
      ++n;
    }
  }
  const double filtered = std::sqrt(sumFiltered / n), raw = std::sqrt(sumRaw / n);
  std::printf("gyro bias error %.2e rad/s; orientation error RMS %.3f mrad (IMU output %.3f mrad)\n",
              (f.gyroBias() - bias).norm(), 1e3 * filtered, 1e3 * raw);
  EXPECT_LT((f.gyroBias() - bias).norm(), 5e-4);
  EXPECT_LT(filtered, raw / 5.0);
  // The filter's own uncertainty agrees with its error (within a factor of 2).
  const double sigma = std::sqrt(f.covariance().topLeftCorner<3, 3>().trace());
  EXPECT_GT(sigma, filtered / 2);
  EXPECT_LT(sigma, filtered * 2);
}

}  // namespace
}  // namespace ballast::test
