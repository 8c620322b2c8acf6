#include "test/integration/daemon_stack/push_trial.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <stdexcept>

#include "model/centroidal_dynamics.hpp"
#include "model/data.hpp"
#include "model/forward_kinematics.hpp"
#include "model/frames.hpp"
#include "test/integration/daemon_stack/daemon_stack.hpp"

namespace ballast::test {
namespace {

/// One line of the trace: the true base, the estimated contacts and push, where the feet are
/// (the middle of each foot's contact points from the true base and the measured joints), and
/// in the plan in force each foot's next foothold (x, y, world) and its touch-down time, "-"
/// for a foot with no swing ahead in the plan, and the planned base roll and y now and 0.2 s on.
void traceLine(std::FILE* out, const DaemonStack& robot, const control::LoopStatus& s,
               bool pushing) {
  const control::BaseState& b = s.truth;
  const model::Model& m = robot.model();
  Eigen::VectorXd q(7 + m.nj());
  for (int i = 0; i < 3; ++i) q[i] = b.position[i];
  for (int i = 0; i < 4; ++i) q[3 + i] = b.orientation[i];
  for (int j = 0; j < m.nj(); ++j) q[7 + j] = j < s.num_joints ? s.q[j] : 0.0;
  model::Data<double> data(m);
  model::forwardKinematics(m, data, q);
  Eigen::Vector3d feet[2];
  double tilt[2];  // the sole's sideways tilt, rad (> 0: its left edge up)
  const auto& frames = robot.settings().locomotion.contactFrames;
  for (int foot = 0; foot < 2; ++foot) {
    const auto toe = model::framePlacement(m, data, m.frameId(frames[2 * foot]));
    feet[foot] = 0.5 * (toe.p + model::framePlacement(m, data, m.frameId(frames[2 * foot + 1])).p);
    tilt[foot] = std::asin(std::clamp(toe.R(2, 1), -1.0, 1.0));
  }
  std::fprintf(out,
               "%7.3f %-8s %s x %7.3f y %7.3f z %5.3f  vx %6.3f vy %6.3f  roll %6.3f pitch %6.3f "
               "yaw %6.3f  feet %d%d%d%d  f %6.1f %6.1f  L %6.3f %6.3f %5.3f %5.2f  R %6.3f %6.3f %5.3f %5.2f\n",
               s.t, control::modeName(s.mode), pushing ? "PUSH" : "    ", b.position[0],
               b.position[1], b.position[2], b.linear_velocity[0], b.linear_velocity[1], b.rpy[0],
               b.rpy[1], b.rpy[2], s.contacts[0], s.contacts[1], s.contacts[2], s.contacts[3],
               s.external_force[0], s.external_force[1], feet[0].x(), feet[0].y(), feet[0].z(),
               tilt[0], feet[1].x(), feet[1].y(), feet[1].z(), tilt[1]);
  const control::PlannerOutput& planned = robot.loop().plan();
  std::fprintf(out, "        next");
  for (int foot = 0; foot < 2; ++foot) {
    const gait::SwingPlanner& swings = planned.plan.swings;
    const int c = 2 * foot;  // toe and heel of a foot share its swing and its foothold
    const gait::SwingTrajectory* next = nullptr;
    for (int i = 0; planned.valid && i < swings.swingCount(c) && !next; ++i)
      if (swings.swing(c, i).touchDown > s.t) next = &swings.swing(c, i);
    if (next)
      std::fprintf(out, "  %s %7.3f %7.3f @ %7.3f", foot == 0 ? "L" : "R", next->foothold.x(),
                   next->foothold.y(), next->touchDown);
    else
      std::fprintf(out, "  %s -", foot == 0 ? "L" : "R");
  }
  // The plan's base roll and lateral position at the nodes nearest now and 0.2 s on.
  if (planned.valid && planned.plan.nodes > 0) {
    using L = model::CentroidalLayout;
    constexpr int kRoll = L::kBaseZyx + 2, kY = L::kBasePosition + 1;  // zyx = [yaw, pitch, roll]
    const locomotion::Plan& p = planned.plan;
    auto node = [&](double t) {
      return std::clamp(static_cast<int>(std::lround((t - p.t0) / p.dt)), 0, p.nodes);
    };
    const int k0 = node(s.t), k1 = node(s.t + 0.2);
    std::fprintf(out, "  plan roll %6.3f -> %6.3f  y %6.3f -> %6.3f", p.x[k0][kRoll],
                 p.x[k1][kRoll], p.x[k0][kY], p.x[k1][kY]);
  }
  std::fprintf(out, "\n");
  // Joints within 0.03 rad of a limit.
  for (int j = 0; j < m.nj() && j < s.num_joints; ++j) {
    const double lo = m.lowerPositionLimit[j], hi = m.upperPositionLimit[j];
    if (s.q[j] < lo + 0.03 || s.q[j] > hi - 0.03)
      std::fprintf(out, "        limit: %s %.3f [%.2f, %.2f]\n", m.jointName[j + 1].c_str(), s.q[j],
                   lo, hi);
  }
}

}  // namespace

PushOutcome runPushTrial(const PushTrial& trial) {
  DaemonStack robot(trial.profile);
  if (!robot.waitForMode(control::Mode::kStand, 5.0))
    throw std::runtime_error("the robot did not stand up");
  if (!robot.run(0.5)) throw std::runtime_error("the robot fell standing");
  const bool walking = trial.speed != 0.0;
  const double period = robot.settings().locomotion.walkGait.period;
  if (walking) {
    if (robot.walk(trial.speed, 0.0, trial.yawRate) != control::Refusal::kNone)
      throw std::runtime_error("walk refused");
  }
  const double t0 = robot.t();
  PushOutcome out;
  char line[512];
  const double pushAt =
      t0 + (walking ? trial.walkBefore + trial.phase * period : trial.standBefore);
  auto fell = [&](const char* when) {
    const control::LoopStatus s = robot.status();
    std::snprintf(line, sizeof line, "fell %s at t %.2f s (%.2f s after the push began)%s%s", when,
                  s.t, s.t - pushAt, s.faults.size > 0 ? ": " : "",
                  s.faults.size > 0 ? s.faults.fault[0].message : "");
    out.message = line;
    out.survived = false;
    return out;
  };
  // Up to the push, tracing as we go.
  const double step = trial.trace ? trial.tracePeriod : 0.02;
  while (robot.t() < pushAt - 1e-9) {
    if (!robot.run(std::min(step, pushAt - robot.t()))) return fell("before the push");
    if (trial.trace) traceLine(trial.trace, robot, robot.status(), false);
  }
  const double yaw = robot.status().truth.rpy[2];
  const double a = trial.directionDeg * M_PI / 180.0 + yaw;
  if (robot.push(trial.body.c_str(), trial.force * std::cos(a), trial.force * std::sin(a), 0.0,
                 trial.duration) != control::Refusal::kNone)
    throw std::runtime_error("push refused");
  const double pushStart = robot.t(), pushEnd = pushStart + trial.duration;
  const double end = pushEnd + trial.after;
  // Watch: every 20 ms (or trace period) the status; velocity over the last gait cycle from
  // positions.
  struct Sample {
    double t, x, y, yaw;
  };
  std::deque<Sample> window;
  bool lastContact[2] = {true, true};
  double backInStand = -1.0, velocityBack = -1.0;
  while (robot.t() < end - 1e-9) {
    if (!robot.run(std::min(step, end - robot.t()))) return fell("after the push");
    const control::LoopStatus s = robot.status();
    if (trial.trace) traceLine(trial.trace, robot, s, s.t < pushEnd);
    out.maxRoll = std::max(out.maxRoll, std::abs(s.truth.rpy[0]));
    for (int foot = 0; foot < 2; ++foot) {
      const bool down = s.contacts[2 * foot];
      if (down && !lastContact[foot]) ++out.touchDowns;
      lastContact[foot] = down;
    }
    if (!walking) {
      const bool stand = s.mode == control::Mode::kStand;
      if (!stand) out.leftStand = true;
      if (stand && backInStand < 0.0 && s.t >= pushEnd) backInStand = s.t - pushEnd;
      if (!stand) backInStand = -1.0;
      continue;
    }
    window.push_back({s.t, s.truth.position[0], s.truth.position[1], s.truth.rpy[2]});
    while (window.size() > 1 && window.front().t < s.t - period - 1e-6) window.pop_front();
    if (s.t < pushEnd + period - 1e-6 || window.front().t > s.t - period + 0.03) continue;
    const double dt = s.t - window.front().t;
    const double vx = (s.truth.position[0] - window.front().x) / dt;
    const double vy = (s.truth.position[1] - window.front().y) / dt;
    // Along and across the chord of the cycle's arc: the heading halfway through it.
    const double turned = std::remainder(s.truth.rpy[2] - window.front().yaw, 2.0 * M_PI);
    const double chordYaw = window.front().yaw + 0.5 * turned;
    const double c = std::cos(chordYaw), sn = std::sin(chordYaw);
    const double forward = c * vx + sn * vy, lateral = -sn * vx + c * vy;
    const double half = 0.5 * trial.yawRate * dt;
    const double chordSpeed =
        std::abs(half) > 1e-9 ? trial.speed * std::sin(half) / half : trial.speed;
    const bool back = std::abs(forward - chordSpeed) <= 0.1 && std::abs(lateral) <= 0.1;
    if (back && velocityBack < 0.0) velocityBack = s.t - pushEnd;
    if (!back) velocityBack = -1.0;
  }
  const control::LoopStatus s = robot.status();
  if (walking) {
    out.recoveryTime = velocityBack;
    out.survived = s.mode == control::Mode::kWalk;
    std::snprintf(line, sizeof line, "%s; velocity back %s%.2f s after the push; roll up to %.2f rad",
                  out.survived ? "walking" : control::modeName(s.mode),
                  velocityBack < 0 ? "never (" : "", velocityBack < 0 ? trial.after : velocityBack,
                  out.maxRoll);
    out.message = line;
    if (velocityBack < 0) out.message += ")";
  } else {
    out.recoveryTime = backInStand;
    out.survived = s.mode == control::Mode::kStand;
    std::snprintf(line, sizeof line, "%s, %d touch-downs, %s%.2f s after the push",
                  control::modeName(s.mode), out.touchDowns,
                  out.leftStand ? "back in stand " : "never left stand; ",
                  backInStand < 0 ? -1.0 : backInStand);
    out.message = line;
  }
  return out;
}

UnpushedPeak unpushedPeak(const std::string& profile, double speed, double settle, double seconds) {
  DaemonStack robot(profile);
  if (!robot.waitForMode(control::Mode::kStand, 5.0))
    throw std::runtime_error("the robot did not stand up");
  UnpushedPeak out;
  out.pushSwitch = robot.settings().locomotion.recovery.walkingPushForce(robot.model().totalMass());
  if (!robot.run(0.5) || robot.walk(speed) != control::Refusal::kNone) return out;
  if (!robot.run(settle)) return out;
  const double end = robot.t() + seconds;
  while (robot.t() < end - 1e-9) {
    if (!robot.run(0.001)) return out;
    const estimation::EstimatorOutput& e = robot.loop().estimator().filterOutput();
    out.raw = std::max(out.raw, e.externalForceRaw.head<2>().norm());
    out.reported = std::max(out.reported, e.externalForce.head<2>().norm());
  }
  out.walked = true;
  return out;
}

}  // namespace ballast::test

