#include "gait/step_adjustment.hpp"

#include <algorithm>
#include <cmath>

namespace ballast::gait {

Eigen::Vector2d limitStep(const Eigen::Vector2d& target, const Eigen::Vector2d& stance, double yaw,
                          bool leftFoot, const StepLimits& limits) {
  Eigen::Vector2d d = toHeading(target - stance, yaw);  // forward, lateral
  d.x() = std::clamp(d.x(), -limits.maxBackward, limits.maxForward);
  const double side = leftFoot ? 1.0 : -1.0;
  d.y() = side * std::clamp(side * d.y(), limits.minWidth, limits.maxWidth);
  return stance + fromHeading(d, yaw);
}

namespace {

/// ξ carried from `xi` at `t` to `step`'s touch-down, the centre of pressure moving from `from`
/// onto `stance` until the lift-off. `stanceGain`, when given, is set to e − α: moving the stance
/// foot by δ moves ξ_td − stance by −(e − α) δ (e − α ≥ 1).
Eigen::Vector2d capturePointAtTouchDown(const CaptureStepInput& in, const Step& step,
                                        const Eigen::Vector2d& xi, const Eigen::Vector2d& from,
                                        const Eigen::Vector2d& stance, double t,
                                        double* stanceGain = nullptr) {
  const double dt = std::max(0.0, step.touchDown - t);
  const double ramp = std::clamp(step.liftOff - t, 0.0, dt);
  if (stanceGain) *stanceGain = std::exp(in.omega * dt) - rampWeight(in.omega, ramp, dt);
  return predictCapturePoint(xi, from, stance, in.omega, ramp, dt, in.forceOffset);
}

}  // namespace

void captureFootholds(const CaptureStepInput& in, Step* steps, int n) {
  // The periodic gait's offsets for the commanded velocity, heading frame.
  const Eigen::Vector2d advance = in.velocity * in.stepTime;
  const PeriodicOffsets b =
      periodicOffsets(advance + Eigen::Vector2d(0.0, in.width), advance - Eigen::Vector2d(0.0, in.width),
                      in.omega, in.stepTime, in.doubleSupportTime);
  const auto yawAt = [&](const Step& step) {
    return in.yaw + in.yawRate * (step.touchDown - in.t);
  };
  const auto target = [&](const Step& step, const Eigen::Vector2d& xiTd) -> Eigen::Vector2d {
    const Eigen::Vector2d& offset = step.left ? b.left : b.right;
    return xiTd - fromHeading(offset, yawAt(step));  // no + d: header comment
  };
  Eigen::Vector2d xi = in.capturePoint;
  Eigen::Vector2d left = in.leftFoot, right = in.rightFoot;
  double t = in.t;
  for (int k = 0; k < n; ++k) {
    Step& step = steps[k];
    const Eigen::Vector2d& stance = step.left ? right : left;
    const Eigen::Vector2d& lifting = step.left ? left : right;
    // Until the lift-off the centre of pressure moves onto the stance foot.
    Eigen::Vector2d from = lifting;
    if (k == 0 && in.doubleSupportTime > 0.0) {
      const double ramp = std::max(0.0, step.liftOff - t);
      from += std::clamp(1.0 - ramp / in.doubleSupportTime, 0.0, 1.0) * (stance - lifting);
    }
    xi = capturePointAtTouchDown(in, step, xi, from, stance, t);
    step.capturePoint = xi;
    step.limited = false;
    if (!step.fixed) {
      const Eigen::Vector2d wanted = target(step, xi);
      step.foothold = limitStep(wanted, stance, yawAt(step), step.left, in.limits);
      step.limited = (step.foothold - wanted).squaredNorm() > 1e-12;
      // One step ahead: where the next step (the other foot, from this foothold) would be held
      // to its limits by an excess Δ, this foothold moves by Δ/(e − α), which brings the next
      // step's target onto its limits, as far as this step's own limits allow.
      const Step* next = k + 1 < n ? &steps[k + 1] : nullptr;
      if (next && !next->fixed && next->left != step.left) {
        double gain = 0.0;
        const Eigen::Vector2d xiNext = capturePointAtTouchDown(in, *next, xi, stance, step.foothold,
                                                               std::max(t, step.touchDown), &gain);
        const Eigen::Vector2d nextWanted = target(*next, xiNext);
        const Eigen::Vector2d excess =
            nextWanted - limitStep(nextWanted, step.foothold, yawAt(*next), next->left, in.limits);
        if (excess.squaredNorm() > 1e-12 && gain > 1e-6)
          step.foothold =
              limitStep(step.foothold + excess / gain, stance, yawAt(step), step.left, in.limits);
      }
    }
    (step.left ? left : right) = step.foothold;
    t = std::max(t, step.touchDown);
  }
}

}  // namespace ballast::gait
