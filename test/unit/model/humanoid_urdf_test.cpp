// The robot itself (urdf/humanoid.urdf), read with urdfdom directly: as heavy-limbed as the
// paper's robot, physically valid, with the frames and limits the controller relies on.
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "model/limbs.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class HumanoidUrdf : public ::testing::Test {
 protected:
  void SetUp() override {
    text_ = readFile(humanoidUrdf());
    urdf_ = urdf::parseURDF(text_);
    ASSERT_TRUE(urdf_);
  }
  /// True if the link hangs below a hip or shoulder joint (part of a limb).
  bool inLimb(urdf::LinkConstSharedPtr link) const {
    for (; link->getParent(); link = link->getParent()) {
      const std::string& j = link->parent_joint->name;
      if (j.find("hip_yaw") != std::string::npos || j.find("shoulder_pitch") != std::string::npos)
        return true;
    }
    return false;
  }
  std::string text_;
  urdf::ModelInterfaceSharedPtr urdf_;
};

TEST_F(HumanoidUrdf, MassSplitIsHeavyLimbed) {
  double total = 0, limbs = 0;
  for (const auto& [name, link] : urdf_->links_) {
    if (!link->inertial) continue;
    total += link->inertial->mass;
    if (inLimb(link)) limbs += link->inertial->mass;
  }
  EXPECT_GE(total, 55.0);
  EXPECT_LE(total, 70.0);
  EXPECT_GE(limbs / total, 0.60);
  EXPECT_LE(limbs / total, 0.68);
  EXPECT_NEAR(humanoid().totalMass(), total, 1e-9);  // the loader merges, loses nothing
}

TEST_F(HumanoidUrdf, EveryInertiaIsPhysicallyValid) {
  int massive = 0;
  for (const auto& [name, link] : urdf_->links_) {
    if (!link->inertial) continue;
    ++massive;
    const auto& in = *link->inertial;
    Eigen::Matrix3d I;
    I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    const Eigen::Vector3d d = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
    EXPECT_GT(in.mass, 0.0) << name;
    EXPECT_GT(d[0], 0.0) << name << ": not positive definite";
    EXPECT_GE(d[0] + d[1], d[2]) << name << ": triangle inequality";
    // A plausible density: radius of gyration under 0.3 m for every axis.
    EXPECT_LT(std::sqrt(d[2] / in.mass), 0.3) << name;
  }
  EXPECT_EQ(massive, 27);
}

TEST_F(HumanoidUrdf, JointsAndLimits) {
  int revolute = 0;
  for (const auto& [name, joint] : urdf_->joints_) {
    if (joint->type != urdf::Joint::REVOLUTE) continue;
    ++revolute;
    ASSERT_TRUE(joint->limits) << name;
    EXPECT_LT(joint->limits->lower, joint->limits->upper) << name;
    EXPECT_GT(joint->limits->velocity, 5.0) << name;
    EXPECT_LE(joint->limits->velocity, 20.0) << name;
    EXPECT_GT(joint->limits->effort, 10.0) << name;
    if (name.find("knee") != std::string::npos || name.find("hip_pitch") != std::string::npos) {
      EXPECT_GE(joint->limits->effort, 200.0) << name;
    }
  }
  EXPECT_EQ(revolute, 24);
  for (const char* side : {"left_", "right_"})
    for (const char* j : {"hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle_pitch", "ankle_roll",
                          "shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_yaw",
                          "wrist_pitch"})
      EXPECT_TRUE(urdf_->getJoint(std::string(side) + j)) << side << j;
}

TEST_F(HumanoidUrdf, FourLimbsOfSixJointsFromTheRootOut) {
  const model::Model& m = humanoid();
  const auto limbs = model::limbs(m);
  ASSERT_EQ(limbs.size(), 4u);
  std::vector<std::string> names, firsts, lasts;
  for (const auto& limb : limbs) {
    EXPECT_EQ(limb.joints.size(), 6u) << limb.name;
    names.push_back(limb.name);
    firsts.push_back(m.jointName[limb.joints.front() + 1]);
    lasts.push_back(m.jointName[limb.joints.back() + 1]);
  }
  EXPECT_EQ(names[0], "left_foot");
  EXPECT_EQ(names[1], "right_foot");
  EXPECT_EQ(firsts, (std::vector<std::string>{"left_hip_yaw", "right_hip_yaw",
                                              "left_shoulder_pitch", "right_shoulder_pitch"}));
  EXPECT_EQ(lasts, (std::vector<std::string>{"left_ankle_roll", "right_ankle_roll",
                                             "left_wrist_pitch", "right_wrist_pitch"}));
}

TEST_F(HumanoidUrdf, ContactPointsLieOnTheSoleOfABoxFoot) {
  for (const char* side : {"left", "right"}) {
    const auto foot = urdf_->getLink(std::string(side) + "_foot");
    ASSERT_TRUE(foot && foot->collision && foot->collision->geometry);
    ASSERT_EQ(foot->collision->geometry->type, urdf::Geometry::BOX);
    const auto& box = static_cast<const urdf::Box&>(*foot->collision->geometry);
    const auto& c = foot->collision->origin.position;
    const double soleZ = c.z - box.dim.z / 2;
    for (const char* point : {"_toe", "_heel"}) {
      const auto link = urdf_->getLink(std::string(side) + point);
      ASSERT_TRUE(link) << side << point;
      const auto& p = link->parent_joint->parent_to_joint_origin_transform.position;
      EXPECT_EQ(link->getParent()->name, foot->name);
      EXPECT_NEAR(p.z, soleZ, 1e-9) << side << point;
      EXPECT_LE(std::abs(p.x - c.x), box.dim.x / 2) << side << point;
    }
  }
  EXPECT_TRUE(urdf_->getLink("imu"));
}

TEST_F(HumanoidUrdf, CommentTableMatchesTheInertials) {
  const std::regex row(R"(^\s{4}(\w+)\s+(\d+\.\d\d)\s+(trunk|leg|arm)$)");
  std::istringstream lines(text_);
  int rows = 0;
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, row)) continue;
    ++rows;
    const auto link = urdf_->getLink(m[1]);
    ASSERT_TRUE(link && link->inertial) << m[1];
    EXPECT_NEAR(link->inertial->mass, std::stod(m[2]), 0.005) << m[1];
  }
  EXPECT_EQ(rows, 27);
}

}  // namespace
}  // namespace ballast::test
