#include "mpc/kinodynamic_problem.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "model/centroidal_dynamics_derivatives.hpp"
#include "mpc/tracking_cost.hpp"

namespace ballast::mpc {

using model::CentroidalLayout;

NodeWorkspace::NodeWorkspace(const KinodynamicProblem& problem)
    : data(problem.model()),
      xdot(problem.nx()),
      Ax(problem.nx(), problem.nx()),
      Bu(problem.nx(), problem.nu()),
      xMid(problem.nx()),
      contacts(kNumContacts, model::FrameKinematicsZyx(problem.nx(), problem.nu())),
      dPosition_du(kNumContacts, model::Mat3X<double>(3, problem.nu())),
      rowDx(3, problem.nx()),
      rowDu(3, problem.nu()),
      pointDx{model::Mat3X<double>(3, problem.nx()), model::Mat3X<double>(3, problem.nx())},
      pointDu{model::Mat3X<double>(3, problem.nu()), model::Mat3X<double>(3, problem.nu())},
      gradX(problem.nx()),
      gradU(problem.nu()),
      axisDx(3, problem.nx()),
      axisRow(problem.nx()),
      xError(problem.nx()),
      uError(problem.nu()),
      derivativesX(problem.nx()),
      derivativesU(problem.nu()) {}

KinodynamicProblem::KinodynamicProblem(const model::Model& model,
                                       const std::array<int, kNumContacts>& contactFrames,
                                       const ProblemSettings& settings)
    : model_(model),
      contactFrames_(contactFrames.begin(), contactFrames.end()),
      nx_(CentroidalLayout{model.nj(), kNumContacts}.nx()),
      nu_(CentroidalLayout{model.nj(), kNumContacts}.nu() + soleMoments(settings)),
      soles_(soleMoments(settings)) {
  setSettings(settings);
}

void KinodynamicProblem::setSettings(const ProblemSettings& s) {
  if (s.stateWeights.size() != nx_ || s.inputWeights.size() != nu_)
    throw std::invalid_argument("kino-dynamic problem: " + std::to_string(nx_) + " state and " +
                                std::to_string(nu_) + " input weights needed, got " +
                                std::to_string(s.stateWeights.size()) + " and " +
                                std::to_string(s.inputWeights.size()));
  if (!(s.soleWidth >= 0.0)) throw std::invalid_argument("kino-dynamic problem: negative sole width");
  if (soleMoments(s) != soles_)
    throw std::invalid_argument("kino-dynamic problem: line feet and soles with width are different problems");
  settings_ = s;
  ++settingsVersion_;
  terminalWeights_ = s.terminalWeightScale * s.stateWeights;
}

void KinodynamicProblem::evaluate(ProblemWorkspace& ws, const NodeReference& ref,
                                  const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                                  NodeValue& value) const {
  compute(static_cast<NodeWorkspace&>(ws), ref, x, u, dt, nullptr, value);
}

void KinodynamicProblem::linearize(ProblemWorkspace& ws, const NodeReference& ref,
                                   const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                                   LqNode& node, NodeValue& value) const {
  compute(static_cast<NodeWorkspace&>(ws), ref, x, u, dt, &node, value);
}

void KinodynamicProblem::adaptInputToMode(const NodeReference& ref, const StanceFlags& before,
                                          Eigen::VectorXd& u) const {
  for (int c = 0; c < kNumContacts; ++c) {
    if (ref.stance[c] == before[c]) continue;
    const int i = CentroidalLayout::force(c);
    u.segment<3>(i) = ref.stance[c] ? Eigen::Vector3d(ref.u.segment<3>(i)) : Eigen::Vector3d::Zero();
    if (soles_ > 0) u[soleMoment(c / 2)] = ref.u[soleMoment(c / 2)];  // a sole lands or lifts
  }
}

bool KinodynamicProblem::standsOnSole(const NodeReference& ref, int foot) const {
  return soles_ > 0 && ref.stance[2 * foot] && ref.stance[2 * foot + 1];
}

void KinodynamicProblem::addSoleMoments(NodeWorkspace& ws, const Eigen::VectorXd& u,
                                        bool derivatives) const {
  for (int foot = 0; foot < soles_; ++foot) {
    const model::FrameKinematicsZyx& toe = ws.contacts[2 * foot];
    const model::FrameKinematicsZyx& heel = ws.contacts[2 * foot + 1];
    const Eigen::Vector3d d = toe.position - heel.position;
    const double length = d.norm();
    if (!(length > 0.0)) continue;  // toe and heel on one point: a point foot has no line
    const Eigen::Vector3d a = d / length;
    const int i = soleMoment(foot);
    const double m = u[i];
    ws.xdot.segment<3>(3) += m * a;
    if (!derivatives) continue;
    ws.Bu.block<3, 1>(3, i) = a;
    if (m == 0.0) continue;
    // ∂a/∂x = (I − a aᵀ)/‖d‖ · ∂d/∂x.
    ws.axisDx.noalias() = toe.dPosition_dx - heel.dPosition_dx;
    ws.axisRow.noalias() = a.transpose() * ws.axisDx;
    ws.axisDx.noalias() -= a * ws.axisRow;
    ws.Ax.middleRows<3>(3) += (m / length) * ws.axisDx;
  }
}

void KinodynamicProblem::dynamics(NodeWorkspace& ws, const Eigen::VectorXd& x,
                                  const Eigen::VectorXd& u, double dt, bool derivatives) const {
  const CentroidalLayout L{model_.nj(), kNumContacts};
  const int nj = model_.nj();
  // Everything that depends on the configuration is evaluated at the interval's joint midpoint
  // x_mid = x + (dt/2)·[0; 0; v_j] (see the header); ∂x_mid/∂v_j = (dt/2)·I on the joints.
  ws.xMid = x;
  ws.xMid.segment(L.kJoints, nj).noalias() += 0.5 * dt * u.segment(L.jointVelocity(), nj);
  // The line search (no node) needs values only: no Jacobians, the same values.
  model::centroidalDynamicsDerivatives(model_, ws.data, contactFrames_, ws.xMid, u, ws.xdot, ws.Ax,
                                       ws.Bu, derivatives);
  if (!derivatives) {
    for (int c = 0; c < kNumContacts; ++c) {  // as frameKinematicsZyx has them
      model::FrameKinematicsZyx& k = ws.contacts[c];
      k.position = model::framePlacement(model_, ws.data, contactFrames_[c]).p;
      k.velocity = ws.data.ov[model_.frames[contactFrames_[c]].body].pointVelocity(k.position);
    }
    addSoleMoments(ws, u, false);
  } else {
    for (int c = 0; c < kNumContacts; ++c)
      model::frameKinematicsZyx(model_, ws.data, contactFrames_[c], ws.xMid, ws.Ax, ws.Bu,
                                ws.contacts[c]);
    addSoleMoments(ws, u, true);  // before the chain rule: the lines turn with the joints too
    // Chain rule through x_mid: ∂/∂v_j += (dt/2)·∂/∂q_j.
    const double half = 0.5 * dt;
    ws.Bu.middleCols(L.jointVelocity(), nj).noalias() += half * ws.Ax.middleCols(L.kJoints, nj);
    for (int c = 0; c < kNumContacts; ++c) {
      model::FrameKinematicsZyx& k = ws.contacts[c];
      k.dVelocity_du.middleCols(L.jointVelocity(), nj).noalias() +=
          half * k.dVelocity_dx.middleCols(L.kJoints, nj);
      ws.dPosition_du[c].setZero();
      ws.dPosition_du[c].middleCols(L.jointVelocity(), nj) = half * k.dPosition_dx.middleCols(L.kJoints, nj);
    }
  }
  ws.haveDerivatives = derivatives;
  if (!derivatives) return;
  ws.derivativesX = x;
  ws.derivativesU = u;
  ws.derivativesDt = dt;
}

void KinodynamicProblem::compute(NodeWorkspace& ws, const NodeReference& ref,
                                 const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                                 LqNode* node, NodeValue& value) const {
  const CentroidalLayout L{model_.nj(), kNumContacts};
  const ProblemSettings& s = settings_;
  // The dynamics' derivatives, unless this workspace has them at this point; the node's
  // matrices, unless it also linearised this node last at this point, in this contact mode and
  // with these settings (SqpSolver::prepare): then only its vectors.
  const bool sameDerivatives = node && ws.haveDerivatives && ws.derivativesDt == dt &&
                               sameBits(ws.derivativesX, x) && sameBits(ws.derivativesU, u);
  ws.keptMatrices = sameDerivatives && ws.matricesNode == node && ws.matricesStance == ref.stance &&
                    ws.matricesSettings == settingsVersion_;
  const bool matrices = node && !ws.keptMatrices;
  if (!sameDerivatives) dynamics(ws, x, u, dt, node != nullptr);
  ws.matricesNode = nullptr;  // until the node's matrices are written, at the end
  value.xdot = ws.xdot;
  value.xdot.head<3>() += ref.externalForce;  // constant: no derivative

  // Equalities: contact-point velocities (5 per foot) and swing forces.
  double eq2 = 0.0;
  int row = 0;
  // One row per selected world axis of a point's velocity condition.
  auto putRows = [&](std::initializer_list<Eigen::Index> axes, const Eigen::Vector3d& residual,
                     const model::Mat3X<double>& dx, const model::Mat3X<double>& du) {
    for (const Eigen::Index a : axes) {
      eq2 += residual[a] * residual[a];
      if (node) node->e[row] = residual[a];
      if (matrices) {
        node->C.row(row) = dx.row(a);
        node->D.row(row) = du.row(a);
      }
      ++row;
    }
  };
  for (int foot = 0; foot < 2; ++foot) {
    const int toe = 2 * foot, heel = 2 * foot + 1;
    // The heel drops the world axis along which the toe-heel direction is largest: what rigidity
    // already fixes. A constant selection keeps the Jacobian exact.
    Eigen::Index dropped;
    (ws.contacts[toe].position - ws.contacts[heel].position).cwiseAbs().maxCoeff(&dropped);
    // A swinging foot whose yaw the legs cannot turn: its middle and its pitch (see the header).
    const bool combined = s.feetFollowBaseYaw && !ref.stance[toe] && !ref.stance[heel];
    // Both feet standing: the second foot's yaw is the first's (both are the base's), so its
    // heel's sideways row is left out.
    const bool sameYaw = s.feetFollowBaseYaw && foot == 1 && ref.stance[0] && ref.stance[1] &&
                         ref.stance[2] && ref.stance[3] && dropped != 2;
    for (int c : {toe, heel}) {
      const model::FrameKinematicsZyx& k = ws.contacts[c];
      Eigen::Vector3d& residual = combined ? ws.pointResidual[c - toe] : ws.rowResidual;
      residual = k.velocity;
      model::Mat3X<double>& dx = combined ? ws.pointDx[c - toe] : ws.rowDx;
      model::Mat3X<double>& du = combined ? ws.pointDu[c - toe] : ws.rowDu;
      if (matrices) {
        dx = k.dVelocity_dx;
        du = k.dVelocity_du;
      }
      if (!ref.stance[c]) {  // v − (ṗ* + k_p (p* − p))
        residual -= ref.swingVelocity[c] + s.swingPositionGain * (ref.swingPosition[c] - k.position);
        if (matrices) {
          dx += s.swingPositionGain * k.dPosition_dx;
          du += s.swingPositionGain * ws.dPosition_du[c];
        }
      }
      if (combined) continue;
      if (c == toe)
        putRows({0, 1, 2}, residual, dx, du);
      else if (sameYaw)
        putRows({2}, residual, dx, du);
      else
        putRows({(dropped + 1) % 3, (dropped + 2) % 3}, residual, dx, du);
    }
    if (combined) {
      // Middle: the mean of the two conditions; pitch: their difference along the vertical.
      ws.rowResidual = 0.5 * (ws.pointResidual[0] + ws.pointResidual[1]);
      if (matrices) {
        ws.rowDx = 0.5 * (ws.pointDx[0] + ws.pointDx[1]);
        ws.rowDu = 0.5 * (ws.pointDu[0] + ws.pointDu[1]);
      }
      putRows({0, 1, 2}, ws.rowResidual, ws.rowDx, ws.rowDu);
      ws.rowResidual = ws.pointResidual[0] - ws.pointResidual[1];
      if (matrices) {
        ws.rowDx = ws.pointDx[0] - ws.pointDx[1];
        ws.rowDu = ws.pointDu[0] - ws.pointDu[1];
      }
      putRows({2}, ws.rowResidual, ws.rowDx, ws.rowDu);
    }
  }
  for (int c = 0; c < kNumContacts; ++c) {
    if (ref.stance[c]) continue;
    const Eigen::Vector3d f = u.segment<3>(L.force(c));
    eq2 += f.squaredNorm();
    if (node) node->e.segment<3>(row) = f;
    if (matrices) {
      node->C.middleRows<3>(row).setZero();
      node->D.middleRows<3>(row).setZero();
      node->D.block<3, 3>(row, L.force(c)).setIdentity();
    }
    row += 3;
  }
  for (int foot = 0; foot < soles_; ++foot) {
    if (standsOnSole(ref, foot)) continue;
    const int i = soleMoment(foot);
    eq2 += u[i] * u[i];
    if (node) node->e[row] = u[i];
    if (matrices) {
      node->C.row(row).setZero();
      node->D.row(row).setZero();
      node->D(row, i) = 1.0;
    }
    ++row;
  }
  value.equalityNorm2 = eq2;

  // Cost, integrated over the stage: tracking, then barriers.
  stateError(x, ref.x, ws.xError);
  ws.uError = u - ref.u;
  const Eigen::VectorXd& ex = ws.xError;
  const Eigen::VectorXd& eu = ws.uError;
  double cost = 0.5 * dt * (ex.dot(s.stateWeights.cwiseProduct(ex)) + eu.dot(s.inputWeights.cwiseProduct(eu)));
  if (matrices) {
    node->neq = row;
    node->A.setIdentity();
    node->A.noalias() += dt * ws.Ax;
    node->B.noalias() = dt * ws.Bu;
    node->Q = (dt * s.stateWeights).asDiagonal();
    node->R = (dt * s.inputWeights).asDiagonal();
    node->S.setZero();
  }
  if (node) {
    node->q = dt * s.stateWeights.cwiseProduct(ex);
    node->r = dt * s.inputWeights.cwiseProduct(eu);
  }
  // Stance points: friction cone and normal force bounds, on the point's 3 force entries.
  for (int c = 0; c < kNumContacts; ++c) {
    if (!ref.stance[c]) continue;
    const int i = L.force(c);
    const Eigen::Vector3d f = u.segment<3>(i);
    const RelaxedBarrier& b = s.frictionBarrier;
    auto barrier = [&](double h, const Eigen::Vector3d& grad) {  // h(f) ≥ 0, ∇h = grad
      cost += dt * b.value(h);
      if (!node) return;
      node->r.segment<3>(i) += dt * b.firstDerivative(h) * grad;
      if (matrices)
        node->R.block<3, 3>(i, i).noalias() += dt * b.secondDerivative(h) * grad * grad.transpose();
    };
    const double tangential = std::sqrt(f.x() * f.x() + f.y() * f.y() + s.frictionRegularization);
    barrier(s.frictionCoefficient * f.z() - tangential,
            Eigen::Vector3d(-f.x() / tangential, -f.y() / tangential, s.frictionCoefficient));
    barrier(f.z() - s.minNormalForce, Eigen::Vector3d::UnitZ());
    barrier(s.maxNormalForce - f.z(), -Eigen::Vector3d::UnitZ());
  }
  // Standing soles: |m| ≤ (w/2)(f_z,toe + f_z,heel), as f_z,toe + f_z,heel ∓ 2m/w ≥ 0 (N).
  for (int foot = 0; foot < 2; ++foot) {
    if (!standsOnSole(ref, foot)) continue;
    const std::array<int, 3> at{L.force(2 * foot) + 2, L.force(2 * foot + 1) + 2, soleMoment(foot)};
    const double normal = u[at[0]] + u[at[1]], lever = 2.0 / s.soleWidth;
    for (const double sign : {1.0, -1.0}) {
      const double h = normal - sign * lever * u[at[2]];
      const RelaxedBarrier& b = s.frictionBarrier;
      cost += dt * b.value(h);
      if (!node) continue;
      const std::array<double, 3> grad{1.0, 1.0, -sign * lever};
      const double d1 = dt * b.firstDerivative(h), d2 = dt * b.secondDerivative(h);
      for (int r = 0; r < 3; ++r) {
        node->r[at[r]] += d1 * grad[r];
        if (!matrices) continue;
        for (int c = 0; c < 3; ++c) node->R(at[r], at[c]) += d2 * grad[r] * grad[c];
      }
    }
  }
  // Joint position and velocity limits: each a scalar bound on one entry.
  auto bound = [&](double h, double sign, int index, bool onState,
                   const RelaxedBarrier& b) {
    cost += dt * b.value(h);
    if (!node) return;
    (onState ? node->q[index] : node->r[index]) += dt * b.firstDerivative(h) * sign;
    if (matrices)
      (onState ? node->Q(index, index) : node->R(index, index)) += dt * b.secondDerivative(h);
  };
  for (int j = 0; j < model_.nj(); ++j) {
    const double qj = x[L.kJoints + j];
    const double lo = model_.lowerPositionLimit[j] + s.jointLimitMargin;
    const double hi = model_.upperPositionLimit[j] - s.jointLimitMargin;
    if (std::isfinite(lo)) bound(qj - lo, 1.0, L.kJoints + j, true, s.limitBarrier);
    if (std::isfinite(hi)) bound(hi - qj, -1.0, L.kJoints + j, true, s.limitBarrier);
    if (s.jointStop.weight > 0.0) {
      if (std::isfinite(lo)) bound(qj - lo, 1.0, L.kJoints + j, true, s.jointStop);
      if (std::isfinite(hi)) bound(hi - qj, -1.0, L.kJoints + j, true, s.jointStop);
    }
    const double vj = u[L.jointVelocity() + j];
    const double vmax = model_.velocityLimit[j];
    bound(vmax - vj, -1.0, L.jointVelocity() + j, false, s.limitBarrier);
    bound(vj + vmax, 1.0, L.jointVelocity() + j, false, s.limitBarrier);
  }
  // Feet distance (eq. collsion): toe–toe and heel–heel.
  for (int pair = 0; pair < 2; ++pair) {
    const model::FrameKinematicsZyx& a = ws.contacts[pair];
    const model::FrameKinematicsZyx& b = ws.contacts[pair + 2];
    const Eigen::Vector3d diff = a.position - b.position;
    const double h = diff.squaredNorm() - s.minFeetDistance * s.minFeetDistance;
    cost += dt * s.collisionBarrier.value(h);
    if (!node) continue;
    // h depends on x and, through x_mid, on v_j: a Gauss-Newton term over (x, u).
    ws.gradX.noalias() = 2.0 * (a.dPosition_dx - b.dPosition_dx).transpose() * diff;
    ws.gradU.noalias() = 2.0 * (ws.dPosition_du[pair] - ws.dPosition_du[pair + 2]).transpose() * diff;
    const double d1 = dt * s.collisionBarrier.firstDerivative(h);
    const double d2 = dt * s.collisionBarrier.secondDerivative(h);
    node->q += d1 * ws.gradX;
    node->r += d1 * ws.gradU;
    if (!matrices) continue;
    node->Q.noalias() += d2 * ws.gradX * ws.gradX.transpose();
    node->S.noalias() += d2 * ws.gradU * ws.gradX.transpose();
    node->R.noalias() += d2 * ws.gradU * ws.gradU.transpose();
  }
  value.cost = cost;
  ws.matricesNode = node;
  ws.matricesStance = ref.stance;
  ws.matricesSettings = settingsVersion_;
}

double KinodynamicProblem::terminalCost(ProblemWorkspace& ws, const NodeReference& ref,
                                        const Eigen::VectorXd& x, LqNode* node) const {
  Eigen::VectorXd& e = static_cast<NodeWorkspace&>(ws).xError;
  stateError(x, ref.x, e);
  const Eigen::VectorXd& w = terminalWeights_;
  if (node) {
    node->setZero();
    node->Q = w.asDiagonal();
    node->q = w.cwiseProduct(e);
  }
  return 0.5 * e.dot(w.cwiseProduct(e));
}

}  // namespace ballast::mpc
