// The planner's output: state and input trajectories on the node grid t0 + k·dt, and the
// contact mode each node was planned with. The whole-body controller samples it at the current
// time: states linearly between nodes, inputs held over each node's interval (the discrete
// dynamics apply u_k on [t_k, t_k+1)).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "mpc/optimal_control_problem.hpp"

namespace ballast::mpc {

struct MpcSolution {
  double t0 = 0.0;
  double dt = 0.02;
  std::vector<Eigen::VectorXd> x;     ///< N + 1 states
  std::vector<Eigen::VectorXd> u;     ///< N inputs
  std::vector<StanceFlags> stance;    ///< N + 1 modes

  int nodes() const { return static_cast<int>(u.size()); }
  bool empty() const { return u.empty(); }
  double endTime() const { return t0 + dt * nodes(); }

  /// x(t) and u(t), clamped to the horizon. x and u must already have the right sizes.
  void sample(double t, Eigen::VectorXd& xt, Eigen::VectorXd& ut, StanceFlags* mode = nullptr) const {
    double s = std::clamp((t - t0) / dt, 0.0, static_cast<double>(nodes()));
    if (std::abs(s - std::round(s)) < 1e-6) s = std::round(s);  // on a node: that node's input
    const int k = std::min(static_cast<int>(std::floor(s)), nodes() - 1);
    const double a = s - k;
    xt = (1.0 - a) * x[k] + a * x[k + 1];
    ut = u[k];
    if (mode) *mode = stance[k];
  }
};

}  // namespace ballast::mpc
