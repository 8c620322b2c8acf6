#include "gait/contact_schedule.hpp"

#include <cmath>
#include <limits>

namespace ballast::gait {
namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTimeEps = 1e-9;
}  // namespace

ContactSchedule::ContactSchedule(const Gait& initial, double startTime) {
  segments_[0] = Segment{startTime, initial};
  count_ = 1;
}

const ContactSchedule::Segment& ContactSchedule::segmentAt(double t) const {
  int i = count_ - 1;
  while (i > 0 && segments_[i].start > t + kTimeEps) --i;
  return segments_[i];
}

double ContactSchedule::segmentEnd(int index) const {
  return index + 1 < count_ ? segments_[index + 1].start : kInf;
}

const Gait& ContactSchedule::gaitAt(double t) const { return segmentAt(t).gait; }

double ContactSchedule::swingStartOffset(const Gait& g, int contact) {
  // Cycle: double support, left swing, double support, right swing (phase 0 starts a double
  // support; the right foot first with rightFirst). Heels leave `toeOffLead` before their toes.
  const double footStart = (isLeft(contact) != g.rightFirst ? 0.5 * g.doubleSupport : 0.5 + 0.5 * g.doubleSupport) *
                           g.period;
  const bool heel = contact == kLeftHeel || contact == kRightHeel;
  return footStart - (heel ? g.toeOffLead : 0.0);
}

double ContactSchedule::nextDoubleSupportStart(const Segment& s, double t) {
  const double half = 0.5 * s.gait.period;
  return s.start + std::ceil((t - s.start) / half - kTimeEps) * half;
}

void ContactSchedule::dropSegmentsBefore(double t) {
  int keep = 0;  // first segment still needed: the one containing t
  while (keep + 1 < count_ && segments_[keep + 1].start <= t) ++keep;
  if (keep == 0) return;
  for (int i = keep; i < count_; ++i) segments_[i - keep] = segments_[i];
  count_ -= keep;
}

double ContactSchedule::setGait(const Gait& gait, double t) {
  dropSegmentsBefore(t);
  if (latestGait() == gait) return segments_[count_ - 1].start;
  // Find the segment in force at t (later, not yet started segments are replaced).
  while (count_ > 1 && segments_[count_ - 1].start > t) --count_;
  const Segment& current = segments_[count_ - 1];
  double start = t;
  Gait next = gait;
  if (current.gait.walking) {
    start = nextDoubleSupportStart(current, t);
    if (gait.walking) {
      // Walking on with other parameters (a step timing): at the next double support, the new
      // cycle starting with the foot whose turn it is (the second of the cycle at a half-cycle
      // boundary), so feet alternate.
      const double cycles = (start - current.start) / current.gait.period;
      const bool half = std::abs(cycles - std::round(cycles)) > 1e-6;
      next.rightFirst = half != current.gait.rightFirst;
      Gait same = current.gait;
      same.rightFirst = next.rightFirst;
      if (same == next) return current.start;  // the walk in force, as it goes on
    }
  }
  if (start <= current.start + kTimeEps) {
    segments_[count_ - 1] = Segment{current.start, next};
    return current.start;
  }
  if (count_ == kMaxSegments) {  // keep the newest; older ones are far in the past by now
    for (int i = 1; i < count_; ++i) segments_[i - 1] = segments_[i];
    --count_;
  }
  segments_[count_++] = Segment{start, next};
  return start;
}

bool ContactSchedule::swingAround(int contact, double t, double until,
                                  SwingInterval& swing) const {
  int i = count_ - 1;
  while (i > 0 && segments_[i].start > t + kTimeEps) --i;
  for (; i < count_; ++i) {
    const Segment& s = segments_[i];
    const double end = segmentEnd(i);
    const double from = std::max(t, s.start);
    if (from >= until || from >= end) break;
    if (!s.gait.walking) continue;
    const double T = s.gait.period;
    const double sw = s.gait.swingDuration();
    const double base = s.start + swingStartOffset(s.gait, contact);
    double k = std::floor((from - base) / T);
    double lift = base + k * T;
    if (lift < s.start - kTimeEps || from >= lift + sw - kTimeEps) lift += T;  // the next one
    if (lift < s.start - kTimeEps) lift += T;
    if (lift >= until || lift + sw > end + kTimeEps) continue;
    swing = SwingInterval{lift, lift + sw};
    return true;
  }
  return false;
}

bool ContactSchedule::inStance(int contact, double t) const {
  SwingInterval s;
  return !(swingAround(contact, t, t + kTimeEps, s) && s.liftOff <= t + kTimeEps &&
           t < s.touchDown - kTimeEps);
}

ContactFlags ContactSchedule::flagsAt(double t) const {
  ContactFlags f;
  for (int c = 0; c < kNumContacts; ++c) f[c] = inStance(c, t);
  return f;
}

double ContactSchedule::nextSwitch(double t, double until) const {
  double next = until;
  for (int c = 0; c < kNumContacts; ++c) {
    SwingInterval s;
    if (!swingAround(c, t, until, s)) continue;
    if (s.liftOff > t + kTimeEps) next = std::min(next, s.liftOff);
    else if (s.touchDown > t + kTimeEps) next = std::min(next, s.touchDown);
  }
  return next;
}

}  // namespace ballast::gait
