// The operating modes and what moves the robot between them (DESIGN.md, "Modes"):
//
//   passive --stand--> stand-up --(stand_up_duration)--> stand <--walk/stop/TTL--> walk
//   stand <--the planner's recovery steps (a push)--> recover --walk--> walk
//   any fault (backend, NaN, fall) --> damp          estop --> damp, latched
//   damp --reset--> passive                            passive: zero torque, on request
//
// Pure logic on plain values: the loop feeds it operator commands, faults and the time, and
// reads the mode and the base command in force. Durations and TTLs are controller time.
// A refusal comes with a message that says what to do next.
#pragma once

#include "control/settings.hpp"
#include "control/types.hpp"

namespace ballast::control {

/// What the loop knows when a command arrives.
struct Situation {
  bool fallen = false;
  bool planner_available = false;
  bool push_available = false;
};

class ModeMachine {
 public:
  /// Limits and durations from the settings; nominal_height is the base height of the nominal
  /// posture, the pose a plain `stand` or `pose` without height returns to.
  void configure(const ControlSettings& settings, double nominal_height);
  void start(Mode initial, double t);

  Mode mode() const { return mode_; }
  bool estopLatched() const { return estop_; }
  const FaultList& faults() const { return faults_; }
  const BaseCommand& command() const { return command_; }
  /// 0..1 through stand-up (1 outside it).
  double standUpProgress(double t) const;
  double standUpStart() const { return stand_up_start_; }

  /// Applies an operator command (not kSwitchSettings, not kPush: the loop does those).
  /// Returns kNone on success; otherwise message says why and what to do.
  Refusal handle(const OperatorCommand& command, double t, const Situation& situation,
                 char (&message)[kMessageLength]);

  /// A fault: damp (and remember it until reset). True if this kind of fault is new.
  bool fault(FaultKind kind, double t, const char* message);
  /// The planner steps to recover from a push while standing (stand -> recover), or has
  /// stopped (recover -> stand). Other modes are left as they are.
  void recovering(bool stepping, double t);
  /// Time passes: a stand-up completes, a velocity command expires.
  void update(double t);
  /// Shutdown: damp without latching anything.
  void damp() { mode_ = Mode::kDamp; }

 private:
  void setMode(Mode mode, double t);
  Refusal checkPose(const OperatorCommand& c, char (&message)[kMessageLength]) const;

  const ControlSettings* settings_ = nullptr;
  double nominal_height_ = 0.0;
  Mode mode_ = Mode::kPassive;
  bool estop_ = false;
  FaultList faults_;
  BaseCommand command_;
  double stand_up_start_ = 0.0;
};

}  // namespace ballast::control
