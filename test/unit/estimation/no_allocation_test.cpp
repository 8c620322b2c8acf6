// The estimator runs in the 1 kHz path: update(), correctPosition() and a settings switch
// allocate nothing, watched by a counting malloc (as test/unit/model/no_allocation_test.cpp).
#include <gtest/gtest.h>

#include "test/unit/allocation_counter.hpp"
#include "test/unit/estimation/synthetic_walk.hpp"
#include "test/unit/settings_support.hpp"

namespace ballast::test {
namespace {

TEST(EstimatorNoAllocation, CounterSeesAnAllocation) {
  EXPECT_GT(allocationsIn([] { Eigen::VectorXd x(100); x.setZero(); }), 0);
}

TEST(EstimatorNoAllocation, UpdateCorrectAndSwitch) {
  const model::Model& m = humanoid();
  SyntheticWalk motion(m);
  SyntheticSensors sensors(motion, SensorNoise{}, 2);
  estimation::StateEstimator est(m, estimatorSettings());
  estimation::EstimatorSettings other = estimatorSettings();
  other.kinematicsVelocityNoise = 0.07;
  // Inputs prepared outside the watched region: a walk through touch-downs and lift-offs.
  const int ticks = 1500;
  std::vector<estimation::EstimatorInput> inputs(ticks, est.makeInput());
  Eigen::VectorXd q, v;
  for (int k = 0; k < ticks; ++k) sensors.sample(k * motion.period, inputs[k], q, v);
  estimation::EstimatorOutput out;
  est.update(inputs[0], out);  // the first update initialises; it allocates nothing either
  long n = allocationsIn([&] {
    for (int k = 1; k < ticks; ++k) {
      est.update(inputs[k], out);
      if (k % 100 == 0) est.correctPosition(out.basePosition, 1e-4 * Eigen::Matrix3d::Identity());
      if (k == 700) est.setSettings(other);
    }
  });
  EXPECT_EQ(n, 0);
  estimation::StateEstimator fresh(m, estimatorSettings());
  n = allocationsIn([&] { fresh.update(inputs[0], out); });
  EXPECT_EQ(n, 0);
}

}  // namespace
}  // namespace ballast::test
