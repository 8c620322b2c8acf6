// Every estimator setting is checked in one place, and the message names the profile key.
#include <gtest/gtest.h>

#include <cmath>

#include "estimation/state_estimator.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using estimation::EstimatorSettings;
using estimation::estimatorNumberKeys;
using estimation::validateSettings;

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

TEST(EstimatorSettings, DefaultsAreValidAndWithinTheirBounds) {
  EXPECT_EQ(validateSettings(EstimatorSettings{}, humanoid()), "");
  const EstimatorSettings s;
  for (const auto& k : estimatorNumberKeys()) {
    EXPECT_GE(s.*k.field, k.min) << k.key;
    EXPECT_LE(s.*k.field, k.max) << k.key;
  }
}

TEST(EstimatorSettings, EveryNumberOutOfRangeNamesItsKey) {
  for (const auto& k : estimatorNumberKeys()) {
    for (double bad : {k.min - 1.0 - std::abs(k.min), k.max * 2 + 1, std::nan(""), HUGE_VAL}) {
      EstimatorSettings s;
      s.*k.field = bad;
      const std::string error = validateSettings(s, humanoid());
      EXPECT_TRUE(startsWith(error, std::string("estimator.") + k.key + ": must be in ["))
          << k.key << " = " << bad << ": " << error;
    }
  }
}

TEST(EstimatorSettings, FramesAreCheckedAgainstTheModel) {
  EstimatorSettings s;
  s.imuFrame = "imu_typo";
  EXPECT_TRUE(startsWith(validateSettings(s, humanoid()), "robot.imu_frame: the model "));
  s.imuFrame = "left_foot";
  EXPECT_EQ(validateSettings(s, humanoid()),
            "robot.imu_frame: 'left_foot' is not rigidly attached to the floating base 'pelvis'");
  s = EstimatorSettings{};
  s.contactFrames[2] = "right_toes";
  EXPECT_TRUE(startsWith(validateSettings(s, humanoid()), "robot.contact_frames[2]: the model "));
  s.contactFrames[2] = "left_toe";
  EXPECT_EQ(validateSettings(s, humanoid()), "robot.contact_frames[2]: 'left_toe' is listed twice");
  s.contactFrames[2] = "pelvis";
  EXPECT_TRUE(startsWith(validateSettings(s, humanoid()),
                         "robot.contact_frames[2]: 'pelvis' is on the floating base"));
  s = EstimatorSettings{};
  s.period = 0.0;
  EXPECT_TRUE(startsWith(validateSettings(s, humanoid()), "control.rate: "));
}

TEST(EstimatorSettings, ConstructorRefusesBadSettingsAndSwitchKeepsFrames) {
  EstimatorSettings bad;
  bad.footHeightNoise = -1;
  EXPECT_THROW(estimation::StateEstimator(humanoid(), bad), std::invalid_argument);

  estimation::StateEstimator est(humanoid(), EstimatorSettings{});
  EstimatorSettings tuned;
  tuned.kinematicsVelocityNoise = 0.1;
  EXPECT_TRUE(est.setSettings(tuned));
  EXPECT_EQ(est.settings().kinematicsVelocityNoise, 0.1);
  EstimatorSettings moved = tuned;
  moved.contactFrames[0] = "left_foot";
  EXPECT_FALSE(est.setSettings(moved));
  EXPECT_EQ(est.settings().contactFrames[0], "left_toe");
}

}  // namespace
}  // namespace ballast::test
