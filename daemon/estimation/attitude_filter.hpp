// Orientation and gyro bias of the IMU: an error-state Kalman filter on SO(3) × R³ with the gyro
// as input and the IMU's own orientation output as the measurement.
//
//   state     R (world <- IMU), b (gyro bias, IMU frame)
//   error     R = R̂·Exp(δθ) (δθ in the IMU frame), b = b̂ + δb;  P = Cov[δθ; δb] (6 x 6)
//   predict   R̂ <- R̂·Exp((ω_m − b̂)·dt);  δθ' = Exp(ω̂·dt)ᵀ δθ − dt·δb − dt·n_g,  δb' = δb + n_b
//             Q = diag(σ_g²·dt·I, σ_b²·dt·I)  (σ_g gyro noise density, σ_b bias random walk)
//   correct   y = Log(R̂ᵀ R_m) = δθ + n_o,  H = [I 0],  n_o ~ N(0, σ_o² I) (orientation noise)
//
// Why a filter and not the IMU orientation as it comes: the gyro is far less noisy over a tick
// than the orientation output (σ_g/√dt·dt = 7.6 µrad against σ_o ≈ 5 mrad at 1 kHz with the
// defaults), so integrating the gyro and pulling gently towards the measured orientation gives
// an orientation 25-30× less noisy (attitude_filter_test: 0.3 mrad RMS from an 8.7 mrad
// output); and the same pull makes the gyro bias observable on all
// three axes, whatever the robot does: a bias makes the integrated gyro drift away from the
// measured orientation at a rate equal to the bias. No "stand still to calibrate" phase is
// needed, and the bias keeps being tracked while walking. The cost is a 6 x 6 covariance, a few
// hundred flops a tick.
//
// Angular velocity out: ω = ω_m − b̂ (IMU frame), the bias-corrected gyro (no low-pass: the
// controllers damp on it and want no lag).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ballast::estimation {

/// Exp: rotation vector -> rotation matrix (Rodrigues; exact near zero).
Eigen::Matrix3d rotationExp(const Eigen::Vector3d& phi);
/// Log: rotation matrix -> rotation vector φ, |φ| ≤ π.
Eigen::Vector3d rotationLog(const Eigen::Matrix3d& R);

class AttitudeFilter {
 public:
  struct Noise {
    double gyroNoiseDensity = 2.4e-4;  ///< rad/s/√Hz
    double gyroBiasRandomWalk = 1e-5;  ///< rad/s/√s
    double gyroBiasInitial = 0.01;     ///< rad/s, σ of the initial bias
    double orientationNoise = 0.005;   ///< rad, σ of a measured orientation
  };
  using Covariance = Eigen::Matrix<double, 6, 6>;

  /// Starts at a measured orientation (world <- IMU) with zero bias.
  void reset(const Eigen::Matrix3d& orientation, const Noise& noise);
  /// Propagates by a gyro sample (IMU frame, rad/s) over dt.
  void predict(const Eigen::Vector3d& gyro, double dt, const Noise& noise);
  /// Fuses a measured orientation (world <- IMU). Returns the residual Log(R̂ᵀ R_m) before the
  /// update (IMU frame, rad).
  Eigen::Vector3d correct(const Eigen::Matrix3d& measured, const Noise& noise);

  bool initialised() const { return initialised_; }
  const Eigen::Matrix3d& orientation() const { return R_; }  ///< world <- IMU
  const Eigen::Vector3d& gyroBias() const { return bias_; }  ///< IMU frame, rad/s
  const Covariance& covariance() const { return P_; }        ///< of [δθ; δb]

 private:
  bool initialised_ = false;
  Eigen::Matrix3d R_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  Covariance P_ = Covariance::Identity();
};

}  // namespace ballast::estimation
