// The locomotion plan at one instant, as the whole-body controller's references (paper Fig. 4:
// MPC -> WBC). Pure data mapping, no allocation:
//   stance flags            -> WbcReference::stance
//   swing/stance references -> contact position, velocity, acceleration (world)
//   base pose and twist     -> base references (world-aligned), ZYX -> quaternion
//   base acceleration       -> (twist at t + h − twist at t) / h from the plan itself, so the
//                              controller feeds forward what the plan's trajectory asks for
//   joints (x*, v_j*)       -> joint references (the arms' tracking task); acceleration likewise
//   contact forces (u*)     -> contact force references (world)
#pragma once

#include "locomotion/plan.hpp"
#include "wbc/interface.hpp"

namespace ballast::control {

/// Fills `out` from the plan sampled at t (`now`) and at t + h (`ahead`), h > 0 in seconds.
/// nj joints; out must be sized by WholeBodyController::makeReference().
void planToWbcReference(const locomotion::PlanSample& now, const locomotion::PlanSample& ahead,
                        double h, int nj, wbc::WbcReference& out);

}  // namespace ballast::control
