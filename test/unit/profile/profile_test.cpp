// Profiles: every problem is reported as file:line:column: key: what; extends merges maps and
// replaces scalars and lists; the shipped profiles load; the man page is the schema's.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "profile/profile.hpp"
#include "profile/settings.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::profile {
namespace {

namespace fs = std::filesystem;

class ProfileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ballast-profile-test-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  /// A minimal valid profile on the humanoid, to extend in tests.
  std::string base() {
    return write("base.yaml", "robot:\n  urdf: " + test::humanoidUrdf() + R"(
  joint_groups:
    legs: [left_hip_yaw, left_hip_roll, left_hip_pitch, left_knee, left_ankle_pitch, left_ankle_roll,
           right_hip_yaw, right_hip_roll, right_hip_pitch, right_knee, right_ankle_pitch, right_ankle_roll]
    arms: [left_shoulder_pitch, left_shoulder_roll, left_shoulder_yaw, left_elbow, left_wrist_yaw, left_wrist_pitch,
           right_shoulder_pitch, right_shoulder_roll, right_shoulder_yaw, right_elbow, right_wrist_yaw, right_wrist_pitch]
  nominal_posture: {left_hip_pitch: -0.4, left_knee: 0.8, left_ankle_pitch: -0.4,
                    right_hip_pitch: -0.4, right_knee: 0.8, right_ankle_pitch: -0.4}
control:
  joint_kp: {legs: 300, arms: 80}
  joint_kd: {legs: 8, arms: 2}
backend:
  name: fake
  fake:
    base_height: 0.9
    faults:
      at: 3
)");
  }
  /// The problems loading path reports (empty if it loads).
  std::vector<std::string> problems(const std::string& path) {
    try {
      const Profile p = Profile::load(path);
      buildSettings(p, loadModel(p));
    } catch (const ProfileError& e) {
      return e.problems;
    }
    return {};
  }
  fs::path dir_;
};

TEST_F(ProfileTest, MinimalProfileLoadsWithDefaults) {
  const Profile p = Profile::load(base());
  EXPECT_EQ(p.name(), "base");
  EXPECT_EQ(p.number("control.rate"), 1000.0);
  EXPECT_EQ(p.origin("control.rate").str(), "default");
  EXPECT_EQ(p.text("wbc.variant"), "hierarchical");
  EXPECT_EQ(p.numbers("planner.q_base_position").size(), 3u);
  EXPECT_EQ(p.origin("backend.name").str(), p.path() + ":14:9");
  const control::ControlSettings s = buildSettings(p, loadModel(p));
  EXPECT_EQ(s.num_joints, 24);
  EXPECT_DOUBLE_EQ(s.kp[3], 300.0);  // left_knee is a leg joint
  EXPECT_DOUBLE_EQ(s.kd[12], 2.0);   // left_shoulder_pitch is an arm joint
}

TEST_F(ProfileTest, EveryDefaultIsValid) {
  // finish() checks every default against its own key and throws std::logic_error otherwise.
  EXPECT_NO_THROW(Profile::load(base()));
  for (const Key& k : schema()) EXPECT_NE(std::string(k.doc), "") << k.name;
}

TEST_F(ProfileTest, UnknownKeySuggestsTheClosest) {
  base();
  const auto p = problems(write("p.yaml", "extends: base\ngait:\n  perod: 0.5\n"));
  ASSERT_EQ(p.size(), 1u) << testing::PrintToString(p);
  EXPECT_EQ(p[0], (dir_ / "p.yaml").string() +
                      ":3:3: gait.perod: unknown key (did you mean gait.period?); "
                      "ballast-profile(5) lists every key");
}

TEST_F(ProfileTest, EveryProblemOfAFileAtOnceWithLineAndColumn) {
  base();
  const std::string path = write("p.yaml", R"(extends: base
control:
  rate: fast
  stand_up_duration: 100
wbc:
  variant: tiered
planner:
  q_base_orientation: [1, 2]
gait:
  period: 0.5
  period: 0.6
safety:
  fall_on_non_foot_contact: maybe
)");
  const auto p = problems(path);
  ASSERT_EQ(p.size(), 6u) << testing::PrintToString(p);
  EXPECT_EQ(p[0], path + ":3:9: control.rate: expected a number, got 'fast'");
  EXPECT_EQ(p[1], path + ":4:22: control.stand_up_duration: 100 is out of range [0.1, 30] s");
  EXPECT_EQ(p[2], path + ":6:12: wbc.variant: expected one of hierarchical|weighted|inverse_dynamics, got 'tiered'");
  EXPECT_EQ(p[3],
            path + ":8:23: planner.q_base_orientation: expected a list of 3 numbers, got a list of 2");
  EXPECT_EQ(p[4], path + ":11:3: gait.period: given twice (first at " + path + ":10:3)");
  EXPECT_EQ(p[5],
            path + ":13:29: safety.fall_on_non_foot_contact: expected true or false, got 'maybe'");
}

TEST_F(ProfileTest, ABarrierWithoutItsQuadraticPartIsRefusedByName) {
  base();
  const std::string path = write("p.yaml", R"(extends: base
planner:
  joint_limit_stop: [10, 0, 0.15]
)");
  const auto p = problems(path);
  ASSERT_EQ(p.size(), 1u) << testing::PrintToString(p);
  EXPECT_NE(p[0].find("planner.joint_limit_stop: delta (the second number) must be positive"),
            std::string::npos)
      << p[0];
  // No weight, no barrier: its delta does not matter.
  const std::string off = write("off.yaml", R"(extends: base
planner:
  joint_limit_stop: [0, 0, 0.15]
)");
  EXPECT_TRUE(problems(off).empty()) << testing::PrintToString(problems(off));
}

TEST_F(ProfileTest, APlanAgeBeyondTheHorizonIsRefused) {
  base();
  // The loop tracks the plan in force up to safety.max_plan_age: a plan covers planner.horizon.
  const std::string path = write("p.yaml", R"(extends: base
planner:
  horizon: 0.4
safety:
  max_plan_age: 0.5
)");
  const auto p = problems(path);
  ASSERT_EQ(p.size(), 1u) << testing::PrintToString(p);
  EXPECT_NE(p[0].find("safety.max_plan_age: must be shorter than planner.horizon"),
            std::string::npos)
      << p[0];
  const std::string within = write("within.yaml", R"(extends: base
planner:
  horizon: 0.4
safety:
  max_plan_age: 0.3
)");
  EXPECT_TRUE(problems(within).empty()) << testing::PrintToString(problems(within));
}

TEST_F(ProfileTest, YamlSyntaxErrorNamesLineAndColumn) {
  const std::string path = write("p.yaml", "robot:\n  urdf: [a, b\ncontrol: {}\n");
  const auto p = problems(path);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].rfind(path + ":3:", 0), 0u) << p[0];
  EXPECT_NE(p[0].find("YAML syntax"), std::string::npos);
}

TEST_F(ProfileTest, SectionMustBeAMapAndTopLevelAMap) {
  base();
  auto p = problems(write("p.yaml", "extends: base\ngait: 3\n"));
  ASSERT_EQ(p.size(), 1u) << testing::PrintToString(p);
  EXPECT_EQ(p[0], (dir_ / "p.yaml").string() +
                      ":2:7: gait: is a section: expected a map of its keys, got '3'");
  p = problems(write("q.yaml", "- a\n- b\n"));
  ASSERT_EQ(p.size(), 1u) << testing::PrintToString(p);
  EXPECT_NE(p[0].find("a profile is a YAML map of sections"), std::string::npos);
}

TEST_F(ProfileTest, ExtendsMergesMapsAndReplacesScalarsAndLists) {
  base();
  const Profile p = Profile::load(write("p.yaml", R"(extends: base
robot:
  nominal_posture: {left_elbow: -20deg}
  contact_frames: [left_heel, left_toe, right_heel, right_toe]
control:
  joint_kp: {arms: 50}
  rate: 500
)"));
  const auto posture = p.numberMap("robot.nominal_posture");
  EXPECT_DOUBLE_EQ(posture.at("left_knee"), 0.8);                      // from the base: maps merge
  EXPECT_NEAR(posture.at("left_elbow"), -20.0 * M_PI / 180.0, 1e-12);  // deg suffix
  EXPECT_EQ(p.value("robot.contact_frames")[0].Scalar(), "left_heel");  // lists replace
  EXPECT_EQ(p.numberMap("control.joint_kp").at("legs"), 300.0);
  EXPECT_EQ(p.numberMap("control.joint_kp").at("arms"), 50.0);
  EXPECT_EQ(p.number("control.rate"), 500.0);
  EXPECT_EQ(p.origin("control.rate").line, 7);
  EXPECT_EQ(p.origin("control.joint_kp", "legs").file, (dir_ / "base.yaml").string());
  EXPECT_EQ(p.files().size(), 2u);
}

TEST_F(ProfileTest, PathsAreRelativeToTheFileThatSetsThem) {
  fs::create_directories(dir_ / "sub");
  base();
  const Profile p =
      Profile::load(write("sub/p.yaml", "extends: ../base.yaml\nterrain:\n  map: maps/x.bt\n"));
  EXPECT_EQ(p.text("terrain.map"), (dir_ / "sub/maps/x.bt").string());
  EXPECT_EQ(p.text("robot.urdf"), test::humanoidUrdf());
}

TEST_F(ProfileTest, ExtendsCycleAndMissingBase) {
  write("a.yaml", "extends: b\n");
  write("b.yaml", "extends: a.yaml\n");
  auto p = problems((dir_ / "a.yaml").string());
  ASSERT_FALSE(p.empty());
  EXPECT_NE(p[0].find("extends: cycle"), std::string::npos) << p[0];
  p = problems(write("c.yaml", "extends: nowhere\n"));
  ASSERT_FALSE(p.empty());
  EXPECT_EQ(
      p[0].rfind(
          (dir_ / "c.yaml").string() + ":1:10: extends: profile 'nowhere': no nowhere.yaml in", 0),
      0u)
      << p[0];
}

TEST_F(ProfileTest, ModelChecksNameTheEntry) {
  base();
  const std::string path = write("p.yaml", R"(extends: base
robot:
  nominal_posture:
    left_knees: 0.5
    right_knee: 3.0
control:
  joint_kp: {torso: 10}
)");
  const auto p = problems(path);
  ASSERT_EQ(p.size(), 3u) << testing::PrintToString(p);
  EXPECT_EQ(p[0].rfind(path + ":4:5: robot.nominal_posture.left_knees: no movable joint", 0), 0u)
      << p[0];
  EXPECT_EQ(p[1].rfind(path + ":5:5: robot.nominal_posture.right_knee: 3 rad is outside the "
                              "joint's limits [0, 2.4]",
                       0),
            0u)
      << p[1];
  EXPECT_EQ(p[2].rfind(path + ":7:14: control.joint_kp.torso: no joint group of that name", 0), 0u)
      << p[2];
}

// A vendor's URDF has no links at the toes and heels: the profile places the points on the foot's
// link. On the humanoid they land exactly where its own toe and heel links are.
TEST_F(ProfileTest, ContactPointsAndImuTakeALinkAndAnOffset) {
  base();
  const std::string path = write("p.yaml", R"(extends: base
robot:
  contact_frames:
    - {link: left_foot, offset: [0.13, 0, -0.06]}
    - {link: left_foot, offset: [-0.07, 0, -0.06]}
    - right_toe
    - {link: right_foot, offset: [-0.07, 0, -0.06]}
  imu_frame: {link: pelvis, offset: [0, 0, 0.04], rpy: [0, 0, 90deg]}
)");
  const Profile p = Profile::load(path);
  const model::Model m = loadModel(p);
  const Settings s = settingsFor(p, m);
  EXPECT_EQ(s.control.contact_frames[0], "left_toe@left_foot");
  EXPECT_EQ(s.control.contact_frames[2], "right_toe");  // a link stays a link
  EXPECT_EQ(s.control.imu_frame, "imu@pelvis");
  EXPECT_EQ(s.control.estimator.contactFrames[1], "left_heel@left_foot");
  const char* own[] = {"left_toe", "left_heel", "right_toe", "right_heel"};
  for (int i = 0; i < 4; ++i) {
    const model::Frame& placed = m.frames[m.frameId(s.control.contact_frames[i])];
    const model::Frame& link = m.frames[m.frameId(own[i])];
    EXPECT_EQ(placed.body, link.body) << own[i];
    EXPECT_TRUE(placed.placement.p.isApprox(link.placement.p, 1e-12)) << own[i];
  }
  const model::Frame& imu = m.frames[m.frameId("imu@pelvis")];
  const model::Frame& imuLink = m.frames[m.frameId("imu")];
  EXPECT_TRUE(imu.placement.p.isApprox(imuLink.placement.p, 1e-12));
  EXPECT_NEAR(imu.placement.R(1, 0), 1.0, 1e-12);  // x of the IMU along the pelvis' y: yaw 90°
}

TEST_F(ProfileTest, AMissingLinkNamesItsElementAndTheClosestLinks) {
  base();
  const std::string path = write("p.yaml", R"(extends: base
robot:
  contact_frames:
    - left_toe
    - {link: left_fot, offset: [-0.07, 0, -0.06]}
    - right_toe
    - right_heal
  imu_frame: {link: pelvis_link, offset: [0, 0, 0.04]}
)");
  const auto p = problems(path);
  ASSERT_EQ(p.size(), 2u) << testing::PrintToString(p);
  EXPECT_EQ(p[0].rfind(path + ":5:7: robot.contact_frames[1]: no link named 'left_fot' in " +
                           test::humanoidUrdf() + "; closest: left_foot",
                       0),
            0u)
      << p[0];
  EXPECT_EQ(p[1].rfind(path + ":8:14: robot.imu_frame: no link named 'pelvis_link' in " +
                           test::humanoidUrdf() + "; closest: pelvis",
                       0),
            0u)
      << p[1];
  // A link name alone, once the placed frames are found: the same message at its element.
  const std::string plain = write("q.yaml", R"(extends: base
robot:
  contact_frames: [left_toe, left_heel, right_toe, right_heal]
)");
  const auto q = problems(plain);
  ASSERT_EQ(q.size(), 1u) << testing::PrintToString(q);
  EXPECT_EQ(q[0].rfind(plain + ":3:52: robot.contact_frames[3]: no link named 'right_heal' in " +
                           test::humanoidUrdf() + "; closest: right_heel",
                       0),
            0u)
      << q[0];
}

TEST_F(ProfileTest, AFrameIsALinkOrALinkWithAnOffset) {
  base();
  const std::string path = write("p.yaml", R"(extends: base
robot:
  contact_frames:
    - {link: left_foot, offset: [0.13, 0], rpy: [0, 0, 0]}
    - {link: left_foot, rpy: [0, 0, 0]}
    - {offset: [0, 0, 0]}
    - [right_heel]
  imu_frame: {link: pelvis, offset: [0, 0, 0.04], up: 1}
)");
  try {
    Profile::load(path);
    FAIL() << "loaded";
  } catch (const ProfileError& e) {
    ASSERT_EQ(e.problems.size(), 2u) << testing::PrintToString(e.problems);
    EXPECT_EQ(e.problems[0], path + ":4:33: robot.contact_frames[0].offset: expected a list of 3 "
                                    "numbers, got a list of 2")
        << e.problems[0];
    EXPECT_EQ(e.problems[1].rfind(path + ":8:51: robot.imu_frame.up: unknown field: a frame has "
                                         "link, offset, rpy",
                                  0),
              0u)
        << e.problems[1];
  }
  const std::string rpy = write("q.yaml", R"(extends: base
robot:
  contact_frames: [left_toe, {link: left_foot, rpy: [0, 0, 0]}, right_toe, right_heel]
)");
  try {
    Profile::load(rpy);
    FAIL() << "loaded";
  } catch (const ProfileError& e) {
    ASSERT_EQ(e.problems.size(), 1u);
    EXPECT_NE(e.problems[0].find("robot.contact_frames[1].rpy: unknown field: a frame has link, "
                                 "offset (a contact point is a point: no rpy)"),
              std::string::npos)
        << e.problems[0];
  }
}

// robot.locked_joints: fixed at their angle in the model, in no group; a name the URDF lacks is
// reported at its entry.
// The settings say whether the robot can turn: the humanoid can, with its wrists locked too;
// with both hip yaws locked its feet stay parallel to the pelvis and it cannot; one is enough.
TEST_F(ProfileTest, TheSettingsSayWhetherTheFeetCanYaw) {
  base();
  auto cannotYaw = [&](const std::string& path) {
    const Profile p = Profile::load(path);
    const model::Model m = loadModel(p);
    return settingsFor(p, m).control.feet_cannot_yaw;
  };
  EXPECT_EQ(cannotYaw(write("a.yaml", "extends: base\n")), "");
  const std::string both = cannotYaw(write("b.yaml", R"(extends: base
robot:
  locked_joints: {left_hip_yaw: 0, right_hip_yaw: 0}
  joint_groups:
    legs: [left_hip_roll, left_hip_pitch, left_knee, left_ankle_pitch, left_ankle_roll,
           right_hip_roll, right_hip_pitch, right_knee, right_ankle_pitch, right_ankle_roll]
)"));
  EXPECT_NE(both.find("no joint of either leg turns its foot about the vertical"), std::string::npos)
      << both;
  EXPECT_EQ(cannotYaw(write("c.yaml", R"(extends: base
robot:
  locked_joints: {left_hip_yaw: 0}
  joint_groups:
    legs: [left_hip_roll, left_hip_pitch, left_knee, left_ankle_pitch, left_ankle_roll,
           right_hip_yaw, right_hip_roll, right_hip_pitch, right_knee, right_ankle_pitch, right_ankle_roll]
)")), "");
}

TEST_F(ProfileTest, LockedJointsLeaveTheModelAndTheGroups) {
  base();
  const std::string path = write("p.yaml", R"(extends: base
robot:
  locked_joints: {left_wrist_yaw: 0.2, right_wrist_yaw: -10deg}
  joint_groups:
    arms: [left_shoulder_pitch, left_shoulder_roll, left_shoulder_yaw, left_elbow, left_wrist_pitch,
           right_shoulder_pitch, right_shoulder_roll, right_shoulder_yaw, right_elbow, right_wrist_pitch]
)");
  const Profile p = Profile::load(path);
  const model::Model m = loadModel(p);
  EXPECT_EQ(m.nj(), 22);
  EXPECT_LT(m.findJoint("left_wrist_yaw"), 0);
  const Settings s = settingsFor(p, m);
  EXPECT_NEAR(s.joints.locked.at("right_wrist_yaw"), -10.0 * M_PI / 180.0, 1e-12);
  EXPECT_EQ(s.control.num_joints, 22);

  const std::string bad = write("q.yaml", R"(extends: base
robot:
  locked_joints: {left_wrist_yaw: 0.2, left_wrist_yew: 0}
)");
  const auto q = problems(bad);
  ASSERT_EQ(q.size(), 1u) << testing::PrintToString(q);
  EXPECT_EQ(q[0].rfind(bad + ":3:40: robot.locked_joints.left_wrist_yew: " + test::humanoidUrdf() +
                           " has no joint 'left_wrist_yew'",
                       0),
            0u)
      << q[0];
  // Still grouped: the group names a joint the model no longer moves.
  const std::string grouped = write("r.yaml", R"(extends: base
robot:
  locked_joints: {left_wrist_yaw: 0.2}
)");
  const auto r = problems(grouped);
  ASSERT_FALSE(r.empty());
  EXPECT_NE(r[0].find("robot.joint_groups.arms: no movable joint named 'left_wrist_yaw'"),
            std::string::npos)
      << r[0];
}

TEST_F(ProfileTest, EveryJointNeedsAGroupAndEveryGroupGains) {
  const std::string path = write("p.yaml", "robot:\n  urdf: " + test::humanoidUrdf() +
                                               "\n  joint_groups:\n    legs: [left_knee]\n"
                                               "control:\n  joint_kd: {legs: 1}\n");
  const auto p = problems(path);
  ASSERT_EQ(p.size(), 2u) << testing::PrintToString(p);
  EXPECT_NE(p[0].find("robot.joint_groups: joints in no group: left_hip_yaw"), std::string::npos);
  EXPECT_NE(p[1].find("control.joint_kp: no entry for joint group 'legs'"), std::string::npos);
}

TEST_F(ProfileTest, BackendSectionIsTheFilesOwnLines) {
  const Profile p = Profile::load(base());
  const Profile::BackendSection s = p.backendSection();
  EXPECT_EQ(s.origin, p.path() + ":16");  // the line of "base_height"
  EXPECT_EQ(s.yaml, "    base_height: 0.9\n    faults:\n      at: 3\n");
}

TEST_F(ProfileTest, MergedBackendSectionIsReemittedAndProblemsRelocated) {
  base();
  const std::string path =
      write("p.yaml", "extends: base\nbackend:\n  fake:\n    faults: {stale: 2}\n");
  const Profile p = Profile::load(path);
  const YAML::Node merged = YAML::Load(p.backendSection().yaml);
  EXPECT_EQ(merged["base_height"].as<double>(), 0.9);
  EXPECT_EQ(merged["faults"]["at"].as<int>(), 3);
  EXPECT_EQ(merged["faults"]["stale"].as<int>(), 2);
  EXPECT_EQ(p.locateBackendProblem("x.yaml:9:9: faults.stale: must be positive"),
            path + ":4:14: faults.stale: must be positive");
  EXPECT_EQ(p.locateBackendProblem("x.yaml:9:9: base_height: too high"),
            (dir_ / "base.yaml").string() + ":16:5: base_height: too high");
  EXPECT_EQ(p.locateBackendProblem("no location here"), "no location here");
}

TEST_F(ProfileTest, AnotherBackendsSectionIsAnErrorOnlyWhereTheBackendIsNamed) {
  base();
  auto p = problems(write("p.yaml", "extends: base\nbackend:\n  faek: {a: 1}\n"));
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].find(":3:3: backend.faek: unknown key: the backend's own section is named after "
                      "backend.name (backend.fake)"),
            std::string::npos)
      << p[0];
  // Switching backend in a derived profile ignores the inherited section of the old one.
  p = problems(write("q.yaml", "extends: base\nbackend:\n  name: other\n  other: {x: 1}\n"));
  EXPECT_TRUE(p.empty()) << testing::PrintToString(p);
}

TEST_F(ProfileTest, RestartChangesListsOnlyRestartKeys) {
  const Profile a = Profile::load(base());
  const Profile b = Profile::load(
      write("b.yaml", "extends: base\ncontrol:\n  rate: 500\n  stand_up_duration: 3\n"));
  const auto changed = Profile::restartChanges(a, b);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].rfind("control.rate", 0), 0u);
  const Profile c =
      Profile::load(write("c.yaml", "extends: base\nbackend:\n  fake: {base_height: 1.0}\n"));
  ASSERT_EQ(Profile::restartChanges(a, c).size(), 1u);
  EXPECT_EQ(Profile::restartChanges(a, c)[0], "backend.fake");
}

TEST_F(ProfileTest, DescribeShowsValuesWithOrigins) {
  const Profile p = Profile::load(base());
  const std::string d = p.describe();
  EXPECT_NE(d.find("  rate: 1000  # default\n"), std::string::npos) << d;
  EXPECT_NE(d.find("  name: fake  # " + p.path() + ":14:9\n"), std::string::npos) << d;
  EXPECT_NE(d.find("    left_knee: 0.8  # " + p.path()), std::string::npos) << d;
}

TEST(ShippedProfiles, LoadAndCheckAgainstTheModel) {
  // Every profile shipped, the study's too: one added is checked without naming it here.
  int shipped = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(std::string(BALLAST_SOURCE_DIR) + "/profiles")) {
    if (entry.path().extension() != ".yaml") continue;
    ++shipped;
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    try {
      const Profile p = Profile::load(path);
      const control::ControlSettings s = buildSettings(p, loadModel(p));
      EXPECT_EQ(s.num_joints, 24);
    } catch (const ProfileError& e) {
      ADD_FAILURE() << e.what();
    }
  }
  EXPECT_GE(shipped, 12);
  const Profile flat = Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml");
  EXPECT_EQ(flat.text("backend.name"), "simbody");
  // The MuJoCo profiles are the Simbody ones with another backend.
  for (const char* name : {"sim-flat", "sim-stage", "sim-rough"}) {
    const Profile simbody = Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/" + name + ".yaml");
    const Profile mujoco =
        Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/" + name + "-mujoco.yaml");
    EXPECT_EQ(mujoco.text("backend.name"), "mujoco");
    EXPECT_EQ(mujoco.text("terrain.map"), simbody.text("terrain.map")) << name;
    EXPECT_EQ(mujoco.text("robot.urdf"), simbody.text("robot.urdf")) << name;
  }
  const Profile hw =
      Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/hardware-example.yaml");
  EXPECT_EQ(hw.text("backend.name"), "socketcan");
  EXPECT_EQ(hw.text("control.initial_mode"), "passive");
}

TEST(ManPage, IsGeneratedFromTheSchema) {
  std::ifstream in(std::string(BALLAST_SOURCE_DIR) + "/man/ballast-profile.5");
  ASSERT_TRUE(in) << "man/ballast-profile.5 is missing";
  std::stringstream text;
  text << in.rdbuf();
  // The whole file against ballastd's output, with the plugins' sections, is
  // DumpSchema.TheManPageIsBallastdsOutputWithEveryBackendsSection; here the daemon's part.
  const std::string page = schemaManPage();
  const std::string keys = page.substr(0, page.find(".SH BRINGING UP A NEW ROBOT"));
  EXPECT_EQ(text.str().rfind(keys, 0), 0u)
      << "man/ballast-profile.5 differs from the schema: regenerate it with\n"
         "  build/bin/ballastd --dump-schema=man > man/ballast-profile.5";
  for (const Key& k : schema()) {
    std::string escaped;
    for (char c : std::string(k.name)) escaped += c == '-' ? std::string("\\-") : std::string(1, c);
    EXPECT_NE(text.str().find(".B " + escaped + "\n"), std::string::npos) << k.name;
  }
}

}  // namespace
}  // namespace ballast::profile

namespace ballast::profile {
namespace {

namespace fs = std::filesystem;

TEST(WbcSettings, FromTheShippedProfileAndTheirProblemsLocated) {
  const Profile p = Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml");
  const wbc::WbcSettings s = settingsFor(p, loadModel(p)).control.wbc;
  EXPECT_EQ(s.variant, wbc::WbcVariant::kHierarchical);
  EXPECT_EQ(s.jointSpaceJoints.size(), 12u);  // the arms group
  EXPECT_EQ(s.jointSpaceJoints[0], "left_shoulder_pitch");
  EXPECT_EQ(s.contactFrames.size(), 4u);
  EXPECT_DOUBLE_EQ(s.period, 0.001);
  EXPECT_EQ(s.torqueLimit.size(), 24u);
  const std::string dir = ::testing::TempDir();
  const std::string bad = dir + "/wbc-bad.yaml";
  std::ofstream(bad) << "extends: " << p.path() << "\nwbc:\n  base_frame: left_toe\n";
  const Profile q = Profile::load(bad);
  try {
    settingsFor(q, loadModel(q));
    ADD_FAILURE() << "a base frame off the base was accepted";
  } catch (const ProfileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(q.path() + ":3:15: wbc.base_frame: ", 0), 0u)
        << "message: " << e.what();
  }
}

// The libraries name the field at fault; the profile layer names the key, also for fields the
// settings derive from a key (the estimator's copy of the contact frames, the control period).
TEST(Settings, LibraryProblemsAreNamedByTheKeyOfTheirField) {
  const Settings s = defaultSettings();
  EXPECT_STREQ(keyOf(s, &s.control.wbc.frictionCoefficient), "wbc.friction_coefficient");
  EXPECT_STREQ(keyOf(s, &s.control.wbc.baseKp[4]), "wbc.base_kp");
  EXPECT_STREQ(keyOf(s, &s.control.estimator.contactFrames[2]), "robot.contact_frames");
  EXPECT_STREQ(keyOf(s, &s.control.estimator.period), "control.rate");
  EXPECT_STREQ(keyOf(s, &s.control.locomotion.walkGait.period), "gait.period");
  EXPECT_STREQ(keyOf(s, &s.server.max_clients), "server.max_clients");
  EXPECT_EQ(keyOf(s, &s.control.num_joints), nullptr);  // the model's, no key's
  // The loop names its limits in messages through the settings it holds (a copy will do).
  const control::ControlSettings c = s.control;
  EXPECT_STREQ(control::settingName(c, &c.max_plan_age, "limit"), "safety.max_plan_age");
  control::ControlSettings bare = c;
  bare.key_of = nullptr;
  EXPECT_STREQ(control::settingName(bare, &bare.max_plan_age, "limit"), "limit");
}

// Every default is read by the same code as a profile, obeys its key's bounds and the rules,
// and is what a profile that sets nothing gets.
TEST(Settings, EveryDefaultParsesAndValidates) {
  for (const schema::Row<Settings>& row : schema()) {
    schema::Value v;
    schema::Problem problem;
    EXPECT_TRUE(schema::read(row, YAML::Load(*row.defaultYaml ? row.defaultYaml : "\"\""), v, problem))
        << row.name << ": " << problem.what;
  }
  const Settings d = defaultSettings();
  EXPECT_TRUE(table().broken(d).empty());
  EXPECT_DOUBLE_EQ(d.control.min_pose_height, 0.7);
  EXPECT_DOUBLE_EQ(d.control.max_pose_height, 0.95);

  const std::string path =
      ::testing::TempDir() + "/ballast-nothing-set-" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(path) << "robot:\n  urdf: " << test::humanoidUrdf() << "\n";
  const Settings p = readSettings(Profile::load(path));
  for (const schema::Row<Settings>& row : schema()) {
    if (row.type != schema::Type::kBool && row.type != schema::Type::kInteger &&
        row.type != schema::Type::kNumber && row.type != schema::Type::kNumbers)
      continue;
    if (row.type == schema::Type::kNumbers && row.size % sizeof(double) != 0) continue;
    EXPECT_EQ(std::memcmp(row.field(p), row.field(d), row.size), 0) << row.name;
  }
  EXPECT_EQ(p.control.contact_frames, d.control.contact_frames);
  EXPECT_EQ(p.control.wbc.baseFrame, d.control.wbc.baseFrame);
  EXPECT_EQ(p.joints.joint_space, d.joints.joint_space);
  std::remove(path.c_str());
}

// `ballastd --dump-schema=yaml` is a profile: every key, at its default.
TEST(Settings, TheYamlDumpLoadsAsAProfile) {
  const std::string dir = ::testing::TempDir() + "/ballast-dump-" + std::to_string(::getpid());
  fs::create_directories(dir);
  const std::string dump = fs::path(dir + "/dump.yaml").lexically_normal().string();
  const std::string profile = dir + "/from-dump.yaml";
  std::ofstream(dump) << schemaYaml();
  std::ofstream(profile) << "extends: dump.yaml\nrobot:\n  urdf: " << test::humanoidUrdf() << "\n";
  const Profile p = Profile::load(profile);
  for (const schema::Row<Settings>& row : schema()) {
    if (std::string(row.name) == "robot.urdf" || std::string(row.name) == "extends" || row.isMap())
      continue;
    EXPECT_EQ(p.origin(row.name).file, dump) << row.name << " is not in the dump";
  }
  EXPECT_NO_THROW(readSettings(p));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ballast::profile
