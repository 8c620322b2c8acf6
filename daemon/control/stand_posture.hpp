// Standing postures: joint positions that keep both feet where the nominal stance puts them
// while the base takes a requested height and orientation (the `pose` command).
//
// The nominal stance: the nominal posture with the base level, soles on the ground. Each foot
// (the contact frames sharing a body) is a 6-D target in that stance frame; the leg from the
// base to it is solved by damped Newton steps on the foot's frame Jacobian (the leg's columns),
// warm-started from the previous solution, joints clamped to their limits. Joints outside the
// legs keep the nominal posture. Everything is sized at construction; solve() and anchor()
// allocate nothing.
//
// Anchored (anchor()): the feet are targets where they are, not where the nominal stance puts
// them. The stance frame is then level, turned to the feet's mean heading and at their mean
// height, and placed so that the feet's mean position in it is the nominal stance's: on a flat
// floor with the feet as the nominal stance has them, the same frame and the same targets. On
// uneven ground (soles tilted, at different heights) the base stands level over the feet as they
// lie, instead of tilting with them.
#pragma once

#include <array>
#include <vector>

#include "control/settings.hpp"
#include "model/data.hpp"

namespace ballast::control {

class StandPosture {
 public:
  static constexpr int kMaxLegJoints = 8;

  /// Throws model::ModelError if the feet cannot be found or a leg has no joints.
  StandPosture(const model::Model& model, const ControlSettings& settings);

  /// New nominal posture (a profile switch); keeps the feet layout and drops an anchor.
  void setNominal(const ControlSettings& settings);

  /// What anchor() takes from the feet: all of their placement, or (anchored before) their
  /// height and tilt, each foot keeping its place along the ground and its heading.
  enum class AnchorPart { kWhole, kHeightAndTilt };

  /// The feet as they are for the base's orientation `worldFromBase` (its roll and pitch make
  /// "level"; its heading does not matter) and joint positions `qj` (model order): the stance
  /// frame and the feet targets become theirs (see above). Keeps the last solution as the warm
  /// start.
  void anchor(const model::Mat3<double>& worldFromBase, const double* qj,
              AnchorPart part = AnchorPart::kWhole);

  /// Back to the nominal stance's feet.
  void unanchor();
  bool anchored() const { return anchored_; }

  /// Base height above the soles in the nominal posture, m.
  double nominalHeight() const { return nominal_height_; }

  /// Joint positions (model order, nj) for the base at `height` above the soles with the given
  /// roll, pitch, yaw relative to the feet. `iterations` Newton steps per leg from the last
  /// solution. Returns the largest remaining foot error (m + rad).
  double solve(double height, double roll, double pitch, double yaw, int iterations, double* q_out);
  /// The same for the base at any place in the stance frame.
  double solve(const model::SE3<double>& stanceFromBase, int iterations, double* q_out);

  /// Where a base of that orientation stands in the stance frame (anchored: as the last anchor
  /// saw the feet; else as the nominal stance has them, level).
  model::SE3<double> baseInStance(const model::Mat3<double>& worldFromBase) const;
  /// The next solve starts from these legs (model order, nj).
  void warmStart(const double* qj);
  /// Whether joint j (model order) is in a leg.
  bool inLeg(int j) const { return in_leg_[j]; }
  /// The foot (0 or 1, the order the contact frames first name their bodies) that contact
  /// point c (settings.contact_frames order) is on.
  int footOfContact(int c) const { return foot_of_contact_[c]; }

 private:
  struct Leg {
    int frame = -1;  // the first contact frame of this foot: its 6-D end frame
    int joints[kMaxLegJoints] = {};
    int num_joints = 0;
    model::SE3<double> target_in_stance;
    model::SE3<double> nominal_in_stance;  // the nominal stance's target
    model::SE3<double> anchor_in_level;    // anchored: the foot in the level frame at the base
  };

  /// The stance frame and targets of the anchored feet.
  void placeAnchor();

  const model::Model& model_;
  model::Data<double> data_;
  model::VecX<double> qj_;      // the last solution, the next solve's warm start
  model::VecX<double> q_feet_;  // the joints an anchor was taken at
  model::Mat6X<double> J_;
  std::array<Leg, 2> legs_;
  double nominal_height_ = 0.0;
  bool anchored_ = false;
  model::SE3<double> level_from_stance_;  // anchored: the stance frame in the level frame
  std::vector<char> in_leg_;              // per joint (model order)
  std::array<int, kNumContacts> foot_of_contact_{};
};

}  // namespace ballast::control
