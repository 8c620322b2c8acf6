// The standing controller the loop runs until the whole-body controller (daemon/wbc) takes its
// place behind the same ControllerInput -> ControllerOutput: joint-space PD to a standing
// posture, plus a gravity feed-forward from the model.
//
// Feed-forward: the joint torques that hold the robot still on its contact points. With
// n = g(q) from RNEA (zero velocity) and the contact-point Jacobians Jc (3 rows per point in
// contact), the contact forces of least norm that carry the base, Jc,bᵀ f = n_b (6 equations),
// leave the joints τ = n_j − Jc,jᵀ f. Without contacts (robot lifted) it is n_j.
//
// Stance: stand-up anchors the standing posture to the feet as they lie (StandPosture::anchor):
// the base level over them at their mean height and heading, the soles kept at their tilt. On
// uneven ground the legs take up the unevenness instead of the body tilting with the feet. The
// whole placement is taken once, when both feet are down; then every tick of stand-up their height
// and tilt as they settle under the weight (taken whole every tick, the stance gave way to
// whatever the feet did: nothing pulled a foot that turned or slid back, and on sim-rough the
// robot turned 0.66 rad on its feet). Standing, the stance stays as stand-up left it (the `pose`
// command is relative to it); without both feet down, the nominal stance.
//
// Reference posture: anchored, stand-up moves the base from its pose over the feet at the start
// to the standing pose (position and roll, pitch, yaw each blended), the legs solved for it every
// tick; the other joints, and all of them unanchored, blend from the posture at its start to the
// standing posture, with a quintic smoothstep (zero velocity and acceleration at both ends), with
// the full feed-forward from the start (fading it in lets the knees sag and the robot tip over
// backwards: measured on the Simbody backend); stand tracks StandPosture for the commanded pose,
// the pose itself moved toward the command at control.pose_speed / pose_angular_speed. Gains come
// from the loop (which blends them across a profile switch).
//
// Per-level errors reported: level 2 (limb tracking) = RMS joint error over all limbs, rad;
// level 3 (base tracking) = norm of the base orientation error, rad; levels 1 and 4 do not
// exist here (NaN).
#pragma once

#include <array>

#include "control/settings.hpp"
#include "control/stand_posture.hpp"
#include "control/types.hpp"
#include "model/data.hpp"

namespace ballast::control {

class StandController {
 public:
  StandController(const model::Model& model, const ControlSettings& settings);

  void setSettings(const ControlSettings& settings);
  double nominalHeight() const { return posture_.nominalHeight(); }

  /// Stand-up starts from this state's posture and the base's current height.
  void beginStandUp(const EstimatedState& state);

  /// Stand-up and stand. kp, kd are the gains in force (model order).
  void compute(const ControllerInput& in, const double* kp, const double* kd, double dt,
               ControllerOutput& out);

  /// Gravity feed-forward for the state (model order, nj entries).
  void gravityFeedForward(const EstimatedState& state, double* tau);

 private:
  /// Both feet have a contact point in contact.
  bool feetDown(const EstimatedState& state) const;
  void anchorFeet(const EstimatedState& state, StandPosture::AnchorPart part);

  const model::Model& model_;
  const ControlSettings* settings_;
  StandPosture posture_;
  model::Data<double> data_;
  model::VecX<double> q_, v_;
  model::MatX<double> Jc_;  // contact-point Jacobians, 3 rows per point
  std::array<int, kNumContacts> contact_frame_{};
  std::array<double, kMaxJoints> stand_up_from_{};
  std::array<double, kMaxJoints> target_{};
  std::array<double, kMaxJoints> tau_{};
  // The pose being tracked, moving toward the command: height, roll, pitch, yaw.
  std::array<double, 4> pose_{};
  // Stand-up's start over the feet: x, y, height in the stance frame; roll, pitch, yaw.
  std::array<double, 6> stand_up_pose_{};
  bool first_tick_ = false;
};

/// Zero torque and gains: the joints are free.
void passiveOutput(int num_joints, const double* q, ControllerOutput& out);
/// Velocity damping only.
void dampOutput(int num_joints, const double* q, double damping, ControllerOutput& out);

}  // namespace ballast::control
