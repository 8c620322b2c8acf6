#include "control/plan_reference.hpp"

#include "model/base_conventions.hpp"

namespace ballast::control {

void planToWbcReference(const locomotion::PlanSample& now, const locomotion::PlanSample& ahead,
                        double h, int nj, wbc::WbcReference& out) {
  for (int c = 0; c < locomotion::kNumContacts; ++c) {
    out.stance[c] = now.stance[c];
    out.contactPosition.col(c) = now.contact[c].position;
    out.contactVelocity.col(c) = now.contact[c].velocity;
    out.contactAcceleration.col(c) = now.contact[c].acceleration;
    out.contactForce.segment<3>(3 * c) = now.contactForce[c];
  }
  out.basePosition = now.basePosition;
  out.baseOrientation = Eigen::Quaterniond(model::rotationFromZyx<double>(now.baseZyx));
  out.baseLinearVelocity = now.baseLinearVelocity;
  out.baseAngularVelocity = now.baseAngularVelocity;
  out.baseLinearAcceleration = (ahead.baseLinearVelocity - now.baseLinearVelocity) / h;
  out.baseAngularAcceleration = (ahead.baseAngularVelocity - now.baseAngularVelocity) / h;
  for (int j = 0; j < nj; ++j) {
    out.jointPosition[j] = now.jointPositions[j];
    out.jointVelocity[j] = now.jointVelocities[j];
    out.jointAcceleration[j] = (ahead.jointVelocities[j] - now.jointVelocities[j]) / h;
  }
}

}  // namespace ballast::control
