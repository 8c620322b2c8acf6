#include "mpc/single_rigid_body_problem.hpp"

#include "model/base_conventions.hpp"
#include "model/centroidal_dynamics.hpp"

namespace ballast::mpc {

using model::CentroidalLayout;

using model::skew;

SingleRigidBodyProblem::SingleRigidBodyProblem(const RigidBody& body, const ProblemSettings& settings)
    : body_(body),
      inertiaInverse_(body.inertia.inverse()),
      settings_(settings),
      terminalWeights_(settings.terminalWeightScale * settings.stateWeights) {}

void SingleRigidBodyProblem::dynamics(const NodeReference& ref, const Eigen::VectorXd& x,
                                      const Eigen::VectorXd& u, Eigen::Matrix<double, 12, 1>& xdot,
                                      Eigen::Matrix<double, 12, 12>& F,
                                      Eigen::Matrix<double, 12, 12>& G) const {
  const Eigen::Vector3d zyx = ref.x.segment<3>(CentroidalLayout::kBaseZyx);
  const Eigen::Matrix3d R = model::rotationFromZyx<double>(zyx);
  const Eigen::Vector3d offset = R * body_.com;  // c − p_b
  const Eigen::Vector3d com = ref.x.segment<3>(CentroidalLayout::kBasePosition) + offset;  // c*
  const Eigen::Matrix3d inertiaInverse = R * inertiaInverse_ * R.transpose();
  // E⁻¹ column by column (E does not depend on roll; closed form in base_conventions.hpp).
  Eigen::Matrix3d Einv;
  for (int k = 0; k < 3; ++k)
    Einv.col(k) = model::angularVelocityToZyxRate<double>(zyx, Eigen::Vector3d::Unit(k));

  F.setZero();
  G.setZero();
  for (int c = 0; c < kNumContacts; ++c) {
    G.block<3, 3>(0, 3 * c).setIdentity();
    G.block<3, 3>(3, 3 * c) = skew<double>(ref.contactPosition[c] - com);
  }
  F.block<3, 3>(CentroidalLayout::kBasePosition, 0) = Eigen::Matrix3d::Identity() / body_.mass;
  F.block<3, 3>(CentroidalLayout::kBasePosition, 3) = skew<double>(offset) * inertiaInverse;
  F.block<3, 3>(CentroidalLayout::kBaseZyx, 3) = Einv * inertiaInverse;
  xdot.setZero();
  xdot.head<3>() = body_.mass * body_.gravity + ref.externalForce;
  xdot.noalias() += G * u;
  xdot.noalias() += F * x;
}

void SingleRigidBodyProblem::evaluate(ProblemWorkspace& ws, const NodeReference& ref,
                                      const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                                      NodeValue& value) const {
  compute(static_cast<TrackingWorkspace&>(ws), ref, x, u, dt, nullptr, value);
}

void SingleRigidBodyProblem::linearize(ProblemWorkspace& ws, const NodeReference& ref,
                                       const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                       double dt, LqNode& node, NodeValue& value) const {
  compute(static_cast<TrackingWorkspace&>(ws), ref, x, u, dt, &node, value);
}

void SingleRigidBodyProblem::compute(TrackingWorkspace& ws, const NodeReference& ref,
                                     const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                                     LqNode* node, NodeValue& value) const {
  Eigen::Matrix<double, 12, 12> F, G;
  Eigen::Matrix<double, 12, 1> xdot;
  dynamics(ref, x, u, xdot, F, G);
  value.xdot = xdot;

  // Swing points carry no force.
  double eq2 = 0.0;
  int row = 0;
  for (int c = 0; c < kNumContacts; ++c) {
    if (ref.stance[c]) continue;
    const Eigen::Vector3d f = u.segment<3>(CentroidalLayout::force(c));
    eq2 += f.squaredNorm();
    if (node) {
      node->e.segment<3>(row) = f;
      node->C.middleRows<3>(row).setZero();
      node->D.middleRows<3>(row).setZero();
      node->D.block<3, 3>(row, CentroidalLayout::force(c)).setIdentity();
    }
    row += 3;
  }
  value.equalityNorm2 = eq2;
  if (node) {
    node->neq = row;
    node->A.setIdentity();
    node->A.noalias() += dt * F;
    node->B.noalias() = dt * G;
  }
  value.cost = trackingCost(settings_, ws, ref, x, u, dt, node) +
               contactForceBarriers(settings_, ref, u, dt, node);
}

double SingleRigidBodyProblem::terminalCost(ProblemWorkspace& ws, const NodeReference& ref,
                                            const Eigen::VectorXd& x, LqNode* node) const {
  return terminalTrackingCost(terminalWeights_, static_cast<TrackingWorkspace&>(ws), ref, x, node);
}

void SingleRigidBodyProblem::adaptInputToMode(const NodeReference& ref, const StanceFlags& before,
                                              Eigen::VectorXd& u) const {
  adaptForcesToMode(ref, before, u);
}

}  // namespace ballast::mpc
