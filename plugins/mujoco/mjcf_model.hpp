// URDF (+ the backend's section, the controller's armature and the terrain) -> an MJCF model,
// as text, for MuJoCo to compile from memory. MuJoCo 2.2.2's own URDF import fixes the root link
// to the world and drops its mass, so the model is built here from urdfdom, as the simbody
// backend builds its Simbody system (plugins/simbody/urdf_multibody.hpp):
//
//   - every URDF link with <inertial> is a MuJoCo body with exactly that mass, centre of mass
//     and inertia (<inertial fullinertia>); the root has a <freejoint/>; revolute and continuous
//     joints are hinges, prismatic ones slides, at the child link's origin on the URDF axis, with
//     the URDF position limits (continuous: none) and the controller's armature (Config::joints;
//     MuJoCo's joint armature is exactly the rotor inertia on M's diagonal, as in the
//     controller's model); a fixed joint to a link with <inertial> makes a body without a joint
//     (welded: MuJoCo merges nothing away, the dynamics are those of the merged body);
//   - links without <inertial> or of zero mass (contact points, sensor frames) fixed to their
//     parent are frames on their nearest massive ancestor (LinkFrame); a locked joint
//     (Config::joints) is a fixed one at its position; a massless link moved by a joint (it
//     carries moving links: the controller's model locks any that moves nothing) is a body with
//     MuJoCo's least mass and inertia;
//   - foot contact as in the simbody backend: each contact point (Config::contact_frames) carries
//     two spheres of foot_sphere_radius side by side across the foot (bottoms on the sole, the
//     pair foot_width wide, else the width of the foot's collision box); the foot bodies have no
//     other collision geometry;
//   - with body_contact, every other body's URDF <collision> boxes, spheres and cylinders are
//     geoms too (MuJoCo collides the shapes themselves; meshes are skipped), reported as
//     Truth::non_foot_contact;
//   - the robot never collides with itself (contype 1, conaffinity 0; the terrain the reverse);
//   - terrain: the floor as a plane, the map's columns (plugins/common/terrain_columns.hpp, the
//     same columns the simbody backend simulates) as boxes, equal neighbouring columns merged into
//     rectangles (the lab stage is one box; columns at the floor's height are the floor). Boxes
//     keep the columns' vertical sides and sharp edges, which a height field's surface
//     (triangles between grid points) would turn into 2 cm ramps. The boxes are not geoms: in
//     MuJoCo's collision detection a height field geom, "terrain", stands for them and reaches
//     them through the columns' grid (terrain_collision.hpp: a step costs the columns near the
//     robot, not every box); its own surface is not used.
#pragma once

#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "mujoco_settings.hpp"
#include "simulated_robot.hpp"  // plugins/common
#include "terrain_columns.hpp"  // plugins/common

namespace ballast::mujoco {

/// A rigid transform: rotation (row-major 3×3) and translation.
struct Transform {
  std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> p{0, 0, 0};

  /// At `p`, turned by fixed-axis roll, pitch, yaw (URDF's rpy).
  static Transform placed(const std::array<double, 3>& p, const std::array<double, 3>& rpy);
  Transform operator*(const Transform& b) const;
  std::array<double, 3> apply(const std::array<double, 3>& v) const;  ///< R v + p
  std::array<double, 3> rotate(const std::array<double, 3>& v) const;  ///< R v
};

/// What the model is built from.
struct ModelInput {
  std::string urdfPath;
  using ContactPoint = plugin::SimulatedRobot::ContactPoint;
  std::vector<ContactPoint> contacts;
  std::map<std::string, double> locked;      ///< joint -> position it is welded at (Config::joints)
  MujocoSettings settings;
  std::map<std::string, double> armature;    ///< joint -> kg·m² (Config::joints)
  plugin::TerrainColumns columns;            ///< empty: no map
  double timestep = 0.001;                   ///< s per MuJoCo step
};

/// The model's text and what the world needs to find its parts by name.
struct BuiltModel {
  std::string xml;  ///< MJCF
  std::string robotName;
  std::string baseBody;                     ///< the root link (the floating base)
  std::vector<std::string> jointNames;      ///< movable joints in URDF file order
  std::map<std::string, double> effortLimit;  ///< movable joint -> URDF effort (0: none)
  /// Movable joint -> URDF position limits; ±infinity for continuous joints.
  std::map<std::string, std::pair<double, double>> positionLimits;
  /// Every URDF link: the MuJoCo body (a link name) it is on and its frame in that body.
  struct LinkFrame {
    std::string body;
    Transform inBody;
  };
  std::map<std::string, LinkFrame> links;
  /// Geom names of each contact point's spheres (Config::contact_frames order).
  std::vector<std::vector<std::string>> footGeoms;
  int bodyGeoms = 0;      ///< collision geoms on other bodies
  int terrainBoxes = 0;   ///< boxes made of the map's columns
  /// Per column (ix + nx·iy) of the map, the number of its box (terrainBoxes() order), −1: none.
  std::vector<int> terrainBoxOfColumn;
  int skippedShapes = 0;  ///< URDF <collision> meshes left out
};

/// Builds the model; throws std::runtime_error naming the URDF file and element, or the
/// settings key, that is wrong.
BuiltModel buildMjcf(const ModelInput& input);

/// The map's columns as boxes (equal neighbours merged): each {x0, y0, x1, y1, top}; columns at
/// or below the floor are left to the floor when there is one. `boxOfColumn`, if given: per
/// column (ix + nx·iy), the number of its box, −1 for none.
std::vector<std::array<double, 5>> terrainBoxes(const plugin::TerrainColumns& columns, bool floor,
                                                double floorHeight,
                                                std::vector<int>* boxOfColumn = nullptr);

}  // namespace ballast::mujoco
