// Base state from the IMU and leg kinematics: the loop's estimator until daemon/estimation
// (the Kalman filter of DESIGN.md) replaces it behind the same EstimatedState.
//
//   orientation, angular velocity : the IMU, moved from the IMU frame to the base
//   contact points                : the lowest contact point and those within
//                                   estimator.contact_height of it
//   position                      : each contact point is anchored in the world when it
//                                   touches down; the base is where the anchored points put it
//   velocity                      : minus the mean velocity of the contact points relative to
//                                   the base (they are at rest in the world)
// With no contact (a fall, the robot lifted) position and velocity integrate the IMU.
// estimator.source = truth uses the simulator's ground truth instead (diagnostics only).
#pragma once

#include <array>

#include "control/settings.hpp"
#include "control/types.hpp"
#include "model/data.hpp"

namespace ballast::control {

class LegOdometry {
 public:
  /// Throws model::ModelError when a contact or IMU frame is missing or the IMU is not on the
  /// base body.
  LegOdometry(const model::Model& model, const ControlSettings& settings);

  void setSettings(const ControlSettings& settings) { settings_ = &settings; }

  /// One update. q, dq, tau are in model joint order; dt > 0.
  void update(const backend::Sensors& sensors, const double* q, const double* dq, const double* tau,
              double dt, EstimatedState& out);

 private:
  const model::Model& model_;
  const ControlSettings* settings_;
  model::Data<double> data_;
  model::VecX<double> q_, v_;
  std::array<int, kNumContacts> contact_frame_{};
  model::Mat3<double> imu_in_base_;
  model::Vec3<double> position_ = model::Vec3<double>::Zero();
  model::Vec3<double> velocity_ = model::Vec3<double>::Zero();
  model::Mat3<double> rotation_ = model::Mat3<double>::Identity();
  std::array<model::Vec3<double>, kNumContacts> anchor_{};
  std::array<bool, kNumContacts> in_contact_{};
  bool initialised_ = false;
};

/// rpy and the other BaseState fields from a quaternion (x, y, z, w) already in `base`.
void fillRpy(BaseState& base);

}  // namespace ballast::control
