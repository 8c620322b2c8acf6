// One push trial on a fresh robot (DaemonStack, lockstep): stand up, walk at `speed` (turning at
// `yawRate`; or keep standing), push for `duration` s at `phase` of the gait cycle, watch `after` s
// more. Shared by the push tests (push_test.cpp) and ballast-push-map.
//
// Frames: the push direction is in the robot's heading frame at the push (0 deg: forward, 90:
// left); the force is applied in the world frame along it, on `body` (a URDF link) at its origin.
#pragma once

#include <cstdio>
#include <string>

namespace ballast::test {

struct PushTrial {
  std::string profile;        ///< path
  double speed = 0.5;         ///< m/s forward; 0: standing
  double yawRate = 0.0;       ///< rad/s, walking: the turn the push lands in
  double directionDeg = 0.0;  ///< heading frame
  double phase = 0.0;         ///< fraction of the gait cycle (walking) at which the push starts
  double force = 60.0;        ///< N
  double duration = 1.0;      ///< s
  double after = 4.0;         ///< s watched after the push ends
  double walkBefore = 4.0;    ///< s walked before the cycle the push lands in
  double standBefore = 1.0;   ///< standing: s from 0.5 s after `stand` to the push
  std::string body = "torso";
  std::FILE* trace = nullptr;  ///< the state every tracePeriod, when set
  double tracePeriod = 0.02;   ///< s (0.001 for every tick)
};

struct PushOutcome {
  bool survived = false;  ///< no fall, no damp; standing: back in stand at the end
  std::string message;    ///< one line: what happened
  /// Walking: s after the push's end until the mean velocity over a gait cycle stays within
  /// 0.1 m/s of the command (each component, along and across the chord of the cycle's path:
  /// the heading half-way through the cycle; turning, the chord's speed is the command's times
  /// sin(ωT/2)/(ωT/2)); -1 if it never did. Standing: s
  /// after the push's end until the robot is back in stand for good; -1 if it is not.
  double recoveryTime = -1.0;
  bool leftStand = false;  ///< standing: the robot stepped (mode recover)
  int touchDowns = 0;      ///< standing: foot touch-downs after the push started
  double maxRoll = 0.0;    ///< largest |roll| of the base (truth) from the push on, rad
};

/// Throws std::runtime_error when the robot cannot be set up (stand-up, walk refused).
PushOutcome runPushTrial(const PushTrial& trial);

/// Walking with no push: the largest horizontal external force the state estimator reads.
struct UnpushedPeak {
  bool walked = false;  ///< no fall, no damp
  double raw = 0.0;     ///< N, horizontal, before the deadband (EstimatorOutput::externalForceRaw)
  double reported = 0.0;  ///< N, past the deadband (what the planner's push switch compares)
  double pushSwitch = 0.0;  ///< N, the walking push switch (gait.recovery_walking_force × mass)
};
/// Stand up, walk at `speed` (m/s forward), ignore the first `settle` s, watch `seconds` more.
UnpushedPeak unpushedPeak(const std::string& profile, double speed, double settle, double seconds);

}  // namespace ballast::test
