// Forward-mode Jacobians with ceres::Jet, a chunk of N directions per evaluation.
//
// fn(xJet, yJet) evaluates y = f(x) on Jet scalars; forwardJacobian seeds N input directions
// at a time and collects ∂y/∂x (ny x nx). Buffers live in a workspace, so repeated calls do
// not allocate. Exact derivatives: no finite differences anywhere.
#pragma once

#include <ceres/jet.h>

#include <Eigen/Core>

namespace ballast::model {

template <int N>
struct ForwardJacobianWorkspace {
  using Jet = ceres::Jet<double, N>;
  Eigen::Matrix<Jet, Eigen::Dynamic, 1> x, y;
  ForwardJacobianWorkspace(int nx, int ny) : x(nx), y(ny) {}
};

template <int N, typename Fn>
void forwardJacobian(Fn&& fn, const Eigen::VectorXd& x0, ForwardJacobianWorkspace<N>& ws,
                     Eigen::MatrixXd& J) {
  using Jet = typename ForwardJacobianWorkspace<N>::Jet;
  const int nx = static_cast<int>(x0.size());
  for (int i = 0; i < nx; ++i) ws.x[i] = Jet(x0[i]);
  for (int start = 0; start < nx; start += N) {
    const int width = std::min(N, nx - start);
    for (int k = 0; k < width; ++k) ws.x[start + k].v[k] = 1.0;
    fn(ws.x, ws.y);
    for (int r = 0; r < ws.y.size(); ++r)
      for (int k = 0; k < width; ++k) J(r, start + k) = ws.y[r].v[k];
    for (int k = 0; k < width; ++k) ws.x[start + k].v[k] = 0.0;
  }
}

}  // namespace ballast::model
