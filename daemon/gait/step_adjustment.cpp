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

void captureFootholds(const CaptureStepInput& in, Step* steps, int n) {
  // The periodic gait's offsets for the commanded velocity, heading frame.
  const Eigen::Vector2d advance = in.velocity * in.stepTime;
  const PeriodicOffsets b =
      periodicOffsets(advance + Eigen::Vector2d(0.0, in.width), advance - Eigen::Vector2d(0.0, in.width),
                      in.omega, in.stepTime, in.doubleSupportTime);
  Eigen::Vector2d xi = in.capturePoint;
  Eigen::Vector2d left = in.leftFoot, right = in.rightFoot;
  double t = in.t;
  for (int k = 0; k < n; ++k) {
    Step& step = steps[k];
    const Eigen::Vector2d& stance = step.left ? right : left;
    const Eigen::Vector2d& lifting = step.left ? left : right;
    const double dt = std::max(0.0, step.touchDown - t);
    // Until the lift-off the centre of pressure moves onto the stance foot.
    const double ramp = std::max(0.0, step.liftOff - t);
    Eigen::Vector2d from = lifting;
    if (k == 0 && in.doubleSupportTime > 0.0)
      from += std::clamp(1.0 - ramp / in.doubleSupportTime, 0.0, 1.0) * (stance - lifting);
    xi = predictCapturePoint(xi, from, stance, in.omega, ramp, dt, in.forceOffset);
    step.capturePoint = xi;
    step.limited = false;
    if (!step.fixed) {
      const double yaw = in.yaw + in.yawRate * (step.touchDown - in.t);
      const Eigen::Vector2d& offset = step.left ? b.left : b.right;
      const Eigen::Vector2d target = xi - fromHeading(offset, yaw);  // no + d: header comment
      step.foothold = limitStep(target, stance, yaw, step.left, in.limits);
      step.limited = (step.foothold - target).squaredNorm() > 1e-12;
    }
    (step.left ? left : right) = step.foothold;
    t = std::max(t, step.touchDown);
  }
}

}  // namespace ballast::gait
