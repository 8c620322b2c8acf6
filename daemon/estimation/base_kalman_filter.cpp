#include "estimation/base_kalman_filter.hpp"

#include <Eigen/Cholesky>

namespace ballast::estimation {

void BaseKalmanFilter::reset(const Vector& state, const Vector& variance) {
  x_ = state;
  P_ = variance.asDiagonal();
}

void BaseKalmanFilter::reset(const Vector& state, const Covariance& covariance) {
  x_ = state;
  P_ = covariance;
}

void BaseKalmanFilter::predict(const Eigen::Vector3d& a, double dt, double accelerationDensity,
                               const std::array<double, kContactPoints>& contactDensity) {
  x_.segment<3>(kPosition) += dt * x_.segment<3>(kVelocity) + 0.5 * dt * dt * a;
  x_.segment<3>(kVelocity) += dt * a;

  // F = I + dt·E, E moving v into p: F P Fᵀ = rows of p += dt·rows of v, then the same on columns.
  P_.middleRows<3>(kPosition) += dt * P_.middleRows<3>(kVelocity);
  P_.middleCols<3>(kPosition) += dt * P_.middleCols<3>(kVelocity);

  const double qa = accelerationDensity * accelerationDensity;
  for (int k = 0; k < 3; ++k) {
    P_(kPosition + k, kPosition + k) += qa * dt * dt * dt / 3.0;
    P_(kPosition + k, kVelocity + k) += qa * dt * dt / 2.0;
    P_(kVelocity + k, kPosition + k) += qa * dt * dt / 2.0;
    P_(kVelocity + k, kVelocity + k) += qa * dt;
  }
  for (int i = 0; i < kContactPoints; ++i)
    for (int k = 0; k < 3; ++k)
      P_(contactIndex(i) + k, contactIndex(i) + k) += contactDensity[i] * contactDensity[i] * dt;
  // Sequential rank-1 updates leave P symmetric only up to round-off; restore it once a tick.
  P_ = 0.5 * (P_ + P_.transpose()).eval();
}

double BaseKalmanFilter::updateScalar(int i, int j, double z, double r) {
  // h = e_j − e_i: P·h is a difference of two columns, hᵀ P h of four entries.
  if (i >= 0)
    Ph_ = P_.col(j) - P_.col(i);
  else
    Ph_ = P_.col(j);
  const double s = (i >= 0 ? Ph_[j] - Ph_[i] : Ph_[j]) + r;
  const double innovation = z - (i >= 0 ? x_[j] - x_[i] : x_[j]);
  // K = P h / s;  x += K·y;  P −= K (P h)ᵀ.
  x_.noalias() += (innovation / s) * Ph_;
  P_.noalias() -= (Ph_ / s) * Ph_.transpose();
  return innovation;
}

void BaseKalmanFilter::updateRelativePosition(int contact, const Eigen::Vector3d& d, double r) {
  for (int k = 0; k < 3; ++k) updateScalar(kPosition + k, contactIndex(contact) + k, d[k], r);
}

void BaseKalmanFilter::updateVelocity(const Eigen::Vector3d& z, double r) {
  for (int k = 0; k < 3; ++k) updateScalar(-1, kVelocity + k, z[k], r);
}

void BaseKalmanFilter::updateContactHeight(int contact, double h, double r) {
  updateScalar(-1, contactIndex(contact) + 2, h, r);
}

void BaseKalmanFilter::anchorContact(int contact, const Eigen::Vector3d& d, double r) {
  const int c = contactIndex(contact);
  x_.segment<3>(c) = x_.segment<3>(kPosition) + d;
  // Rows first, then columns: the copied rows already hold the new diagonal block's source.
  P_.middleRows<3>(c) = P_.middleRows<3>(kPosition);
  P_.middleCols<3>(c) = P_.middleCols<3>(kPosition);
  P_.block<3, 3>(c, c).diagonal().array() += r;
}

bool BaseKalmanFilter::updatePosition(const Eigen::Vector3d& z, const Eigen::Matrix3d& covariance) {
  const Eigen::Matrix3d S = P_.block<3, 3>(kPosition, kPosition) + covariance;
  const Eigen::LLT<Eigen::Matrix3d> llt(S);
  if (llt.info() != Eigen::Success) return false;
  // K = P Hᵀ S⁻¹ with H selecting p: P Hᵀ = the columns of p.
  const Eigen::Matrix<double, kSize, 3> PHt = P_.middleCols<3>(kPosition);
  const Eigen::Matrix<double, kSize, 3> K = llt.solve(PHt.transpose()).transpose();
  x_.noalias() += K * (z - x_.segment<3>(kPosition));
  P_.noalias() -= K * PHt.transpose();
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  return true;
}

}  // namespace ballast::estimation
