#include "gait/swing_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ballast::gait {

SwingPlanner::SwingPlanner(const SwingPlannerParameters& params,
                           const std::array<Eigen::Vector3d, kNumContacts>& nominalOffsets)
    : params_(params), nominalOffsets_(nominalOffsets) {
  for (auto& p : stance_) p.setZero();
}

Eigen::Vector3d SwingPlanner::keepFeetApart(int contact, const Eigen::Vector3d& foothold,
                                            double yaw, const GaitState& state) const {
  // The other foot's point at the same place along the foot (toe with toe, heel with heel).
  const int other = (contact + 2) % kNumContacts;
  const Eigen::Vector3d d = foothold - state.contactPositions[other];
  const double lateral = toHeading(d.head<2>(), yaw).y();  // left of the other point
  const double side = isLeft(contact) ? 1.0 : -1.0;
  const double shortfall = params_.minFeetDistance - side * lateral;
  if (shortfall <= 0.0) return foothold;
  Eigen::Vector3d left = Eigen::Vector3d::Zero();
  left.head<2>() = fromHeading(Eigen::Vector2d::UnitY(), yaw);
  return foothold + side * shortfall * left;
}

Eigen::Vector2d SwingPlanner::placeOnFoot(int contact, double yaw) const {
  const Eigen::Vector3d centre = 0.5 * (nominalOffsets_[isLeft(contact) ? kLeftToe : kRightToe] +
                                        nominalOffsets_[isLeft(contact) ? kLeftHeel : kRightHeel]);
  const Eigen::Vector3d local = nominalOffsets_[contact] - centre;
  return fromHeading(local.head<2>(), yaw);
}

double SwingPlanner::omega() const {
  return pendulumFrequency(params_.foothold.comHeight, params_.foothold.gravity);
}

void SwingPlanner::planSteps(const ContactSchedule& schedule, const GaitState& state,
                             const VelocityCommand& command, double until) {
  numSteps_ = 0;
  for (int foot = 0; foot < 2; ++foot) {
    const int toe = foot == 0 ? kLeftToe : kRightToe;
    SwingInterval interval;
    double from = state.t;
    for (int n = 0; n < kMaxSwings && schedule.swingAround(toe, from, until, interval); ++n) {
      Step& step = steps_[numSteps_++];
      step = Step{};
      step.left = foot == 0;
      step.liftOff = interval.liftOff;
      step.touchDown = interval.touchDown;
      const bool started = interval.liftOff <= state.t;
      const double progress = (state.t - interval.liftOff) / (interval.touchDown - interval.liftOff);
      for (int i = 0; i < count_[toe]; ++i)
        if (std::abs(swings_[toe][i].liftOff - interval.liftOff) < 1e-6 && started &&
            progress > params_.replanUntil) {
          step.fixed = true;
          step.foothold = swings_[toe][i].foothold;
        }
      from = interval.touchDown + 1e-6;
    }
  }
  std::sort(steps_.begin(), steps_.begin() + numSteps_,
            [](const Step& a, const Step& b) { return a.touchDown < b.touchDown; });
  if (numSteps_ == 0) return;
  const double w = omega();
  CaptureStepInput in;
  in.t = state.t;
  in.omega = w;
  in.capturePoint = capturePoint(state.com.head<2>(), state.comVelocity.head<2>(), w);
  in.forceOffset = forceOffset(state.externalForce.head<2>(), state.mass, w);
  const auto& p = state.contactPositions;
  in.leftFoot = 0.5 * (p[kLeftToe] + p[kLeftHeel]).head<2>();
  in.rightFoot = 0.5 * (p[kRightToe] + p[kRightHeel]).head<2>();
  in.yaw = state.base.yaw;
  in.yawRate = command.yawRate;
  in.velocity = Eigen::Vector2d(command.vx, command.vy);
  const auto& o = nominalOffsets_;
  in.width = 0.5 * (o[kLeftToe] + o[kLeftHeel] - o[kRightToe] - o[kRightHeel]).y();
  const Gait& walkGait = schedule.gaitAt(steps_[0].touchDown - 1e-6);
  in.stepTime = 0.5 * walkGait.period;
  in.doubleSupportTime = in.stepTime - walkGait.swingDuration();
  in.limits = params_.limits;
  in.limits.minWidth = params_.minFeetDistance;
  captureFootholds(in, steps_.data(), numSteps_);
  for (int k = 0; k < std::min(numSteps_, 2); ++k) stepsLimited_ |= steps_[k].limited;
}

Eigen::Vector3d SwingPlanner::footOffset(int contact, double touchDown, const PlanarPose& base,
                                         const GaitState& state, const Eigen::Vector3d& vDesired,
                                         double yawRate, double stance,
                                         const TerrainQuery& terrain) {
  if (!params_.search.enabled) return Eigen::Vector3d::Zero();
  const int foot = isLeft(contact) ? 0 : 1;
  auto& known = footOffsets_[foot];
  for (int i = 0; i < footOffsetCount_[foot]; ++i)
    if (std::abs(known[i].touchDown - touchDown) < 1e-6) return known[i].offset;
  // The foot's toe and heel by the paper's rule, the same for either point's swing.
  const int toe = contact & ~1, heel = toe + 1;  // kLeftToe, kLeftHeel / kRightToe, kRightHeel
  const auto paper = [&](int c) {
    return raibertFoothold(base, nominalOffsets_[c], state.comVelocity, vDesired, yawRate, stance,
                           params_.foothold, terrain);
  };
  const Eigen::Vector3d paperToe = paper(toe), paperHeel = paper(heel);
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  bool kept = false;
  // Where the last update put this touch-down's foot, while it is still good, supported and in
  // the window: the paper's foothold moves a little every update, and the nearest good place
  // to it can jump from one side of a patch to another and back within a few updates, which
  // throws the swinging foot.
  for (int i = 0; i < previousOffsetCount_[foot] && !kept; ++i) {
    const FootOffset& last = previousOffsets_[foot][i];
    if (std::abs(last.touchDown - touchDown) >= 1e-6 || last.offset.isZero()) continue;
    Eigen::Vector3d d = last.toe - paperToe;
    d.z() = 0.0;
    if (d.norm() <= searchRadius(paperToe, paperHeel, params_.search) &&
        goodPlacement(paperToe, paperHeel, d.x(), d.y(), terrain, params_.search) &&
        supported(paperToe, paperHeel, d.x(), d.y(), terrain, params_.search)) {
      offset = d;
      kept = true;
    }
  }
  if (!kept) offset = footholdOffset(paperToe, paperHeel, terrain, params_.search);
  if (footOffsetCount_[foot] < kMaxSwings)
    known[footOffsetCount_[foot]++] = {touchDown, offset, paperToe + offset};
  return offset;
}

void SwingPlanner::update(const ContactSchedule& schedule, const GaitState& state,
                          const VelocityCommand& command, double horizon,
                          const TerrainQuery& terrain) {
  const double until = state.t + horizon;
  Eigen::Vector3d vDesired = Eigen::Vector3d::Zero();
  vDesired.head<2>() = fromHeading(Eigen::Vector2d(command.vx, command.vy), state.base.yaw);
  const bool capture = params_.rule == FootholdRule::kCapturePoint;
  stepsLimited_ = false;
  if (capture) planSteps(schedule, state, command, until);
  previousOffsets_ = footOffsets_;
  previousOffsetCount_ = footOffsetCount_;
  footOffsetCount_.fill(0);
  for (int c = 0; c < kNumContacts; ++c) {
    std::array<SwingTrajectory, kMaxSwings> previous = swings_[c];
    const int previousCount = count_[c];
    if (schedule.inStance(c, state.t)) stance_[c] = state.contactPositions[c];

    Eigen::Vector3d start = state.contactPositions[c];
    int n = 0;
    SwingInterval interval;
    double from = state.t;
    while (n < kMaxSwings && schedule.swingAround(c, from, until, interval)) {
      SwingTrajectory s;
      s.liftOff = interval.liftOff;
      s.touchDown = interval.touchDown;
      s.liftOffPosition = start;
      const SwingTrajectory* kept = nullptr;
      for (int i = 0; i < previousCount; ++i)
        if (std::abs(previous[i].liftOff - s.liftOff) < 1e-6) kept = &previous[i];
      const bool started = s.liftOff <= state.t;
      if (kept && started) s.liftOffPosition = kept->liftOffPosition;

      const double progress = (state.t - s.liftOff) / (s.touchDown - s.liftOff);
      if (kept && started && progress > params_.replanUntil) {
        s.touchDownPosition = kept->touchDownPosition;
        s.foothold = kept->foothold;
        s.moveFrom = kept->moveFrom;
        s.movePosition = kept->movePosition;
        s.moveVelocity = kept->moveVelocity;
      } else {
        const Eigen::Vector2d onFoot =
            placeOnFoot(c, state.base.yaw + command.yawRate * (s.touchDown - state.t));
        const WalkingPushAxis& push = params_.walkingPush;
        const bool blend = capture && push.paperAcross > 0.0;
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        if (!capture || blend) {
          const PlanarPose base = state.base.predicted(command, s.touchDown - state.t);
          const double stance = schedule.gaitAt(s.touchDown).stanceDuration();
          // The centre of mass's velocity, not the base's: what the step has to catch is the
          // centre of mass, and with heavy limbs the pelvis swings against it within a step (by
          // most of its velocity in a stop from 1 m/s).
          p = raibertFoothold(base, nominalOffsets_[c], state.comVelocity, vDesired,
                              command.yawRate, stance, params_.foothold, terrain);
          p += footOffset(c, s.touchDown, base, state, vDesired, command.yawRate, stance, terrain);
          p = keepFeetApart(c, p, base.yaw, state);
        }
        if (capture) {
          // The foot's foothold from step adjustment; this point's place on the foot.
          const Step* step = nullptr;
          for (int k = 0; k < numSteps_; ++k)
            if (steps_[k].left == isLeft(c) &&
                (!step || std::abs(steps_[k].touchDown - s.touchDown) <
                              std::abs(step->touchDown - s.touchDown)))
              step = &steps_[k];
          s.foothold = step ? step->foothold : Eigen::Vector2d(s.liftOffPosition.head<2>());
          if (blend) {
            const Eigen::Vector2d d = p.head<2>() - onFoot - s.foothold;
            s.foothold += push.paperAcross * (d - push.axis * push.axis.dot(d));
          }
          p.head<2>() = s.foothold + onFoot;
        } else {
          // The foot's centre where this point lands: when the capture point's rule takes over
          // (the walking push switch) while this swing is held, its next step starts from here.
          s.foothold = p.head<2>() - onFoot;
        }
        p.z() = terrain.height(p.x(), p.y());
        s.touchDownPosition = p;
      }
      // A swing re-aimed on its way moves on from where its reference is now (capture point
      // rule; the paper's swings keep their one cubic from lift-off).
      if (capture && kept && started && !(progress > params_.replanUntil) &&
          state.t > kept->moveStart()) {
        const PointReference now = kept->at(state.t);
        s.moveFrom = state.t;
        s.movePosition = now.position;
        s.moveVelocity = now.velocity;
        s.movePosition.z() = s.moveVelocity.z() = 0.0;
      }
      // The ground under the sole's whole width: the point's path and its parallels `patch` to
      // either side (the foothold search's margin around a point). A toe whose own line ran on a
      // low patch beside a 4 cm one started forward flat, its sole's side caught the higher
      // patch's edge and the foot pitched over it (rough ground in real time: a fall).
      const Eigen::Vector2d up = s.liftOffPosition.head<2>(), down = s.touchDownPosition.head<2>();
      const Eigen::Vector2d path = down - up;
      const Eigen::Vector2d side =
          params_.search.patch * (path.norm() > 1e-6 ? Eigen::Vector2d(-path.y(), path.x()) / path.norm()
                                                     : Eigen::Vector2d(0.0, 1.0));
      s.apexHeight = -std::numeric_limits<double>::infinity();
      for (const double k : {-1.0, 0.0, 1.0}) {
        const Eigen::Vector2d a = up + k * side, b = down + k * side;
        s.apexHeight = std::max(s.apexHeight, terrain.maxHeightAlong(a.x(), a.y(), b.x(), b.y()));
      }
      const double highest = std::max({s.apexHeight, s.liftOffPosition.z(), s.touchDownPosition.z()});
      const double lowest = std::min(s.liftOffPosition.z(), s.touchDownPosition.z());
      s.lift = highest - lowest > params_.stepHeight ? params_.stepLift : 0.0;
      s.apexHeight = highest + params_.apexClearance;
      swings_[c][n++] = s;
      start = s.touchDownPosition;
      from = s.touchDown + 1e-6;
    }
    count_[c] = n;
  }
}

double SwingPlanner::longestNextSwing(double t) const {
  double longest = 0.0;
  for (const int toe : {kLeftToe, kRightToe})
    for (int i = 0; i < count_[toe]; ++i) {
      const SwingTrajectory& s = swings_[toe][i];
      if (s.liftOff <= t) continue;
      longest = std::max(longest, (s.touchDownPosition - s.liftOffPosition).head<2>().norm());
      break;
    }
  return longest;
}

const SwingTrajectory* SwingPlanner::swingAt(int contact, double t) const {
  for (int i = 0; i < count_[contact]; ++i) {
    const SwingTrajectory& s = swings_[contact][i];
    if (t >= s.liftOff && t < s.touchDown) return &s;
  }
  return nullptr;
}

PointReference SwingPlanner::reference(int contact, double t) const {
  if (const SwingTrajectory* s = swingAt(contact, t)) return s->at(t);
  PointReference r;
  r.position = stance_[contact];
  for (int i = 0; i < count_[contact]; ++i)  // landed by t: the last touch-down before it
    if (swings_[contact][i].touchDown <= t) r.position = swings_[contact][i].touchDownPosition;
  return r;
}

}  // namespace ballast::gait
