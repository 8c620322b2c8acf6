// A planner seated in a control loop for one scope: the loop's planner thread stops (and the
// seat empties) before the planner, declared before this guard, is destroyed. In lockstep the
// planner answers while the loop ticks on, so a planner that went out of scope with the loop
// alive would be planning in freed memory.
#pragma once

#include "control/control_loop.hpp"

namespace ballast::control {

class AttachedPlanner {
 public:
  AttachedPlanner(ControlLoop& loop, Planner& planner) : loop_(loop) { loop.attachPlanner(&planner); }
  ~AttachedPlanner() { loop_.detachPlanner(); }
  AttachedPlanner(const AttachedPlanner&) = delete;
  AttachedPlanner& operator=(const AttachedPlanner&) = delete;

 private:
  ControlLoop& loop_;
};

}  // namespace ballast::control
