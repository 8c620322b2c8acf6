// One node of the linear-quadratic subproblem the SQP solves each iteration.
//
// In the deviations (δx, δu) from the current iterate:
//   dynamics      δx_{k+1} = A δx + B δu + b
//   equalities    C δx + D δu + e = 0                  (neq rows; D has full row rank)
//   cost          ½ δxᵀ Q δx + δuᵀ S δx + ½ δuᵀ R δu + qᵀ δx + rᵀ δu
// The terminal node uses only Q and q. Matrices are sized for the problem's maximum and used
// through `neq` rows, so building a node does not allocate.
#pragma once

#include <Eigen/Core>
#include <cstring>

namespace ballast::mpc {

/// a and b are the same numbers to the bit, sizes included: work kept from one solve to the next
/// (SqpSolver::prepare) is used again only on them.
template <class A, class B>
bool sameBits(const Eigen::PlainObjectBase<A>& a, const Eigen::PlainObjectBase<B>& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

struct LqNode {
  Eigen::MatrixXd A, B, C, D, Q, R, S;
  Eigen::VectorXd b, e, q, r;
  int neq = 0;

  LqNode(int nx, int nu, int maxEq)
      : A(nx, nx), B(nx, nu), C(maxEq, nx), D(maxEq, nu), Q(nx, nx), R(nu, nu), S(nu, nx),
        b(nx), e(maxEq), q(nx), r(nu) {
    setZero();
  }
  void setZero() {
    A.setZero(); B.setZero(); C.setZero(); D.setZero(); Q.setZero(); R.setZero(); S.setZero();
    b.setZero(); e.setZero(); q.setZero(); r.setZero();
    neq = 0;
  }
  int nx() const { return static_cast<int>(A.rows()); }
  int nu() const { return static_cast<int>(B.cols()); }
};

}  // namespace ballast::mpc
