// Swing trajectories of every contact point over the planning horizon.
//
// Each update (at the planner's rate) walks the contact schedule over [t, t + horizon] and, for
// every swing in it, sets lift-off where the point is (or where its previous swing in the
// horizon lands), touch-down by the paper's foothold equation (footholds.hpp) at the predicted
// base pose, and the apex `apexClearance` above the highest terrain between them. A swing in
// progress keeps its lift-off and re-aims its touch-down until `replanUntil` of its duration,
// then holds it, so late corrections do not jerk the foot. Left footholds are kept at least
// `minFeetDistance` left of the right foot's (and vice versa) in the heading frame: the paper's
// foot-collision constraint (eq. collsion), enforced where footholds are chosen.
#pragma once

#include <array>

#include "gait/contact.hpp"
#include "gait/contact_schedule.hpp"
#include "gait/footholds.hpp"
#include "gait/swing_trajectory.hpp"

namespace ballast::gait {

/// Filled by the profile (gait.*: defaults and bounds in daemon/profile/schema.cpp).
struct SwingPlannerParameters {
  double apexClearance;   ///< m above the terrain between lift-off and touch-down
  /// A swing whose terrain rises or falls more than stepHeight (m) between lift-off and
  /// touch-down lifts (and lowers) vertically for stepLift of its duration at each end.
  double stepHeight;
  double stepLift;
  double replanUntil;      ///< fraction of a swing after which its touch-down is held
  double minFeetDistance;  ///< m, lateral, between left and right contact points
  FootholdParameters foothold;
};

/// What the planner needs to know about the robot now.
struct GaitState {
  double t = 0.0;
  PlanarPose base;                              ///< base position (world) and yaw
  Eigen::Vector3d baseVelocity = Eigen::Vector3d::Zero();  ///< world
  std::array<Eigen::Vector3d, kNumContacts> contactPositions{};  ///< world
};

class SwingPlanner {
 public:
  static constexpr int kMaxSwings = 4;  ///< per contact point within one horizon

  /// nominalOffsets: each contact point under its hip in the nominal stance, heading frame,
  /// relative to the base (x forward, y left).
  SwingPlanner(const SwingPlannerParameters& params,
               const std::array<Eigen::Vector3d, kNumContacts>& nominalOffsets);

  void update(const ContactSchedule& schedule, const GaitState& state,
              const VelocityCommand& command, double horizon, const TerrainQuery& terrain);

  /// The planned swing of `contact` containing t, or nullptr.
  const SwingTrajectory* swingAt(int contact, double t) const;
  /// Swing reference, or the held stance position (zero velocity) when t is in a stance.
  PointReference reference(int contact, double t) const;
  const SwingPlannerParameters& parameters() const { return params_; }
  void setParameters(const SwingPlannerParameters& p) { params_ = p; }

 private:
  Eigen::Vector3d keepFeetApart(int contact, const Eigen::Vector3d& foothold, double yaw,
                                const GaitState& state) const;

  SwingPlannerParameters params_;
  std::array<Eigen::Vector3d, kNumContacts> nominalOffsets_;
  std::array<std::array<SwingTrajectory, kMaxSwings>, kNumContacts> swings_{};
  std::array<int, kNumContacts> count_{};
  std::array<Eigen::Vector3d, kNumContacts> stance_{};  ///< position at the last update
};

}  // namespace ballast::gait
