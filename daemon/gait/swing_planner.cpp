#include "gait/swing_planner.hpp"

#include <cmath>

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
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const Eigen::Vector3d d = foothold - state.contactPositions[other];
  const double lateral = -sy * d.x() + cy * d.y();  // left of the other point, heading frame
  const double side = isLeft(contact) ? 1.0 : -1.0;
  const double shortfall = params_.minFeetDistance - side * lateral;
  if (shortfall <= 0.0) return foothold;
  return foothold + side * shortfall * Eigen::Vector3d(-sy, cy, 0.0);
}

void SwingPlanner::update(const ContactSchedule& schedule, const GaitState& state,
                          const VelocityCommand& command, double horizon,
                          const TerrainQuery& terrain) {
  const double until = state.t + horizon;
  const double cy = std::cos(state.base.yaw), sy = std::sin(state.base.yaw);
  const Eigen::Vector3d vDesired(cy * command.vx - sy * command.vy, sy * command.vx + cy * command.vy,
                                 0.0);
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
      } else {
        const PlanarPose base = state.base.predicted(command, s.touchDown - state.t);
        const double stance = schedule.gaitAt(s.touchDown).stanceDuration();
        Eigen::Vector3d p = raibertFoothold(base, nominalOffsets_[c], state.baseVelocity, vDesired,
                                            command.yawRate, stance, params_.foothold, terrain);
        p = keepFeetApart(c, p, base.yaw, state);
        p.z() = terrain.height(p.x(), p.y());
        s.touchDownPosition = p;
      }
      s.apexHeight = terrain.maxHeightAlong(s.liftOffPosition.x(), s.liftOffPosition.y(),
                                            s.touchDownPosition.x(), s.touchDownPosition.y());
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
