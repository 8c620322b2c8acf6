// Standing postures: joint positions that keep both feet where the nominal stance puts them
// while the base takes a requested height and orientation (the `pose` command).
//
// The nominal stance: the nominal posture with the base level, soles on the ground. Each foot
// (the contact frames sharing a body) is a 6-D target in that stance frame; the leg from the
// base to it is solved by damped Newton steps on the foot's frame Jacobian (the leg's columns),
// warm-started from the previous solution, joints clamped to their limits. Joints outside the
// legs keep the nominal posture. Everything is sized at construction; solve() allocates nothing.
#pragma once

#include <array>

#include "control/settings.hpp"
#include "model/data.hpp"

namespace ballast::control {

class StandPosture {
 public:
  static constexpr int kMaxLegJoints = 8;

  /// Throws model::ModelError if the feet cannot be found or a leg has no joints.
  StandPosture(const model::Model& model, const ControlSettings& settings);

  /// New nominal posture (a profile switch); keeps the feet layout.
  void setNominal(const ControlSettings& settings);

  /// Base height above the soles in the nominal posture, m.
  double nominalHeight() const { return nominal_height_; }

  /// Joint positions (model order, nj) for the base at `height` above the soles with the given
  /// roll, pitch, yaw relative to the feet. `iterations` Newton steps per leg from the last
  /// solution. Returns the largest remaining foot error (m + rad).
  double solve(double height, double roll, double pitch, double yaw, int iterations, double* q_out);

 private:
  struct Leg {
    int frame = -1;  // the first contact frame of this foot: its 6-D end frame
    int joints[kMaxLegJoints] = {};
    int num_joints = 0;
    model::SE3<double> target_in_stance;
  };

  const model::Model& model_;
  model::Data<double> data_;
  model::VecX<double> qj_;
  model::Mat6X<double> J_;
  std::array<Leg, 2> legs_;
  double nominal_height_ = 0.0;
};

}  // namespace ballast::control
