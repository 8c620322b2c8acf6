// Step adjustment: footholds from the capture point (capture_point.hpp), the steps of the
// horizon in order, each within the robot's reach of the foot it steps from.
//
// For the steps ahead (foot, lift-off and touch-down times), from the capture point ξ now:
//   stance  = the other foot: its foothold if it steps earlier in the sequence, else where it is
//   ξ_td    = ξ carried from the previous touch-down (or now) to this one with the centre of
//             pressure moving from the lifting foot to the stance foot until the lift-off (the
//             double support) and on the stance foot after it (capture_point.hpp); now, within a
//             double support, the centre of pressure is taken as far along as its time is
//   foothold = ξ_td − R(ψ_td)·b_foot                                 (b: the periodic gait's
//             capture-point offset for the commanded velocity)
//   limited to the reach of the leg from the stance foot (StepLimits, in the heading frame at the
//   touch-down: forward/backward, and sideways between the feet distance and the widest step);
//   one step ahead: if the next step's foothold, planned from this one, would be held to its
//   limits by an excess Δ, this foothold moves by Δ/(e − α) (the next step's ξ_td − p_stance
//   changes by −(e − α) per metre the stance foot moves; e, α of the next step's interval),
//   within this step's own limits (`limited` says whether those held the target itself). A
//   push towards the stance foot's side while the other foot swings (the swinging foot must
//   land beside the stance foot, then the stance foot step out in the push's direction) lands
//   the swinging foot nearer the stance foot, so the step out is within reach;
//   then ξ goes on from ξ_td about the new foot.
// A step already fixed (a swing past its replanning point) keeps its foothold and the sequence
// goes on from it. With nothing disturbing the robot (ξ on its periodic orbit), the footholds are
// the periodic gait's: the commanded velocity, the nominal width. A push moves ξ, and the next
// foothold moves with it by e^{ωΔt}: deadbeat in the pendulum model (the paper's velocity
// feedback k (v − v_des), k = 0.15 s, is about a quarter of that at touch-down).
// A push (its offset d = f/(m ω²)) carries ξ until each touch-down (ξ_td above), but the
// foothold is not moved on by d, where the centre of pressure would hold ξ still against the
// push after the landing: that bets on the push outlasting the step, and a push that ends within
// the swing leaves the foot d further ahead of a body no longer pushed (standing, 60 N for 1 s
// along +x: steps 0.41 m apart and a fall). Each step is planned again on the push as it is
// then, so a push that lasts is followed step by step.
//
// Footholds here are foot reference points (the middle of a foot's contact points), world x, y.
// ψ_td is the heading at the touch-down: the heading now advanced by the commanded yaw rate.
#pragma once

#include <Eigen/Core>
#include <array>

#include "gait/capture_point.hpp"

namespace ballast::gait {

/// Reach of a step from the stance foot, heading frame (m). The swing foot lands at most
/// maxForward ahead of and maxBackward behind the stance foot, and sideways (towards its own
/// side) at least minWidth (the feet-distance constraint, eq. collsion) and at most maxWidth.
struct StepLimits {
  double maxForward = 0.5;
  double maxBackward = 0.35;
  double minWidth = 0.12;
  double maxWidth = 0.45;
};

/// `target` moved into the reach of a step of the left (or right) foot from `stance`, heading
/// yaw. Returns the limited foothold.
Eigen::Vector2d limitStep(const Eigen::Vector2d& target, const Eigen::Vector2d& stance, double yaw,
                          bool leftFoot, const StepLimits& limits);

/// One step of the sequence.
struct Step {
  bool left = true;       ///< the left foot lands
  double liftOff = 0.0;   ///< s, controller time
  double touchDown = 0.0; ///< s, controller time
  bool fixed = false;     ///< foothold already chosen (held): kept
  Eigen::Vector2d foothold = Eigen::Vector2d::Zero();  ///< in: when fixed; out: the foothold
  Eigen::Vector2d capturePoint = Eigen::Vector2d::Zero();  ///< out: predicted ξ at touch-down
  bool limited = false;   ///< out: the reach limits moved the foothold
};

struct CaptureStepInput {
  double t = 0.0;                                      ///< now
  double omega = 3.4;                                  ///< 1/s
  Eigen::Vector2d capturePoint = Eigen::Vector2d::Zero();  ///< ξ now, world
  Eigen::Vector2d forceOffset = Eigen::Vector2d::Zero();   ///< d, world
  Eigen::Vector2d leftFoot = Eigen::Vector2d::Zero();      ///< foot reference points now, world
  Eigen::Vector2d rightFoot = Eigen::Vector2d::Zero();
  double yaw = 0.0;        ///< heading now
  double yawRate = 0.0;    ///< commanded, rad/s
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< commanded, heading frame, m/s
  double width = 0.2;      ///< nominal lateral distance between the feet, m
  double stepTime = 0.4;   ///< s from one touch-down to the next
  double doubleSupportTime = 0.08;  ///< s of each step with both feet down
  StepLimits limits;
};


/// Footholds for steps[0..n) (in touch-down order) by the rule of the header comment.
void captureFootholds(const CaptureStepInput& in, Step* steps, int n);

}  // namespace ballast::gait
