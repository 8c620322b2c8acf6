// The MuJoCo model of the URDF: the robot the controller's model describes (mass, inertia,
// limits, armature), fixed joints and frames, the foot spheres, the terrain as boxes, and what
// is wrong with a bad URDF, by element.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "mjcf_model.hpp"
#include "mujoco_world.hpp"
#include "terrain_maps.hpp"
#include "test/integration/simbody/sim_test_support.hpp"

namespace ballast::mujoco {
namespace {

using simbody::test::humanoidUrdfPath;
using simbody::test::kContactFrames;

WorldOptions options(const std::string& yaml = "") {
  WorldOptions o;
  o.urdfPath = humanoidUrdfPath();
  for (const char* frame : kContactFrames) o.contacts.push_back({frame, frame, {0, 0, 0}});
  o.settings = parseMujocoSettings(yaml, "test.yaml:1");
  return o;
}

TEST(MujocoModel, TheRobotHasTheUrdfsMassJointsLimitsAndArmature) {
  WorldOptions o = options();
  o.armature = {{"left_knee", 0.015}, {"right_wrist_pitch", 0.01}};
  MujocoWorld world(o);
  const mjModel* m = world.model();
  EXPECT_NEAR(world.mass(), 62.0, 1e-9);  // urdf/humanoid.urdf: 62 kg
  ASSERT_EQ(world.numJoints(), 24);
  EXPECT_EQ(world.jointNames()[0], "left_hip_yaw");
  EXPECT_EQ(world.jointNames()[23], "right_wrist_pitch");
  EXPECT_EQ(m->nq, 7 + 24);  // a free base and the 24 hinges
  EXPECT_EQ(m->nv, 6 + 24);
  const int knee = mj_name2id(m, mjOBJ_JOINT, "left_knee");
  ASSERT_GE(knee, 0);
  EXPECT_EQ(m->jnt_type[knee], mjJNT_HINGE);
  EXPECT_TRUE(m->jnt_limited[knee]);
  EXPECT_DOUBLE_EQ(m->jnt_range[2 * knee], 0.0);
  EXPECT_DOUBLE_EQ(m->jnt_range[2 * knee + 1], 2.4);
  EXPECT_DOUBLE_EQ(m->dof_armature[m->jnt_dofadr[knee]], 0.015);
  EXPECT_DOUBLE_EQ(m->dof_armature[m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "right_wrist_pitch")]], 0.01);
  EXPECT_DOUBLE_EQ(m->dof_armature[m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "left_hip_yaw")]], 0.0);
  // A link's mass and inertia as the URDF gives them (the shin: 3 kg, 0.0377 0.0377 0.0032).
  const int shin = mj_name2id(m, mjOBJ_BODY, "left_shin");
  EXPECT_DOUBLE_EQ(m->body_mass[shin], 3.0);
  EXPECT_NEAR(m->body_inertia[3 * shin] + m->body_inertia[3 * shin + 1] + m->body_inertia[3 * shin + 2],
              0.0377 + 0.0377 + 0.0032, 1e-12);
  EXPECT_NEAR(m->body_ipos[3 * shin + 2], -0.16, 1e-12);
  // The waist and neck are fixed: torso and head are bodies without a joint of their own.
  const int torso = mj_name2id(m, mjOBJ_BODY, "torso");
  EXPECT_EQ(m->body_jntnum[torso], 0);
  EXPECT_EQ(m->body_parentid[torso], mj_name2id(m, mjOBJ_BODY, "pelvis"));
  EXPECT_EQ(m->body_weldid[torso], m->body_weldid[m->body_parentid[torso]]);
  // Links without <inertial> are frames on their bodies: the toe on the foot, 6 cm under it.
  const BuiltModel::LinkFrame& toe = world.built().links.at("left_toe");
  EXPECT_EQ(toe.body, "left_foot");
  EXPECT_NEAR(toe.inBody.p[0], 0.13, 1e-12);
  EXPECT_NEAR(toe.inBody.p[2], -0.06, 1e-12);
  EXPECT_EQ(world.built().links.at("imu").body, "pelvis");
  EXPECT_EQ(world.built().links.at("lidar").body, "head");
}

TEST(MujocoModel, EachContactPointHasTwoSpheresAcrossTheSoleAsInSimbody) {
  MujocoWorld world(options());
  const mjModel* m = world.model();
  const BuiltModel& b = world.built();
  ASSERT_EQ(b.footGeoms.size(), 4u);
  for (std::size_t c = 0; c < 4; ++c) {
    ASSERT_EQ(b.footGeoms[c].size(), 2u) << kContactFrames[c];
    const int g0 = mj_name2id(m, mjOBJ_GEOM, b.footGeoms[c][0].c_str());
    const int g1 = mj_name2id(m, mjOBJ_GEOM, b.footGeoms[c][1].c_str());
    EXPECT_EQ(m->geom_type[g0], mjGEOM_SPHERE);
    EXPECT_DOUBLE_EQ(m->geom_size[3 * g0], 0.01);
    // The foot box is 10 cm wide: sphere centres 8 cm apart, bottoms on the sole (z = -0.06).
    EXPECT_NEAR(m->geom_pos[3 * g1 + 1] - m->geom_pos[3 * g0 + 1], 0.08, 1e-12);
    EXPECT_NEAR(m->geom_pos[3 * g0 + 2], -0.05, 1e-12);
  }
  // The feet carry nothing else; every other body its collision box.
  const int foot = mj_name2id(m, mjOBJ_BODY, "left_foot");
  EXPECT_EQ(m->body_geomnum[foot], 4);
  EXPECT_EQ(b.bodyGeoms, 27 - 2);  // 27 links with a box, the feet aside
  EXPECT_EQ(b.skippedShapes, 0);
}

TEST(MujocoModel, TheStageIsOneBoxAndTheMapsFloorIsTheFloorPlane) {
  const std::string path = ::testing::TempDir() + "stage15.bt";
  const auto tree = maps::makeTerrainMap(maps::stage(0.15, 1.5, 2.0, 3.0), 0.02, {-2, 6, -2, 2});
  std::string error;
  ASSERT_TRUE(maps::writeTerrainMap(*tree, path, error)) << error;
  const plugin::TerrainColumns columns = plugin::loadTerrainColumns(path, 0.0, 0.5);
  const auto boxes = terrainBoxes(columns, true, 0.0);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_NEAR(boxes[0][0], 1.5, 1e-6);
  EXPECT_NEAR(boxes[0][2], 3.5, 1e-6);
  EXPECT_NEAR(boxes[0][4], 0.15, 0.01);
  EXPECT_NEAR(boxes[0][3] - boxes[0][1], 3.0, 0.021);
  // Without the floor the map's floor cells are boxes too (merged into a few rectangles).
  const auto all = terrainBoxes(columns, false, 0.0);
  EXPECT_GT(all.size(), 1u);
  EXPECT_LT(all.size(), 10u);
  double area = 0;
  for (const auto& b : all) area += (b[2] - b[0]) * (b[3] - b[1]);
  EXPECT_NEAR(area, 8.0 * 4.0, 0.1);
}

const char* const kLinkWithMass = R"(<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>)";

// The boxes are not geoms but reached through the columns' grid (terrain_collision.hpp): a
// contact sphere still meets the columns as boxes with vertical sides and sharp edges, where a
// height field's own surface (triangles between the grid's points) would be a ramp 2 cm wide.
TEST(MujocoModel, ASphereMeetsTheStagesTopSideAndEdgeAsTheColumnsHaveThem) {
  const std::string map = ::testing::TempDir() + "edge10.bt";
  const auto tree =
      maps::makeTerrainMap(maps::stage(0.10, 0.6, 1.4, 2.0), 0.02, {-1, 3, -1.5, 1.5});
  std::string error;
  ASSERT_TRUE(maps::writeTerrainMap(*tree, map, error)) << error;
  // One body carrying one contact sphere (no collision box: one sphere, on the point).
  const std::string urdf = ::testing::TempDir() + "ball.urdf";
  std::ofstream(urdf) << "<robot name='ball'><link name='base'>" << kLinkWithMass << "</link></robot>";
  WorldOptions o = options("imu: {frame: base}\nlidar: {enabled: false}\n");
  o.urdfPath = urdf;
  o.contacts = {{"foot", "base", {0, 0, 0}}};
  o.terrainMap = map;
  MujocoWorld world(o);
  const double r = 0.01, edge = 0.6, top = world.terrainHeight(edge + 0.01, 0.0);
  ASSERT_NEAR(top, 0.10, 0.011);
  ASSERT_EQ(world.terrainHeight(edge - 0.01, 0.0), 0.0);
  // The sphere's centre at (x, 0, z): its one contact's distance and normal (terrain to sphere).
  struct Touch {
    int count = 0;
    double dist = 0;
    std::array<double, 3> normal{};
  };
  auto touch = [&](double x, double z) {
    world.modifyState([&](const mjModel* m, mjData* d) {
      double* q = d->qpos + m->jnt_qposadr[0];  // the free joint: position, then quaternion
      q[0] = x, q[1] = 0.0, q[2] = z - r, q[3] = 1, q[4] = q[5] = q[6] = 0;
    });
    Touch t;
    t.count = world.data()->ncon;
    if (t.count == 0) return t;
    const mjContact& c = world.data()->contact[0];
    t.dist = c.dist;
    // The frame's normal points from geom1 to geom2.
    const double sign = world.model()->geom_bodyid[c.geom1] == 0 ? 1.0 : -1.0;
    t.normal = {sign * c.frame[0], sign * c.frame[1], sign * c.frame[2]};
    return t;
  };
  // On the top 2 mm inside the edge: the top face.
  Touch t = touch(edge + 0.002, top + r - 0.001);
  ASSERT_EQ(t.count, 1);
  EXPECT_NEAR(t.dist, -0.001, 1e-9);
  EXPECT_NEAR(t.normal[2], 1.0, 1e-9);
  // Beside the stage, 5 cm below its top: the vertical side.
  t = touch(edge - r + 0.001, top - 0.05);
  ASSERT_EQ(t.count, 1);
  EXPECT_NEAR(t.dist, -0.001, 1e-9);
  EXPECT_NEAR(t.normal[0], -1.0, 1e-9);
  // Over the edge: the corner, along the line from it to the centre.
  t = touch(edge - 0.005, top + 0.005);
  ASSERT_EQ(t.count, 1);
  EXPECT_NEAR(t.dist, std::hypot(0.005, 0.005) - r, 1e-9);
  EXPECT_NEAR(t.normal[0], -std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(t.normal[2], std::sqrt(0.5), 1e-9);
  // Over a seam between the stage's columns, away from the edge: the stage is one box, one contact.
  t = touch(1.0, top + r - 0.001);
  EXPECT_EQ(t.count, 1);
  EXPECT_NEAR(t.dist, -0.001, 1e-9);
  // Clear of the stage and above the floor: nothing.
  EXPECT_EQ(touch(edge - r - 0.001, top - 0.05).count, 0);
}

std::string worldError(const std::string& urdf, const std::string& yaml = "") {
  const std::string path = ::testing::TempDir() + "bad.urdf";
  std::ofstream(path) << urdf;
  WorldOptions o = options(yaml);
  o.urdfPath = path;
  o.contacts = {{"foot", "foot", {0, 0, 0}}};
  try {
    MujocoWorld world(o);
  } catch (const std::exception& e) {
    std::string message = e.what();
    const auto at = message.find(path);
    if (at != std::string::npos) message.replace(at, path.size(), "bad.urdf");
    return message;
  }
  return "";
}

TEST(MujocoModel, BadUrdfsNameTheElement) {
  const std::string base = std::string("<robot name='r'><link name='base'>") + kLinkWithMass + "</link>";
  EXPECT_EQ(worldError("<robot name='r'><link name='base'/><link name='foot'/><joint name='f' type='fixed'>"
                    "<parent link='base'/><child link='foot'/></joint></robot>"),
            "bad.urdf: the root link 'base' has no <inertial>: the floating base needs a mass");
  EXPECT_EQ(worldError(base + "<link name='leg'>" + kLinkWithMass + "</link><joint name='slide' type='planar'>"
                           "<parent link='base'/><child link='leg'/></joint><link name='foot'/><joint name='f' type='fixed'>"
                           "<parent link='leg'/><child link='foot'/></joint></robot>"),
            "bad.urdf: joint 'slide': only revolute, continuous, prismatic and fixed joints are "
            "simulated (the root's floating joint aside)");
  EXPECT_EQ(worldError(base + "<link name='toe'/><joint name='t' type='fixed'><parent link='base'/>"
                           "<child link='toe'/></joint></robot>"),
            "bad.urdf: no link 'foot' (contact frame 0)");
}

TEST(MujocoModel, MasslessLinksOnJointsAreBodiesOfLeastMassAndLockedJointsAreWelded) {
  // Without <inertial> and of zero mass: MuJoCo refuses a moving body without mass, so it gets
  // the least (the controller's model locks such a joint when nothing with mass is below it,
  // and the daemon has the simulation weld it: Config::joints).
  const std::string base = std::string("<robot name='r'><link name='base'>") + kLinkWithMass + "</link>";
  const std::string tail =
      "<joint name='hip' type='revolute'><parent link='base'/><child link='leg'/><axis xyz='0 1 0'/>"
      "<limit lower='-1' upper='1' effort='10' velocity='1'/></joint><link name='foot'/>"
      "<joint name='f' type='fixed'><parent link='leg'/><child link='foot'/><origin xyz='0 0 -0.3'/></joint></robot>";
  const std::string path = ::testing::TempDir() + "massless.urdf";
  for (const std::string& leg :
       {std::string("<link name='leg'/>"),
        std::string("<link name='leg'><inertial><mass value='0'/><inertia ixx='0' ixy='0' ixz='0' "
                    "iyy='0' iyz='0' izz='0'/></inertial></link>")}) {
    std::ofstream(path) << base + leg + tail;
    WorldOptions o = options("imu: {frame: base}\nlidar: {enabled: false}\n");
    o.urdfPath = path;
    o.contacts = {{"foot", "foot", {0, 0, 0}}};
    {
      MujocoWorld world(o);
      EXPECT_EQ(world.numJoints(), 1);
      EXPECT_NEAR(world.mass(), 1.0, 1e-5);
    }
    o.locked = {{"hip", 0.5}};
    MujocoWorld welded(o);
    EXPECT_EQ(welded.numJoints(), 0);
    EXPECT_NEAR(welded.mass(), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace ballast::mujoco
