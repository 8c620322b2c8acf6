// QP fixtures shared by the wbc tests: random problems of a given shape and a KKT checker that
// knows nothing about how the solver works.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <Eigen/Core>

#include "wbc/qp_solver.hpp"

namespace ballast::test {

using wbc::kInf;

/// A random feasible QP: H = BᵀB + 0.1 I, rows and bounds around a random feasible point x0,
/// some sides absent, and a linear term large enough that many constraints end up active.
inline void randomFeasibleQp(wbc::QpSolver& qp, int n, int me, int mi, std::mt19937& rng,
                             bool withBounds = true) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.05, 1.0);
  auto rnd = [&](int r, int c) { return Eigen::MatrixXd::NullaryExpr(r, c, [&] { return u(rng); }).eval(); };
  qp.resize(n, me, mi);
  const Eigen::MatrixXd B = rnd(n, n);
  qp.H() = B.transpose() * B + 0.1 * Eigen::MatrixXd::Identity(n, n);
  qp.g() = 10.0 * rnd(n, 1);
  const Eigen::VectorXd x0 = rnd(n, 1);
  qp.A() = rnd(me, n);
  qp.b() = qp.A() * x0;
  qp.C() = rnd(mi, n);
  const Eigen::VectorXd cx0 = qp.C() * x0;
  for (int i = 0; i < mi; ++i) {
    const int kind = std::uniform_int_distribution<int>(0, 3)(rng);
    qp.lower()[i] = kind == 1 ? -kInf : cx0[i] - pos(rng);
    qp.upper()[i] = kind == 2 ? kInf : cx0[i] + pos(rng);
    if (kind == 3 && i % 7 == 0) qp.lower()[i] = qp.upper()[i] = cx0[i];  // equality as two sides
  }
  if (withBounds)
    for (int i = 0; i < n; ++i) {
      if (i % 3 == 0) continue;
      qp.lowerBound()[i] = x0[i] - pos(rng);
      qp.upperBound()[i] = x0[i] + pos(rng);
    }
}

/// The largest KKT residual of the solver's answer (stationarity, primal feasibility, multiplier
/// signs, complementarity), each measured directly on the data.
struct KktReport {
  double stationarity = 0, primal = 0, dualSign = 0, complementarity = 0;
  double worst() const { return std::max({stationarity, primal, dualSign, complementarity}); }
  std::string str() const {
    return "stationarity " + std::to_string(stationarity) + ", primal " + std::to_string(primal) +
           ", dual sign " + std::to_string(dualSign) + ", complementarity " +
           std::to_string(complementarity);
  }
};

inline KktReport kkt(wbc::QpSolver& qp) {
  KktReport k;
  const Eigen::VectorXd x = qp.x();
  const Eigen::VectorXd le = qp.equalityMultipliers(), lc = qp.inequalityMultipliers(),
                        lb = qp.boundMultipliers();
  const Eigen::VectorXd grad = qp.H() * x + qp.g();
  Eigen::VectorXd st = grad - lb;
  if (qp.equalities() > 0) st -= qp.A().transpose() * le;
  if (qp.inequalities() > 0) st -= qp.C().transpose() * lc;
  k.stationarity = st.cwiseAbs().maxCoeff();
  if (qp.equalities() > 0) k.primal = (qp.A() * x - qp.b()).cwiseAbs().maxCoeff();
  auto side = [&](double value, double lo, double hi, double lambda) {
    k.primal = std::max({k.primal, lo - value, value - hi});
    // λ > 0 only at the lower side, λ < 0 only at the upper side.
    if (lambda > 0) {
      k.complementarity = std::max(k.complementarity, lambda * std::abs(value - lo));
      if (lo == -kInf) k.dualSign = std::max(k.dualSign, lambda);
    } else if (lambda < 0) {
      k.complementarity = std::max(k.complementarity, -lambda * std::abs(hi - value));
      if (hi == kInf) k.dualSign = std::max(k.dualSign, -lambda);
    }
  };
  const Eigen::VectorXd cx = qp.inequalities() > 0 ? Eigen::VectorXd(qp.C() * x) : Eigen::VectorXd();
  for (int i = 0; i < qp.inequalities(); ++i) side(cx[i], qp.lower()[i], qp.upper()[i], lc[i]);
  for (int i = 0; i < qp.variables(); ++i)
    side(x[i], qp.lowerBound()[i], qp.upperBound()[i], lb[i]);
  return k;
}

}  // namespace ballast::test
