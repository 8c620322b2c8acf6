#include "mpc/tracking_cost.hpp"

#include <cmath>

#include "model/centroidal_dynamics.hpp"

namespace ballast::mpc {

using model::CentroidalLayout;

void stateError(const Eigen::VectorXd& x, const Eigen::VectorXd& xRef, Eigen::VectorXd& e) {
  e = x - xRef;
  for (int k = 0; k < 3; ++k) {
    double& a = e[CentroidalLayout::kBaseZyx + k];
    a = std::remainder(a, 2.0 * M_PI);
  }
}

double trackingCost(const ProblemSettings& s, TrackingWorkspace& ws, const NodeReference& ref,
                    const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt, LqNode* node) {
  stateError(x, ref.x, ws.xError);
  ws.uError = u - ref.u;
  const Eigen::VectorXd& ex = ws.xError;
  const Eigen::VectorXd& eu = ws.uError;
  if (node) {
    node->Q = (dt * s.stateWeights).asDiagonal();
    node->R = (dt * s.inputWeights).asDiagonal();
    node->S.setZero();
    node->q = dt * s.stateWeights.cwiseProduct(ex);
    node->r = dt * s.inputWeights.cwiseProduct(eu);
  }
  return 0.5 * dt * (ex.dot(s.stateWeights.cwiseProduct(ex)) + eu.dot(s.inputWeights.cwiseProduct(eu)));
}

double contactForceBarriers(const ProblemSettings& s, const NodeReference& ref,
                            const Eigen::VectorXd& u, double dt, LqNode* node) {
  double cost = 0.0;
  for (int c = 0; c < kNumContacts; ++c) {
    if (!ref.stance[c]) continue;
    const int i = CentroidalLayout::force(c);
    const Eigen::Vector3d f = u.segment<3>(i);
    const RelaxedBarrier& b = s.frictionBarrier;
    auto barrier = [&](double h, const Eigen::Vector3d& grad) {  // h(f) ≥ 0, ∇h = grad
      cost += dt * b.value(h);
      if (!node) return;
      node->r.segment<3>(i) += dt * b.firstDerivative(h) * grad;
      node->R.block<3, 3>(i, i).noalias() += dt * b.secondDerivative(h) * grad * grad.transpose();
    };
    const double tangential = std::sqrt(f.x() * f.x() + f.y() * f.y() + s.frictionRegularization);
    barrier(s.frictionCoefficient * f.z() - tangential,
            Eigen::Vector3d(-f.x() / tangential, -f.y() / tangential, s.frictionCoefficient));
    barrier(f.z() - s.minNormalForce, Eigen::Vector3d::UnitZ());
    barrier(s.maxNormalForce - f.z(), -Eigen::Vector3d::UnitZ());
  }
  return cost;
}

double terminalTrackingCost(const Eigen::VectorXd& terminalWeights, TrackingWorkspace& ws,
                            const NodeReference& ref, const Eigen::VectorXd& x, LqNode* node) {
  stateError(x, ref.x, ws.xError);
  const Eigen::VectorXd& e = ws.xError;
  const Eigen::VectorXd& w = terminalWeights;
  if (node) {
    node->setZero();
    node->Q = w.asDiagonal();
    node->q = w.cwiseProduct(e);
  }
  return 0.5 * e.dot(w.cwiseProduct(e));
}

void adaptForcesToMode(const NodeReference& ref, const StanceFlags& before, Eigen::VectorXd& u) {
  for (int c = 0; c < kNumContacts; ++c) {
    if (ref.stance[c] == before[c]) continue;
    const int i = CentroidalLayout::force(c);
    u.segment<3>(i) = ref.stance[c] ? Eigen::Vector3d(ref.u.segment<3>(i)) : Eigen::Vector3d::Zero();
  }
}

}  // namespace ballast::mpc
