// Every estimator setting is checked in one place, and the problem names the field (the profile
// layer names its key).
#include <gtest/gtest.h>

#include <cmath>

#include "estimation/state_estimator.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using estimation::EstimatorSettings;
using estimation::validateSettings;

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

/// Every number of the settings.
const std::vector<double EstimatorSettings::*>& numbers() {
  using S = EstimatorSettings;
  static const std::vector<double S::*> fields{
      &S::gyroNoiseDensity,        &S::gyroBiasRandomWalk,      &S::gyroBiasInitial,
      &S::orientationNoise,        &S::accelerometerNoiseDensity, &S::kinematicsPositionNoise,
      &S::kinematicsVelocityNoise, &S::kinematicsVelocityGate,  &S::footHeightNoise,
      &S::contactDriftNoise,       &S::swingNoiseScale,         &S::initialPositionNoise,
      &S::initialVelocityNoise,    &S::contactForceThreshold,   &S::contactForceRelease,
      &S::contactForceReleaseTime, &S::contactForceBandwidth};
  return fields;
}

TEST(EstimatorSettings, DefaultsAreValid) {
  EXPECT_FALSE(validateSettings(estimatorSettings(), humanoid()));
}

TEST(EstimatorSettings, EveryNumberOutOfRangeNamesItsField) {
  for (double EstimatorSettings::*field : numbers()) {
    for (double bad : {-1.0, std::nan(""), HUGE_VAL}) {
      EstimatorSettings s = estimatorSettings();
      s.*field = bad;
      const model::SettingsProblem problem = validateSettings(s, humanoid());
      EXPECT_EQ(problem.field, &(s.*field)) << bad << ": " << problem.message;
      EXPECT_TRUE(startsWith(problem.message, "must be")) << problem.message;
    }
  }
}

TEST(EstimatorSettings, FramesAreCheckedAgainstTheModel) {
  EstimatorSettings s = estimatorSettings();
  s.imuFrame = "imu_typo";
  EXPECT_EQ(validateSettings(s, humanoid()).field, &s.imuFrame);
  EXPECT_TRUE(startsWith(validateSettings(s, humanoid()).message, "the model "));
  s.imuFrame = "left_foot";
  EXPECT_EQ(validateSettings(s, humanoid()).message,
            "'left_foot' is not rigidly attached to the floating base 'pelvis'");
  s = estimatorSettings();
  s.contactFrames[2] = "right_toes";
  EXPECT_EQ(validateSettings(s, humanoid()).field, &s.contactFrames[2]);
  EXPECT_TRUE(startsWith(validateSettings(s, humanoid()).message, "the model "));
  s.contactFrames[2] = "left_toe";
  EXPECT_EQ(validateSettings(s, humanoid()).message, "'left_toe' is listed twice");
  s.contactFrames[2] = "pelvis";
  EXPECT_TRUE(startsWith(validateSettings(s, humanoid()).message, "'pelvis' is on the floating base"));
  s = estimatorSettings();
  s.period = 0.0;
  EXPECT_EQ(validateSettings(s, humanoid()).field, &s.period);
}

TEST(EstimatorSettings, ConstructorRefusesBadSettingsAndSwitchKeepsFrames) {
  EstimatorSettings bad = estimatorSettings();
  bad.footHeightNoise = -1;
  EXPECT_THROW(estimation::StateEstimator(humanoid(), bad), std::invalid_argument);

  estimation::StateEstimator est(humanoid(), estimatorSettings());
  EstimatorSettings tuned = estimatorSettings();
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
