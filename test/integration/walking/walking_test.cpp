// The stack of the paper's Fig. 4 walking the humanoid in the Simbody backend (issue 6 §3 without
// the daemon: the daemon's acceptance tests repeat these through the CLI). Each test prints the
// figures it checks (run with --gtest_filter=... to see one; BALLAST_RIG_TRACE=1 for the trace).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "model/base_conventions.hpp"
#include "test/integration/walking/walking_rig.hpp"

namespace ballast::test {
namespace {

/// Samples the rig every 10 ms of simulated time while it runs, and reduces a window of samples
/// to the figures the tests check.
class Recorder {
 public:
  explicit Recorder(WalkingRig& rig) : rig_(rig) {
    const model::Model& m = rig.model();
    for (const char* side : {"left_", "right_"}) {
      shoulder_.push_back(m.jointId(std::string(side) + "shoulder_pitch"));
      hip_.push_back(m.jointId(std::string(side) + "hip_pitch"));
    }
  }

  /// Runs `seconds` under `command`; false on a fall.
  bool run(const locomotion::LocomotionCommand& command, double seconds) {
    const int chunks = static_cast<int>(std::lround(seconds / 0.01));
    for (int i = 0; i < chunks; ++i) {
      if (!rig_.run(command, 0.01)) return false;
      record();
    }
    return true;
  }
  /// Starts a new measurement window (at the current time).
  void mark() { from_ = samples_.size(); }

  struct Figures {
    double vx = 0, vy = 0;   ///< mean velocity in the heading frame, m/s
    double yawRate = 0;      ///< mean, rad/s
    double shoulderSwing = 0;      ///< smaller of the two shoulder pitch half-ranges, rad
    double armLegCorrelation = 0;  ///< of (left − right) shoulder pitch with (left − right) hip pitch
    double maxTilt = 0;      ///< rad
    double minHeight = 1e9;  ///< m
  };
  /// Figures over the samples since mark().
  Figures figures() const {
    Figures f;
    const std::size_t n = samples_.size() - from_;
    if (n < 2) return f;
    const Sample& a = samples_[from_];
    const Sample& b = samples_.back();
    const double duration = b.t - a.t;
    double forward = 0, left = 0;
    for (std::size_t i = from_ + 1; i < samples_.size(); ++i) {
      const Sample& p = samples_[i - 1];
      const Sample& q = samples_[i];
      const Eigen::Vector3d d = q.position - p.position;
      const double yaw = 0.5 * (p.yaw + q.yaw);
      forward += std::cos(yaw) * d.x() + std::sin(yaw) * d.y();
      left += -std::sin(yaw) * d.x() + std::cos(yaw) * d.y();
    }
    f.vx = forward / duration;
    f.vy = left / duration;
    f.yawRate = (b.yaw - a.yaw) / duration;
    double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
    double ms = 0, mh = 0;
    for (std::size_t i = from_; i < samples_.size(); ++i) {
      const Sample& s = samples_[i];
      for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], s.shoulder[k]), hi[k] = std::max(hi[k], s.shoulder[k]);
      ms += (s.shoulder[0] - s.shoulder[1]) / n;
      mh += (s.hip[0] - s.hip[1]) / n;
      f.maxTilt = std::max(f.maxTilt, s.tilt);
      f.minHeight = std::min(f.minHeight, s.position.z());
    }
    f.shoulderSwing = 0.5 * std::min(hi[0] - lo[0], hi[1] - lo[1]);
    double sab = 0, saa = 0, sbb = 0;
    for (std::size_t i = from_; i < samples_.size(); ++i) {
      const double da = samples_[i].shoulder[0] - samples_[i].shoulder[1] - ms;
      const double db = samples_[i].hip[0] - samples_[i].hip[1] - mh;
      sab += da * db, saa += da * da, sbb += db * db;
    }
    f.armLegCorrelation = sab / std::sqrt(saa * sbb + 1e-30);
    return f;
  }

 private:
  struct Sample {
    double t, yaw, tilt;
    Eigen::Vector3d position;
    double shoulder[2], hip[2];
  };
  void record() {
    Sample s;
    s.t = rig_.time();
    s.position = rig_.basePosition();
    const Eigen::Matrix3d R = rig_.baseRotation();
    const double yaw = model::zyxFromRotation(R)[0];
    s.yaw = samples_.empty() ? yaw : samples_.back().yaw + std::remainder(yaw - samples_.back().yaw, 2 * M_PI);
    s.tilt = std::acos(std::clamp(R(2, 2), -1.0, 1.0));
    const Eigen::VectorXd q = rig_.jointPositions();
    for (int k = 0; k < 2; ++k) s.shoulder[k] = q[shoulder_[k]], s.hip[k] = q[hip_[k]];
    samples_.push_back(s);
  }

  WalkingRig& rig_;
  std::vector<int> shoulder_, hip_;
  std::vector<Sample> samples_;
  std::size_t from_ = 0;
};

locomotion::LocomotionCommand walk(double vx, double vy = 0.0, double yawRate = 0.0) {
  locomotion::LocomotionCommand c;
  c.walk = true;
  c.vx = vx;
  c.vy = vy;
  c.yawRate = yawRate;
  return c;
}

void print(const char* what, const Recorder::Figures& f) {
  std::printf("%s: vx %.3f m/s, vy %.3f m/s, yaw rate %.3f rad/s; shoulder swing %.3f rad, "
              "arm-leg correlation %.2f; max tilt %.3f rad, min base height %.3f m\n",
              what, f.vx, f.vy, f.yawRate, f.shoulderSwing, f.armLegCorrelation, f.maxTilt,
              f.minHeight);
}

TEST(Walking, StandsStill) {
  WalkingRig rig;
  const Eigen::Vector3d p0 = rig.basePosition();
  ASSERT_TRUE(rig.run({}, 3.0)) << rig.why();
  EXPECT_LT((rig.basePosition() - p0).head<2>().norm(), 0.02);
  EXPECT_LT(rig.baseVelocity().norm(), 0.02);
  EXPECT_EQ(rig.failedPlans(), 0);
}

/// Walks at vx for 10 s: no fall, mean speed over the last 5 s within 10 %, the arms swing
/// against the legs (the MPC moves them, through the centroidal momentum). At 1.0 m/s here;
/// 0.5, 1.2 and 1.5 m/s through the CLI (acceptance.walk.forward_*, both simulators).
void walksForward(double vx, WalkingRig& rig, Recorder& rec) {
  ASSERT_TRUE(rec.run(walk(vx), 5.0)) << rig.why();
  rec.mark();
  ASSERT_TRUE(rec.run(walk(vx), 5.0)) << rig.why();
  const Recorder::Figures f = rec.figures();
  char what[64];
  std::snprintf(what, sizeof what, "walk %.1f m/s, last 5 s", vx);
  print(what, f);
  EXPECT_NEAR(f.vx, vx, 0.1 * vx);
  EXPECT_LT(std::abs(f.vy), 0.1);
  // Frozen arms (armJointVelocity ≥ 5) swing ≤ 0.025 rad at 0.5 m/s; these swing 0.1–0.3.
  EXPECT_GT(f.shoulderSwing, 0.05) << "arms (nearly) frozen";
  EXPECT_LT(f.armLegCorrelation, -0.5) << "arms do not swing against the legs";
  EXPECT_EQ(rig.failedPlans(), 0);
  EXPECT_EQ(rig.degradedTicks(), 0);
}

TEST(Walking, WalksAtOneMetrePerSecondAndStops) {
  WalkingRig rig;
  Recorder rec(rig);
  walksForward(1.0, rig, rec);
  if (HasFatalFailure()) return;
  // Stop: at rest, standing on all four contact points, within 2 s.
  ASSERT_TRUE(rec.run({}, 2.0)) << rig.why();
  std::printf("stop from 1.0 m/s: after 2 s base speed %.3f m/s, contacts %d%d%d%d\n",
              rig.baseVelocity().norm(), rig.inContact(0), rig.inContact(1), rig.inContact(2),
              rig.inContact(3));
  EXPECT_LT(rig.baseVelocity().norm(), 0.05);
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(rig.inContact(c)) << c;
  EXPECT_FALSE(rig.plan().walking);
}

/// Turning on the spot and walking sideways: no fall, tracked within 15 % over the last 3 s.
TEST(Walking, TurnsOnTheSpot) {
  WalkingRig rig;
  Recorder rec(rig);
  ASSERT_TRUE(rec.run(walk(0.0, 0.0, 0.5), 3.0)) << rig.why();
  rec.mark();
  ASSERT_TRUE(rec.run(walk(0.0, 0.0, 0.5), 3.0)) << rig.why();
  const Recorder::Figures f = rec.figures();
  print("turn 0.5 rad/s, last 3 s", f);
  EXPECT_NEAR(f.yawRate, 0.5, 0.15 * 0.5);
  EXPECT_LT(std::hypot(f.vx, f.vy), 0.1);
}

TEST(Walking, WalksSideways) {
  WalkingRig rig;
  Recorder rec(rig);
  ASSERT_TRUE(rec.run(walk(0.0, 0.3), 3.0)) << rig.why();
  rec.mark();
  ASSERT_TRUE(rec.run(walk(0.0, 0.3), 3.0)) << rig.why();
  const Recorder::Figures f = rec.figures();
  print("sideways 0.3 m/s, last 3 s", f);
  EXPECT_NEAR(f.vy, 0.3, 0.15 * 0.3);
  EXPECT_LT(std::abs(f.vx), 0.05);
  EXPECT_LT(std::abs(f.yawRate), 0.05);
}

/// A push of `force` N along x on the torso for 1 s while walking at 0.5 m/s: no fall, and
/// walking on at the commanded speed afterwards.
void takesAPush(double force) {
  WalkingRig rig;
  Recorder rec(rig);
  ASSERT_TRUE(rec.run(walk(0.5), 3.0)) << rig.why();
  ASSERT_TRUE(rig.push("torso", Eigen::Vector3d(force, 0.0, 0.0), 1.0));
  rec.mark();
  ASSERT_TRUE(rec.run(walk(0.5), 1.0)) << rig.why();
  print("during the push", rec.figures());
  ASSERT_TRUE(rec.run(walk(0.5), 2.0)) << rig.why();
  rec.mark();
  ASSERT_TRUE(rec.run(walk(0.5), 2.0)) << rig.why();
  const Recorder::Figures f = rec.figures();
  print("2 s after the push", f);
  EXPECT_NEAR(f.vx, 0.5, 0.1);
}

TEST(Walking, TakesAFortyNewtonPush) { takesAPush(40.0); }

}  // namespace
}  // namespace ballast::test
