// Swing trajectories of every contact point over the planning horizon.
//
// Each update (at the planner's rate) walks the contact schedule over [t, t + horizon] and, for
// every swing in it, sets lift-off where the point is (or where its previous swing in the
// horizon lands), touch-down by the foothold rule, and the apex `apexClearance` above the
// highest terrain between them. Foothold rules:
//   kPaper         the paper's eq. (desired_swing_traj) (footholds.hpp) at the predicted base
//                  pose, per contact point, from the measured base velocity;
//   kCapturePoint  step adjustment (step_adjustment.hpp): the feet's footholds in touch-down
//                  order from the capture point of the measured centre of mass (and an
//                  external force's offset), within the reach of each step; each contact point
//                  then sits at its place on its foot, turned to the heading at touch-down;
//                  with a share `walkingPush.paperAcross`, each foothold moves that fraction of
//                  the way to the paper's across `walkingPush.axis` (a push along the walk,
//                  recovery.hpp).
// A swing in progress keeps its lift-off and re-aims its touch-down until `replanUntil` of its
// duration, then holds it; a re-aimed swing moves on from where its reference is (a cubic from
// its position and velocity then, swing_trajectory.hpp), so the foot never jumps. Left footholds
// are kept at least `minFeetDistance` left of the right foot's (and vice versa) in the heading
// frame: the paper's foot-collision constraint (eq. collsion), enforced where footholds are
// chosen.
// Under the paper's rule, where the ground under its foothold is not good (unknown, an edge,
// steep) or the sole would not rest on its toe and heel, the foot moves to the nearest good
// place within a small window (foothold_search.hpp), and stays at that place over the updates
// while it is good and within the window of the paper's foothold.
#pragma once

#include <array>

#include "gait/contact.hpp"
#include "gait/contact_schedule.hpp"
#include "gait/foothold_search.hpp"
#include "gait/footholds.hpp"
#include "gait/recovery.hpp"
#include "gait/step_adjustment.hpp"
#include "gait/swing_trajectory.hpp"

namespace ballast::gait {

enum class FootholdRule { kPaper, kCapturePoint };

/// Filled by the profile (gait.*: defaults and bounds in daemon/profile/schema.cpp).
struct SwingPlannerParameters {
  double apexClearance;   ///< m above the terrain between lift-off and touch-down
  /// A swing whose terrain rises or falls more than stepHeight (m) between lift-off and
  /// touch-down lifts (and lowers) vertically for stepLift of its duration at each end.
  double stepHeight;
  double stepLift;
  double replanUntil;      ///< fraction of a swing after which its touch-down is held
  double minFeetDistance;  ///< m, lateral, between left and right contact points
  FootholdParameters foothold;  ///< kPaper; its comHeight and gravity serve kCapturePoint too
  FootholdRule rule;            ///< gait.footholds
  StepLimits limits;            ///< kCapturePoint (minWidth: minFeetDistance)
  FootholdSearchParameters search;  ///< kPaper: footholds off unknown cells, edges and steep cells
  /// kCapturePoint: across a push along the walk, the footholds moved part of the way to the
  /// paper's (gait::walkingPushAxis; none by default).
  WalkingPushAxis walkingPush;
};

/// What the planner needs to know about the robot now.
struct GaitState {
  double t = 0.0;
  PlanarPose base;                              ///< base position (world) and yaw
  Eigen::Vector3d baseVelocity = Eigen::Vector3d::Zero();  ///< world
  std::array<Eigen::Vector3d, kNumContacts> contactPositions{};  ///< world
  Eigen::Vector3d com = Eigen::Vector3d::Zero();                 ///< world
  Eigen::Vector3d comVelocity = Eigen::Vector3d::Zero();         ///< world
  Eigen::Vector3d externalForce = Eigen::Vector3d::Zero();       ///< estimated, world, N
  double mass = 1.0;                                             ///< kg
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
  /// The swings of `contact` in the last update's horizon, in time order.
  int swingCount(int contact) const { return count_[contact]; }
  const SwingTrajectory& swing(int contact, int i) const { return swings_[contact][i]; }
  /// Capture point rule: ω of the pendulum.
  double omega() const;
  /// Capture point rule: one of the next two steps (one per foot) in the last update could not
  /// land where the capture point asked, held to the step limits (Step::limited).
  bool stepsLimited() const { return stepsLimited_; }
  /// The horizontal distance (m) its foot covers in the longer of the two feet's next swings
  /// that lift off after t (their toes' swings in the last update): what a gait's swing time
  /// has to carry (cadence.hpp, fitSwing). 0 when neither foot has one in the horizon.
  double longestNextSwing(double t) const;
  const SwingPlannerParameters& parameters() const { return params_; }
  void setParameters(const SwingPlannerParameters& p) { params_ = p; }

 private:
  /// footholdOffset() of the foot `contact` belongs to, at its swing's touch-down: searched by
  /// the foot's first point to ask in an update, reused by the other (the same question).
  Eigen::Vector3d footOffset(int contact, double touchDown, const PlanarPose& base,
                             const GaitState& state, const Eigen::Vector3d& vDesired,
                             double yawRate, double stance, const TerrainQuery& terrain);
  /// Where contact point `contact` sits from its foot's centre (toe and heel midway), world
  /// x-y, the foot turned to `yaw`.
  Eigen::Vector2d placeOnFoot(int contact, double yaw) const;
  Eigen::Vector3d keepFeetApart(int contact, const Eigen::Vector3d& foothold, double yaw,
                                const GaitState& state) const;
  /// Capture point rule: steps_[0..numSteps_) and their footholds for this update.
  void planSteps(const ContactSchedule& schedule, const GaitState& state,
                 const VelocityCommand& command, double until);

  static constexpr int kMaxSteps = 2 * kMaxSwings;
  std::array<Step, kMaxSteps> steps_{};
  int numSteps_ = 0;
  bool stepsLimited_ = false;

  SwingPlannerParameters params_;
  std::array<Eigen::Vector3d, kNumContacts> nominalOffsets_;
  std::array<std::array<SwingTrajectory, kMaxSwings>, kNumContacts> swings_{};
  std::array<int, kNumContacts> count_{};
  std::array<Eigen::Vector3d, kNumContacts> stance_{};  ///< position at the last update
  /// This update's foothold offsets per foot (0 left, 1 right) and touch-down time.
  struct FootOffset {
    double touchDown;
    Eigen::Vector3d offset;
    Eigen::Vector3d toe;  ///< where the offset put the toe (world)
  };
  std::array<std::array<FootOffset, kMaxSwings>, 2> footOffsets_{};
  std::array<int, 2> footOffsetCount_{};
  /// The last update's: a moved foothold stays where it was while that is still good and
  /// supported (footOffset).
  std::array<std::array<FootOffset, kMaxSwings>, 2> previousOffsets_{};
  std::array<int, 2> previousOffsetCount_{};
};

}  // namespace ballast::gait
