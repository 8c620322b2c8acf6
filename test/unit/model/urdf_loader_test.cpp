// The URDF loader: the humanoid's structure, and a clear error for each kind of broken file.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using model::JointType;
using model::loadUrdfString;
using model::ModelError;

TEST(UrdfLoader, HumanoidStructure) {
  const model::Model& m = humanoid();
  EXPECT_EQ(m.name, "ballast_humanoid");
  EXPECT_EQ(m.nj(), 24);
  EXPECT_EQ(m.nq, 31);
  EXPECT_EQ(m.nv, 30);
  EXPECT_EQ(m.bodyName[0], "pelvis");
  // Depth-first, file order: left leg, right leg, left arm, right arm.
  EXPECT_EQ(m.jointName[1], "left_hip_yaw");
  EXPECT_EQ(m.jointName[6], "left_ankle_roll");
  EXPECT_EQ(m.jointName[7], "right_hip_yaw");
  EXPECT_EQ(m.jointName[13], "left_shoulder_pitch");
  EXPECT_EQ(m.jointName[24], "right_wrist_pitch");
  for (int i = 1; i < m.nbodies(); ++i) {
    EXPECT_LT(m.parent[i], i);
    EXPECT_EQ(m.jointType[i], JointType::Revolute);
    EXPECT_NEAR(m.jointAxis[i].norm(), 1.0, 1e-12);
  }
  for (const char* f : {"left_toe", "left_heel", "right_toe", "right_heel", "imu", "lidar", "torso"})
    EXPECT_GE(m.findFrame(f), 0) << f;
  // Torso and head are merged into the pelvis body.
  EXPECT_EQ(m.frames[m.frameId("torso")].body, 0);
  EXPECT_EQ(m.frames[m.frameId("head")].body, 0);
  EXPECT_NEAR(m.inertia[0].mass, 22.5, 1e-12);
  EXPECT_NEAR(m.frames[m.frameId("head")].placement.p.z(), 0.55, 1e-12);
  EXPECT_EQ(m.frames[m.frameId("left_toe")].body, m.frames[m.frameId("left_foot")].body);
  // Limits as written.
  const int knee = m.jointId("left_knee");
  EXPECT_DOUBLE_EQ(m.lowerPositionLimit[knee], 0.0);
  EXPECT_DOUBLE_EQ(m.upperPositionLimit[knee], 2.4);
  EXPECT_DOUBLE_EQ(m.effortLimit[knee], 250.0);
  EXPECT_DOUBLE_EQ(m.velocityLimit[knee], 14.0);
  EXPECT_THROW(m.frameId("no_such_frame"), ModelError);
  EXPECT_EQ(m.findJoint("waist"), -1);  // fixed joints are not joints of the model
}

// A two-link robot; tests replace pieces of it to break it in one place at a time.
const std::string kInertial =
    R"(<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>)";
std::string tinyRobot(const std::string& childInertial = kInertial,
                      const std::string& jointType = "revolute",
                      const std::string& limit =
                          R"(<limit lower="-1" upper="1" effort="10" velocity="5"/>)",
                      const std::string& axis = R"(<axis xyz="0 1 0"/>)",
                      const std::string& extra = "") {
  return "<?xml version=\"1.0\"?>\n<robot name=\"tiny\">\n"
         "  <link name=\"base\">" + kInertial + "</link>\n"
         "  <link name=\"child\">" + childInertial + "</link>\n"
         "  <joint name=\"j1\" type=\"" + jointType + "\">\n"
         "    <parent link=\"base\"/><child link=\"child\"/>" + axis + limit + "\n"
         "  </joint>\n" + extra + "</robot>\n";
}

/// The loader's message for `xml`, or "" if it loads.
std::string errorFor(const std::string& xml) {
  try {
    loadUrdfString(xml, "tiny.urdf");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(UrdfLoader, TinyRobotLoads) {
  const model::Model m = loadUrdfString(tinyRobot(), "tiny.urdf");
  EXPECT_EQ(m.nj(), 1);
  EXPECT_EQ(m.jointName[1], "j1");
}

TEST(UrdfLoader, MissingFileNamesThePath) {
  try {
    model::loadUrdfFile("/nonexistent/robot.urdf");
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.urdf: cannot read"),
              std::string::npos)
        << e.what();
  }
}

TEST(UrdfLoader, XmlSyntaxErrorHasLineAndColumn) {
  std::string xml = tinyRobot();
  xml.replace(xml.find("</joint>"), 8, "</jont>");
  const std::string msg = errorFor(xml);
  EXPECT_TRUE(std::regex_search(msg, std::regex(R"(^tiny\.urdf:\d+:\d+: XML error)"))) << msg;
}

TEST(UrdfLoader, RootElementMustBeRobot) {
  const std::string msg = errorFor("<?xml version=\"1.0\"?>\n<model name=\"x\"/>\n");
  EXPECT_NE(msg.find("tiny.urdf: the root element is <model>"), std::string::npos) << msg;
}

TEST(UrdfLoader, NotATreeIsRejectedWithUrdfdomsReason) {
  // A second parentless link: two roots.
  const std::string msg = errorFor(tinyRobot(kInertial, "revolute",
                                             R"(<limit lower="-1" upper="1" effort="10" velocity="5"/>)",
                                             R"(<axis xyz="0 1 0"/>)",
                                             "  <link name=\"stray\">" + kInertial + "</link>\n"));
  EXPECT_NE(msg.find("tiny.urdf: invalid URDF:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("root"), std::string::npos) << msg;
}

TEST(UrdfLoader, ACycleHasNoRootAndIsRejected) {
  // base -> child -> base: every link has a parent, so none is the root.
  const std::string msg =
      errorFor(tinyRobot(kInertial, "revolute",
                         R"(<limit lower="-1" upper="1" effort="10" velocity="5"/>)",
                         R"(<axis xyz="0 1 0"/>)",
                         "  <joint name=\"back\" type=\"revolute\">\n"
                         "    <parent link=\"child\"/><child link=\"base\"/><axis xyz=\"0 1 0\"/>"
                         "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"5\"/>\n"
                         "  </joint>\n"));
  EXPECT_NE(msg.find("tiny.urdf: invalid URDF:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("root"), std::string::npos) << msg;
}

TEST(UrdfLoader, DanglingChildLinkIsRejected) {
  std::string xml = tinyRobot();
  xml.replace(xml.find("<child link=\"child\"/>"), 21, "<child link=\"ghost\"/>");
  const std::string msg = errorFor(xml);
  EXPECT_NE(msg.find("tiny.urdf: invalid URDF:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("ghost"), std::string::npos) << msg;
}

TEST(UrdfLoader, UnsupportedJointTypeNamesJointAndLine) {
  const std::string msg = errorFor(tinyRobot(kInertial, "planar"));
  EXPECT_NE(msg.find("tiny.urdf:5:3: <joint name=\"j1\">: type 'planar' is not supported"),
            std::string::npos)
      << msg;
}

TEST(UrdfLoader, FloatingJointInsideTheTreeIsRejected) {
  const std::string msg = errorFor(tinyRobot(kInertial, "floating", ""));
  EXPECT_NE(msg.find("<joint name=\"j1\">: type 'floating'"), std::string::npos) << msg;
}

TEST(UrdfLoader, AJointMovingNoInertiaIsLockedAndSaysWhy) {
  // A link without <inertial>, of zero mass, or a point mass on the axis: the joint moves
  // nothing the dynamics can see, so it is held at zero (within its limits), not a joint.
  const std::string pointOnAxis =
      R"(<inertial><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>)";
  const std::string massless =
      R"(<inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>)";
  for (const std::string& inertial : {std::string(), massless, pointOnAxis}) {
    SCOPED_TRACE(inertial);
    const model::Model m = loadUrdfString(
        tinyRobot(inertial, "revolute", R"(<limit lower="0.2" upper="1" effort="10" velocity="5"/>)"),
        "tiny.urdf");
    EXPECT_EQ(m.nj(), 0);
    ASSERT_EQ(m.lockedJoints.size(), 1u);
    EXPECT_EQ(m.lockedJoints[0].name, "j1");
    EXPECT_DOUBLE_EQ(m.lockedJoints[0].position, 0.2);  // zero is outside its limits
    EXPECT_NE(m.lockedJoints[0].reason.find("no inertia about its axis"), std::string::npos)
        << m.lockedJoints[0].reason;
    EXPECT_EQ(m.frames[m.frameId("child")].body, 0);
  }
  // A point mass off the axis is a pendulum: a joint.
  const std::string pointOffAxis =
      R"(<inertial><origin xyz="0 0 -0.3"/><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>)";
  EXPECT_EQ(loadUrdfString(tinyRobot(pointOffAxis), "tiny.urdf").nj(), 1);
}

/// A second link (`inner` inside <link>) on revolute joint j2 from `parent`, `joint` inside it.
std::string secondLink(const std::string& name, const std::string& parent, const std::string& inner,
                       const std::string& joint) {
  return "  <link name=\"" + name + "\">" + inner + "</link>\n"
         "  <joint name=\"j2\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"" +
         name + "\"/>" + joint +
         "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"5\"/></joint>\n";
}

TEST(UrdfLoader, AMasslessLinkCarryingMovingLinksIsABodyOfZeroInertia) {
  // Vendors chain joints through massless links (a hip's yaw and roll meeting at one point).
  const std::string xml = tinyRobot(
      "", "revolute", R"(<limit lower="-1" upper="1" effort="10" velocity="5"/>)",
      R"(<axis xyz="0 0 1"/>)",
      secondLink("grandchild", "child", kInertial, R"(<origin xyz="0.1 0 0"/><axis xyz="1 0 0"/>)"));
  const model::Model m = loadUrdfString(xml, "tiny.urdf");
  EXPECT_EQ(m.nj(), 2);
  EXPECT_TRUE(m.lockedJoints.empty());
  EXPECT_EQ(m.inertia[1].mass, 0.0);
  model::Data<double> d(m);
  const model::VecX<double> q = model::neutralConfiguration(m);
  model::crba(m, d, q);
  const Eigen::LLT<model::MatX<double>> llt(d.M);
  EXPECT_EQ(llt.info(), Eigen::Success);  // the mass matrix is positive definite
}

TEST(UrdfLoader, AMimicJointIsHeldWhereItsLeaderPutsIt) {
  const std::string xml = tinyRobot(
      kInertial, "revolute", R"(<limit lower="-1" upper="1" effort="10" velocity="5"/>)",
      R"(<axis xyz="0 1 0"/>)",
      secondLink("finger", "child", kInertial,
                 R"(<axis xyz="0 1 0"/><mimic joint="j1" multiplier="-2" offset="0.1"/>)"));
  const model::Model free = loadUrdfString(xml, "tiny.urdf");
  EXPECT_EQ(free.nj(), 1);
  ASSERT_EQ(free.lockedJoints.size(), 1u);
  EXPECT_EQ(free.lockedJoints[0].name, "j2");
  EXPECT_DOUBLE_EQ(free.lockedJoints[0].position, 0.1);  // -2 * 0 + 0.1
  EXPECT_NE(free.lockedJoints[0].reason.find("mimics joint 'j1'"), std::string::npos);
  // Its leader locked at 0.3: -2 * 0.3 + 0.1 = -0.5.
  model::UrdfOptions options;
  options.locked["j1"] = 0.3;
  const model::Model locked = loadUrdfString(xml, "tiny.urdf", options);
  EXPECT_EQ(locked.nj(), 0);
  ASSERT_EQ(locked.lockedJoints.size(), 2u);
  EXPECT_EQ(locked.lockedJoints[0].reason, "locked on request");
  EXPECT_DOUBLE_EQ(locked.lockedJoints[1].position, -0.5);
  // The finger is where j1 at 0.3 and j2 at -0.5 put it: rotated by -0.2 about y in the base.
  const model::Mat3<double> R = locked.frames[locked.frameId("finger")].placement.R;
  EXPECT_NEAR(R(0, 2), std::sin(-0.2), 1e-12);
}

TEST(UrdfLoader, VendorFilesCrlfAndSimulatorElementsLoadAsTheSameModel) {
  std::string vendor = tinyRobot(
      kInertial, "revolute", R"(<limit lower="-1" upper="1" effort="10" velocity="5"/>)",
      R"(<axis xyz="0 1 0"/>)",
      "  <gazebo reference=\"child\"><mu1>0.8</mu1></gazebo>\n"
      "  <transmission name=\"t1\"><type>transmission_interface/SimpleTransmission</type>"
      "<joint name=\"j1\"><hardwareInterface>EffortJointInterface</hardwareInterface></joint>"
      "</transmission>\n"
      "  <mujoco><compiler meshdir=\"meshes\"/></mujoco>\n");
  vendor.replace(vendor.find("<link name=\"child\">") + 19, 0,
                 "<visual><geometry><mesh filename=\"package://robot/meshes/child.STL\"/>"
                 "</geometry></visual>");
  std::string crlf;
  for (const char c : vendor) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const model::Model plain = loadUrdfString(tinyRobot(), "tiny.urdf");
  for (const std::string& xml : {vendor, crlf}) {
    const model::Model m = loadUrdfString(xml, "vendor.urdf");
    EXPECT_EQ(m.nj(), plain.nj());
    EXPECT_EQ(m.jointName, plain.jointName);
    EXPECT_NEAR(m.totalMass(), plain.totalMass(), 1e-12);
  }
  // Positions in messages still count lines in a CRLF file.
  std::string broken = crlf;
  broken.replace(broken.find("</joint>"), 8, "</jont>");
  EXPECT_TRUE(std::regex_search(errorFor(broken), std::regex(R"(^tiny\.urdf:7:\d+: XML error)")))
      << errorFor(broken);
}

TEST(UrdfLoader, NonPhysicalInertiaIsRejected) {
  const std::string triangle =
      R"(<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.5"/></inertial>)";
  EXPECT_NE(errorFor(tinyRobot(triangle)).find("<link name=\"child\">: <inertial>: principal "
                                               "moments"),
            std::string::npos)
      << errorFor(tinyRobot(triangle));
  const std::string indefinite =
      R"(<inertial><mass value="1"/><inertia ixx="0.1" ixy="0.3" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>)";
  EXPECT_NE(errorFor(tinyRobot(indefinite)).find("not positive semi-definite"), std::string::npos)
      << errorFor(tinyRobot(indefinite));
  const std::string negative =
      R"(<inertial><mass value="-1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>)";
  EXPECT_NE(errorFor(tinyRobot(negative)).find("mass must be positive"), std::string::npos)
      << errorFor(tinyRobot(negative));
}

TEST(UrdfLoader, BadLimitsAreRejected) {
  const std::string inverted =
      errorFor(tinyRobot(kInertial, "revolute",
                         R"(<limit lower="1" upper="-1" effort="10" velocity="5"/>)"));
  EXPECT_NE(inverted.find("<joint name=\"j1\">: <limit> lower (1.000000) must be below upper"),
            std::string::npos)
      << inverted;
  const std::string noEffort = errorFor(
      tinyRobot(kInertial, "revolute", R"(<limit lower="-1" upper="1" effort="0" velocity="5"/>)"));
  EXPECT_NE(noEffort.find("<limit> effort must be positive"), std::string::npos) << noEffort;
  const std::string badVelocity = errorFor(tinyRobot(
      kInertial, "revolute", R"(<limit lower="-1" upper="1" effort="10" velocity="-2"/>)"));
  EXPECT_NE(badVelocity.find("<limit> velocity must be positive"), std::string::npos)
      << badVelocity;
  // urdfdom itself refuses a revolute joint without <limit>; a continuous one reaches us.
  const std::string revoluteNoLimit = errorFor(tinyRobot(kInertial, "revolute", ""));
  EXPECT_NE(revoluteNoLimit.find("tiny.urdf: invalid URDF:"), std::string::npos)
      << revoluteNoLimit;
  const std::string continuousNoLimit = errorFor(tinyRobot(kInertial, "continuous", ""));
  EXPECT_NE(continuousNoLimit.find("<joint name=\"j1\">: no <limit>"), std::string::npos)
      << continuousNoLimit;
}

TEST(UrdfLoader, ContinuousJointHasUnboundedPosition) {
  const model::Model m = loadUrdfString(
      tinyRobot(kInertial, "continuous", R"(<limit effort="10" velocity="5"/>)"), "tiny.urdf");
  EXPECT_TRUE(std::isinf(m.upperPositionLimit[0]));
  EXPECT_TRUE(std::isinf(m.lowerPositionLimit[0]));
}

TEST(UrdfLoader, ZeroAxisIsRejected) {
  const std::string msg = errorFor(tinyRobot(kInertial, "revolute",
                                             R"(<limit lower="-1" upper="1" effort="10" velocity="5"/>)",
                                             R"(<axis xyz="0 0 0"/>)"));
  EXPECT_NE(msg.find("tiny.urdf"), std::string::npos) << msg;
  EXPECT_NE(msg.find("axis"), std::string::npos) << msg;
}

TEST(UrdfLoader, WorldRootWithFloatingJointIsSkipped) {
  std::string xml = tinyRobot();
  xml.replace(xml.find("</robot>"), 8,
              "  <link name=\"world\"/>\n"
              "  <joint name=\"float\" type=\"floating\"><parent link=\"world\"/>"
              "<child link=\"base\"/></joint>\n</robot>");
  const model::Model m = loadUrdfString(xml, "tiny.urdf");
  EXPECT_EQ(m.bodyName[0], "base");
  EXPECT_EQ(m.nj(), 1);
}

TEST(UrdfLoader, MasslessBaseIsRejected) {
  std::string xml = tinyRobot();
  xml.replace(xml.find("<link name=\"base\">" + kInertial + "</link>"),
              std::string("<link name=\"base\">" + kInertial + "</link>").size(),
              "<link name=\"base\"/>");
  const std::string msg = errorFor(xml);
  EXPECT_NE(msg.find("<link name=\"base\">: the floating base"), std::string::npos) << msg;
}

// A locked joint is a fixed one at its angle: the model loses the joint, not the mass, and
// every frame sits where the free model puts it with the joint at that angle.
TEST(UrdfLoader, ALockedJointIsFixedAtItsAngle) {
  model::UrdfOptions options;
  options.locked = {{"left_elbow", -0.7}, {"right_wrist_yaw", 0.3}};
  const model::Model locked = model::loadUrdfFile(humanoidUrdf(), options);
  const model::Model& free = humanoid();
  ASSERT_EQ(locked.nj(), free.nj() - 2);
  EXPECT_LT(locked.findJoint("left_elbow"), 0);
  EXPECT_LT(locked.findJoint("right_wrist_yaw"), 0);
  EXPECT_EQ(locked.frames[locked.frameId("left_forearm")].body,
            locked.frames[locked.frameId("left_upper_arm")].body);

  model::VecX<double> qf = model::neutralConfiguration(free);
  qf[7 + free.jointId("left_elbow")] = -0.7;
  qf[7 + free.jointId("right_wrist_yaw")] = 0.3;
  qf[7 + free.jointId("left_knee")] = 0.5;
  model::VecX<double> ql = model::neutralConfiguration(locked);
  ql[7 + locked.jointId("left_knee")] = 0.5;
  model::Data<double> df{free}, dl{locked};
  model::forwardKinematics(free, df, qf);
  model::forwardKinematics(locked, dl, ql);
  for (const char* f : {"left_hand", "right_hand", "left_toe", "head"}) {
    const auto a = model::framePlacement(free, df, free.frameId(f));
    const auto b = model::framePlacement(locked, dl, locked.frameId(f));
    EXPECT_TRUE(a.p.isApprox(b.p, 1e-12)) << f;
    EXPECT_TRUE(a.R.isApprox(b.R, 1e-12)) << f;
  }
  EXPECT_NEAR(model::centerOfMass(locked, dl, ql).z(), model::centerOfMass(free, df, qf).z(), 1e-12);
  EXPECT_NEAR(dl.mass, df.mass, 1e-12);
}

TEST(UrdfLoader, ALockedJointMustBeAMovableJointLockedWithinItsLimits) {
  model::UrdfOptions options;
  options.locked = {{"left_elbw", 0.0}};
  try {
    model::loadUrdfFile(humanoidUrdf(), options);
    FAIL();
  } catch (const model::LockedJointError& e) {
    EXPECT_EQ(e.joint, "left_elbw");
    EXPECT_NE(std::string(e.what()).find("has no joint 'left_elbw'"), std::string::npos) << e.what();
  }
  options.locked = {{"left_knee", -0.5}};
  try {
    model::loadUrdfFile(humanoidUrdf(), options);
    FAIL();
  } catch (const model::LockedJointError& e) {
    EXPECT_NE(std::string(e.what()).find("<joint name=\"left_knee\">: locked at -0.500000: outside "
                                         "the joint's limits [0.000000, 2.400000]"),
              std::string::npos)
        << e.what();
  }
  options.locked = {{"waist", 0.0}};
  EXPECT_THROW(model::loadUrdfFile(humanoidUrdf(), options), model::LockedJointError);
}

}  // namespace
}  // namespace ballast::test
