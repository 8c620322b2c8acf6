// The linear Kalman filter against hand-computed cases and against a dense textbook filter
// (x = F x + B a, P = F P Fᵀ + Q; K = P Hᵀ (H P Hᵀ + R)⁻¹ with all measurements of a tick
// stacked into one batch, Joseph-form covariance update).
#include <gtest/gtest.h>

#include <random>

#include <Eigen/Dense>

#include "estimation/base_kalman_filter.hpp"

namespace ballast::test {
namespace {

using estimation::BaseKalmanFilter;
using estimation::kContactPoints;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
constexpr int N = BaseKalmanFilter::kSize;

struct DenseKalmanFilter {
  VectorXd x;
  MatrixXd P;

  void predict(const Vector3d& a, double dt, double sa, const std::array<double, kContactPoints>& sc) {
    MatrixXd F = MatrixXd::Identity(N, N);
    F.block(0, 3, 3, 3) = dt * Eigen::Matrix3d::Identity();
    MatrixXd B = MatrixXd::Zero(N, 3);
    B.topRows(3) = 0.5 * dt * dt * Eigen::Matrix3d::Identity();
    B.middleRows(3, 3) = dt * Eigen::Matrix3d::Identity();
    MatrixXd Q = MatrixXd::Zero(N, N);
    for (int k = 0; k < 3; ++k) {
      Q(k, k) = sa * sa * dt * dt * dt / 3;
      Q(k, 3 + k) = Q(3 + k, k) = sa * sa * dt * dt / 2;
      Q(3 + k, 3 + k) = sa * sa * dt;
    }
    for (int c = 0; c < kContactPoints; ++c)
      for (int k = 0; k < 3; ++k) Q(6 + 3 * c + k, 6 + 3 * c + k) = sc[c] * sc[c] * dt;
    x = F * x + B * a;
    P = F * P * F.transpose() + Q;
  }
  void update(const MatrixXd& H, const VectorXd& z, const MatrixXd& R) {
    const MatrixXd S = H * P * H.transpose() + R;
    const MatrixXd K = P * H.transpose() * S.inverse();
    x += K * (z - H * x);
    const MatrixXd IKH = MatrixXd::Identity(N, N) - K * H;
    P = IKH * P * IKH.transpose() + K * R * K.transpose();
  }
};

MatrixXd randomCovariance(std::mt19937& rng, double scale) {
  std::normal_distribution<double> g(0.0, 1.0);
  MatrixXd A = MatrixXd::NullaryExpr(N, N, [&] { return g(rng); });
  return scale * (A * A.transpose() / N + 0.1 * MatrixXd::Identity(N, N));
}

TEST(BaseKalmanFilter, PredictByHand) {
  BaseKalmanFilter kf;
  BaseKalmanFilter::Vector x = BaseKalmanFilter::Vector::Zero(), var;
  x.segment<3>(0) << 1.0, 2.0, 3.0;
  x.segment<3>(3) << 0.5, -1.0, 0.0;
  x.segment<3>(6) << 4.0, 5.0, 6.0;
  var.setConstant(0.01);
  var.segment<3>(3).setConstant(0.04);
  kf.reset(x, var);
  const double dt = 0.1, sa = 2.0;
  kf.predict(Vector3d(0.0, 0.0, 10.0), dt, sa, {0.3, 0.3, 0.3, 0.3});
  // p = p + v dt + a dt²/2; v = v + a dt; c unchanged.
  EXPECT_NEAR(kf.state()[0], 1.05, 1e-15);
  EXPECT_NEAR(kf.state()[1], 1.9, 1e-15);
  EXPECT_NEAR(kf.state()[2], 3.05, 1e-15);
  EXPECT_NEAR(kf.state()[5], 1.0, 1e-15);
  EXPECT_EQ(kf.state()[6], 4.0);
  // P_pp = 0.01 + dt²·0.04 + 4·dt³/3; P_pv = dt·0.04 + 4·dt²/2; P_vv = 0.04 + 4·dt; P_cc = 0.01 + 0.09·dt.
  const auto& P = kf.covariance();
  EXPECT_NEAR(P(0, 0), 0.01 + 0.0004 + 4.0 * 0.001 / 3.0, 1e-15);
  EXPECT_NEAR(P(0, 3), 0.004 + 0.02, 1e-15);
  EXPECT_NEAR(P(3, 0), 0.004 + 0.02, 1e-15);
  EXPECT_NEAR(P(3, 3), 0.04 + 0.4, 1e-15);
  EXPECT_NEAR(P(6, 6), 0.01 + 0.009, 1e-15);
  EXPECT_EQ(P(0, 1), 0.0);
  EXPECT_EQ(P(0, 6), 0.0);
}

TEST(BaseKalmanFilter, RepeatedHeightMeasurementsAddInformation) {
  // A scalar Gaussian measured n times: 1/σ² = 1/σ0² + n/r, μ = σ²·(μ0/σ0² + Σz/r).
  BaseKalmanFilter kf;
  BaseKalmanFilter::Vector x = BaseKalmanFilter::Vector::Zero(), var;
  var.setConstant(1.0);
  const int c = 2, iz = BaseKalmanFilter::contactIndex(c) + 2;
  x[iz] = 0.3;
  var[iz] = 0.04;
  kf.reset(x, var);
  const double r = 0.01;
  const double z[] = {0.01, -0.02, 0.005, 0.0};
  double sum = 0;
  for (double zi : z) {
    kf.updateContactHeight(c, zi, r);
    sum += zi;
  }
  const double info = 1 / 0.04 + 4 / r;
  EXPECT_NEAR(kf.covariance()(iz, iz), 1 / info, 1e-15);
  EXPECT_NEAR(kf.state()[iz], (0.3 / 0.04 + sum / r) / info, 1e-14);
  // Nothing else moved: the state was uncorrelated.
  EXPECT_EQ(kf.state()[0], 0.0);
  EXPECT_EQ(kf.covariance()(0, 0), 1.0);
}

TEST(BaseKalmanFilter, FourStanceVelocitiesAverage) {
  // v measured by four stance points with equal noise: the posterior mean is the
  // precision-weighted mean of the prior and the four readings.
  BaseKalmanFilter kf;
  BaseKalmanFilter::Vector x = BaseKalmanFilter::Vector::Zero(), var;
  var.setConstant(0.25);
  kf.reset(x, var);
  const double r = 0.0025;
  const Vector3d z[4] = {{0.10, 0.0, 0.01}, {0.12, 0.01, 0.0}, {0.08, -0.01, -0.01}, {0.10, 0.0, 0.0}};
  for (const Vector3d& zi : z) kf.updateVelocity(zi, r);
  const double info = 1 / 0.25 + 4 / r;
  EXPECT_NEAR(kf.state()[3], (0.40 / r) / info, 1e-14);
  EXPECT_NEAR(kf.state()[4], 0.0, 1e-14);
  EXPECT_NEAR(kf.covariance()(3, 3), 1 / info, 1e-15);
}

TEST(BaseKalmanFilter, RelativePositionSplitsByVariance) {
  // c − p = d with independent p (σp²) and c (σc²): the innovation goes to p and c in proportion
  // to their variances, and they become correlated.
  BaseKalmanFilter kf;
  BaseKalmanFilter::Vector x = BaseKalmanFilter::Vector::Zero(), var;
  var.setConstant(1.0);
  var[0] = 0.01;                                  // p_x
  var[BaseKalmanFilter::contactIndex(1)] = 0.03;  // c_1,x
  kf.reset(x, var);
  const double r = 0.0;  // noiseless: the constraint holds exactly afterwards
  kf.updateScalar(0, BaseKalmanFilter::contactIndex(1), 0.4, r + 1e-300);
  const int ic = BaseKalmanFilter::contactIndex(1);
  EXPECT_NEAR(kf.state()[0], -0.4 * 0.01 / 0.04, 1e-14);
  EXPECT_NEAR(kf.state()[ic], 0.4 * 0.03 / 0.04, 1e-14);
  EXPECT_NEAR(kf.state()[ic] - kf.state()[0], 0.4, 1e-14);
  // Posterior: P_pp = 0.01 − 0.01²/0.04, P_pc = 0.01·0.03/0.04.
  EXPECT_NEAR(kf.covariance()(0, 0), 0.01 - 0.0001 / 0.04, 1e-15);
  EXPECT_NEAR(kf.covariance()(0, ic), 0.0003 / 0.04, 1e-15);
}

TEST(BaseKalmanFilter, MatchesDenseBatchFilter) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  BaseKalmanFilter kf;
  DenseKalmanFilter ref;
  BaseKalmanFilter::Vector x0 = BaseKalmanFilter::Vector::NullaryExpr([&] { return g(rng); });
  const MatrixXd P0 = randomCovariance(rng, 0.01);
  kf.reset(x0, BaseKalmanFilter::Covariance(P0));
  ref.x = x0;
  ref.P = P0;
  const std::array<double, kContactPoints> sc{0.002, 0.2, 0.002, 0.002};
  for (int tick = 0; tick < 50; ++tick) {
    const Vector3d a(g(rng), g(rng), g(rng));
    kf.predict(a, 0.001, 0.05, sc);
    ref.predict(a, 0.001, 0.05, sc);
    // One tick of measurements: points 0, 2, 3 in stance (relative position, velocity,
    // height), each with its own variance.
    MatrixXd H = MatrixXd::Zero(21, N);
    VectorXd z(21), r(21);
    int row = 0;
    for (int c : {0, 2, 3}) {
      const Vector3d d(g(rng), g(rng), g(rng)), w(g(rng), g(rng), g(rng));
      const double h = 0.01 * g(rng);
      kf.updateRelativePosition(c, d, 1e-4 * (c + 1));
      kf.updateVelocity(w, 2e-3);
      kf.updateContactHeight(c, h, 3e-5);
      for (int k = 0; k < 3; ++k, ++row) {
        H(row, k) = -1;
        H(row, 6 + 3 * c + k) = 1;
        z[row] = d[k];
        r[row] = 1e-4 * (c + 1);
      }
      for (int k = 0; k < 3; ++k, ++row) {
        H(row, 3 + k) = 1;
        z[row] = w[k];
        r[row] = 2e-3;
      }
      H(row, 6 + 3 * c + 2) = 1;
      z[row] = h;
      r[row++] = 3e-5;
    }
    ref.update(H, z, r.asDiagonal().toDenseMatrix());
    if (tick % 10 == 9) {
      const Vector3d zp(g(rng), g(rng), g(rng));
      Eigen::Matrix3d Rp;
      Rp << 0.02, 0.005, 0, 0.005, 0.03, 0.001, 0, 0.001, 0.01;
      ASSERT_TRUE(kf.updatePosition(zp, Rp));
      MatrixXd Hp = MatrixXd::Zero(3, N);
      Hp.leftCols(3).setIdentity();
      ref.update(Hp, zp, Rp);
    }
  }
  EXPECT_LT((kf.state() - ref.x).norm(), 1e-9 * (1 + ref.x.norm()));
  EXPECT_LT((kf.covariance() - ref.P).norm(), 1e-9 * ref.P.norm());
  // Still a covariance.
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatrixXd>(kf.covariance()).eigenvalues().minCoeff(), 0.0);
}

TEST(BaseKalmanFilter, AnchorIsExactStateAugmentation) {
  // c_i := p + d + n is the linear map x' = T x + e (row of c_i copies p) with noise r on c_i:
  // P' = T P Tᵀ + diag(r on c_i).
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  BaseKalmanFilter kf;
  BaseKalmanFilter::Vector x0 = BaseKalmanFilter::Vector::NullaryExpr([&] { return g(rng); });
  const MatrixXd P0 = randomCovariance(rng, 0.1);
  kf.reset(x0, BaseKalmanFilter::Covariance(P0));
  const Vector3d d(0.1, -0.2, -0.9);
  const int c = 3, ic = BaseKalmanFilter::contactIndex(c);
  kf.anchorContact(c, d, 0.5);
  MatrixXd T = MatrixXd::Identity(N, N);
  T.block(ic, ic, 3, 3).setZero();
  T.block(ic, 0, 3, 3).setIdentity();
  MatrixXd expected = T * P0 * T.transpose();
  expected.block(ic, ic, 3, 3).diagonal().array() += 0.5;
  EXPECT_LT((kf.covariance() - expected).norm(), 1e-14);
  EXPECT_LT((kf.contactPosition(c) - (x0.head<3>() + d)).norm(), 1e-15);
  EXPECT_EQ(kf.state().head<6>(), x0.head<6>());
}

TEST(BaseKalmanFilter, RejectsAnIndefinitePositionCovariance) {
  BaseKalmanFilter kf;
  kf.reset(BaseKalmanFilter::Vector(BaseKalmanFilter::Vector::Zero()),
           BaseKalmanFilter::Vector(BaseKalmanFilter::Vector::Constant(1e-4)));
  Eigen::Matrix3d bad = -Eigen::Matrix3d::Identity();
  EXPECT_FALSE(kf.updatePosition(Vector3d(1, 1, 1), bad));
  EXPECT_EQ(kf.position(), Vector3d::Zero());
}

}  // namespace
}  // namespace ballast::test
