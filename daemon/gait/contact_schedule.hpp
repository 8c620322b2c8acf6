// Contact schedule: which contact points are closed at a time, from the profile's gait.
//
// A gait is periodic with period T. Walking: the left foot lifts at phase 0, the right at 0.5
// (the other way round with `rightFirst`: a recovery step to the right starts with the right foot);
// each foot swings for (1 − double_support)/2 of the period, so both feet are down for
// `double_support` of each cycle, in two equal phases. A heel may lift (and land) `toe_off_lead`
// seconds before its toe (heel-strike / toe-off); 0 moves toe and heel together. Standing
// keeps every contact closed.
//
// The schedule is a short sequence of gait segments. A new gait takes effect at a safe time:
// from standing, walking starts at once (its phase 0, first swing after a double support);
// walking ends or changes only at the start of a double-support phase that follows a
// touch-down of both feet, so no swing is cut short; walking on with another period or double
// support begins its cycle with the foot whose turn it is (the request's rightFirst is then the
// schedule's to choose). Queries take absolute controller time.
#pragma once

#include <array>
#include <cstddef>

#include "gait/contact.hpp"

namespace ballast::gait {

/// A walking gait's numbers come from the profile (gait.*); Gait{} is standing.
struct Gait {
  bool walking = false;
  double period;          ///< s, one cycle (two steps)
  double doubleSupport;   ///< fraction of the cycle with both feet down
  double toeOffLead;      ///< s, heel leaves and lands this much before its toe
  bool rightFirst = false;  ///< the right foot swings first in each cycle

  double swingDuration() const { return 0.5 * (1.0 - doubleSupport) * period; }
  double stanceDuration() const { return period - swingDuration(); }
  bool operator==(const Gait& o) const {
    return walking == o.walking && period == o.period && doubleSupport == o.doubleSupport &&
           toeOffLead == o.toeOffLead && rightFirst == o.rightFirst;
  }
};

/// One swing of one contact point: lift-off and touch-down times.
struct SwingInterval {
  double liftOff = 0.0;
  double touchDown = 0.0;
};

class ContactSchedule {
 public:
  static constexpr int kMaxSegments = 8;

  ContactSchedule() : ContactSchedule(Gait{}, 0.0) {}  ///< standing from time 0
  explicit ContactSchedule(const Gait& initial, double startTime = 0.0);

  /// Requests `gait` from time t on; returns the time it takes effect (see header comment).
  double setGait(const Gait& gait, double t);
  /// The gait in force at t, and the one last requested.
  const Gait& gaitAt(double t) const;
  const Gait& latestGait() const { return segments_[count_ - 1].gait; }

  ContactFlags flagsAt(double t) const;
  bool inStance(int contact, double t) const;
  /// The swing of `contact` that contains t, or the next one starting after t, if any starts
  /// before `until`. Returns false if there is none.
  bool swingAround(int contact, double t, double until, SwingInterval& swing) const;
  /// Earliest time > t at which any contact opens or closes, or `until` if none before it.
  double nextSwitch(double t, double until) const;

 private:
  struct Segment {
    double start;
    Gait gait;
  };
  const Segment& segmentAt(double t) const;
  double segmentEnd(int index) const;
  /// Within a walking segment: local phase offset of a contact's swing start, in seconds.
  static double swingStartOffset(const Gait& g, int contact);
  /// Next time ≥ t (within the walking segment) where both feet are down after both touched
  /// down, i.e. the start of a double-support phase.
  static double nextDoubleSupportStart(const Segment& s, double t);
  void dropSegmentsBefore(double t);

  std::array<Segment, kMaxSegments> segments_;
  int count_ = 0;
};

}  // namespace ballast::gait
