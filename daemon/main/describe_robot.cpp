#include "main/describe_robot.hpp"

#include <fmt/format.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "model/algorithms.hpp"
#include "model/limbs.hpp"
#include "profile/schema.hpp"
#include "profile/settings.hpp"

namespace ballast::daemon {
namespace {

using model::Model;
using model::SE3;
using model::Vec3;

constexpr double kKneeBend = 0.8;  // rad: the shipped profiles' standing posture

std::string list(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return "[" + s + "]";
}

std::string vec(const Vec3<double>& v) {
  auto r = [](double x) { return std::abs(x) < 5e-4 ? 0.0 : x; };
  return fmt::format("[{:.3f}, {:.3f}, {:.3f}]", r(v.x()), r(v.y()), r(v.z()));
}

/// Toe and heel of a foot link, in its frame: the bottom face of its largest collision box (at
/// the zero posture, world x forward), its spheres, or a guess (found = false).
struct Sole {
  Vec3<double> toe, heel;
  bool found = false;
};

/// Front and back of the lowest face of a box (`size`, placed at oMb in the world), on its centre
/// line, in the frame of the link at oMl.
Sole bottomOfBox(const SE3<double>& oMb, const Vec3<double>& size, const SE3<double>& oMl) {
  Vec3<double> lo = Vec3<double>::Constant(std::numeric_limits<double>::infinity());
  Vec3<double> hi = -lo;
  for (int k = 0; k < 8; ++k) {
    const Vec3<double> corner((k & 1 ? 0.5 : -0.5) * size.x(), (k & 2 ? 0.5 : -0.5) * size.y(),
                              (k & 4 ? 0.5 : -0.5) * size.z());
    const Vec3<double> w = oMb.act(corner);
    lo = lo.cwiseMin(w);
    hi = hi.cwiseMax(w);
  }
  const double y = oMb.p.y();
  return Sole{oMl.actInv(Vec3<double>(hi.x(), y, lo.z())), oMl.actInv(Vec3<double>(lo.x(), y, lo.z())),
              true};
}

SE3<double> placement(const urdf::Pose& o) {
  const Eigen::Quaterniond q(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z);
  return SE3<double>{q.normalized().toRotationMatrix(), Vec3<double>(o.position.x, o.position.y, o.position.z)};
}

/// The uniform box a link's inertia would be (principal axes, sides from the moments:
/// a² = 6 (I_b + I_c − I_a) / m), placed in the world; false if the inertia is none or no box's.
bool inertiaBox(const urdf::Link& l, const SE3<double>& oMl, SE3<double>& oMb, Vec3<double>& size) {
  if (!l.inertial || !(l.inertial->mass > 0.0)) return false;
  const urdf::Inertial& in = *l.inertial;
  Eigen::Matrix3d I;
  I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
  const Vec3<double> m = eig.eigenvalues();
  for (int a = 0; a < 3; ++a) {
    const double side2 = 6.0 * (m.sum() - 2.0 * m[a]) / in.mass;
    if (!(side2 > 0.0)) return false;
    size[a] = std::sqrt(side2);
  }
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  oMb = oMl * placement(in.origin) * SE3<double>{axes, Vec3<double>::Zero()};
  return true;
}

Sole soleOf(const urdf::ModelInterface& urdf, const std::string& link, const SE3<double>& oMl) {
  Sole sole;
  const urdf::LinkConstSharedPtr l = urdf.getLink(link);
  double largest = 0.0;
  for (const auto& c : l ? l->collision_array : std::vector<urdf::CollisionSharedPtr>{}) {
    if (!c || !c->geometry || c->geometry->type != urdf::Geometry::BOX) continue;
    const auto& box = static_cast<const urdf::Box&>(*c->geometry);
    const double volume = box.dim.x * box.dim.y * box.dim.z;
    if (volume <= largest) continue;
    largest = volume;
    sole = bottomOfBox(oMl * placement(c->origin), Vec3<double>(box.dim.x, box.dim.y, box.dim.z), oMl);
  }
  if (sole.found) return sole;
  // No box: the foot's spheres (front and back ones, at their bottoms).
  Vec3<double> front = oMl.p, back = oMl.p;
  int spheres = 0;
  for (const auto& c : l ? l->collision_array : std::vector<urdf::CollisionSharedPtr>{}) {
    if (!c || !c->geometry || c->geometry->type != urdf::Geometry::SPHERE) continue;
    const double r = static_cast<const urdf::Sphere&>(*c->geometry).radius;
    const Vec3<double> centre =
        oMl.act(Vec3<double>(c->origin.position.x, c->origin.position.y, c->origin.position.z));
    const Vec3<double> bottom = centre - Vec3<double>(0, 0, r);
    if (spheres == 0 || bottom.x() > front.x()) front = bottom;
    if (spheres == 0 || bottom.x() < back.x()) back = bottom;
    ++spheres;
  }
  if (spheres >= 2 && front.x() - back.x() > 0.02)
    return Sole{oMl.actInv(front), oMl.actInv(back), true};
  // Else a guess: the bottom of the box the foot's inertia would be (a foot is mostly a plate
  // under its ankle; a point foot of millimetres says nothing of its sole, and points at the
  // ankle put the ankle links on the ground), or 8 cm either side of its origin or its sphere.
  SE3<double> oMb;
  Vec3<double> size;
  if (l && inertiaBox(*l, oMl, oMb, size)) {
    sole = bottomOfBox(oMb, size, oMl);
    sole.found = false;
    return sole;
  }
  front = back = Vec3<double>(front.x(), front.y(), std::min(front.z(), back.z()));
  front.x() += 0.08;
  back.x() -= 0.08;
  return Sole{oMl.actInv(front), oMl.actInv(back), false};
}

struct Leg {
  model::Limb limb;
  std::string foot;  ///< the leaf link
  Sole sole;
};

/// The standing posture of a leg: the knee (a middle pitch joint) bent by kKneeBend, the first
/// and last pitch joints back by half of it each so the sole stays level; {} if the leg has no
/// three pitch joints or the angles leave the limits.
std::map<std::string, double> standingPosture(const Model& m, const model::Data<double>& d,
                                              const model::Limb& limb) {
  std::vector<int> pitch;  // joint indices, root to leaf
  std::vector<double> along;  // each axis's y component in the world
  for (int j : limb.joints) {
    const Vec3<double> axis = d.oMi[j + 1].R * m.jointAxis[j + 1];
    if (m.jointType[j + 1] == model::JointType::Revolute && std::abs(axis.y()) > 0.9) {
      pitch.push_back(j);
      along.push_back(axis.y());
    }
  }
  if (pitch.size() < 3) return {};
  const std::size_t knee = pitch.size() / 2;
  for (const double bend : {kKneeBend, -kKneeBend}) {  // the knee's own direction: its limits
    const double angles[3] = {-bend / 2 / along.front(), bend / along[knee], -bend / 2 / along.back()};
    const int joints[3] = {pitch.front(), pitch[knee], pitch.back()};
    bool inside = true;
    for (int k = 0; k < 3; ++k)
      inside = inside && angles[k] >= m.lowerPositionLimit[joints[k]] &&
               angles[k] <= m.upperPositionLimit[joints[k]];
    if (!inside) continue;
    std::map<std::string, double> posture;
    for (int k = 0; k < 3; ++k) posture[m.jointName[joints[k] + 1]] = angles[k];
    return posture;
  }
  return {};
}

}  // namespace

std::string describeRobot(const std::string& urdfPath) {
  const Model m = model::loadUrdfFile(urdfPath);
  std::ifstream in(urdfPath);
  std::stringstream text;
  text << in.rdbuf();
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(text.str());

  model::Data<double> d(m);
  model::VecX<double> q = model::neutralConfiguration(m);
  model::forwardKinematics(m, d, q);

  // Limbs: legs are the two whose leaves are lowest, left the one at +y.
  std::vector<model::Limb> limbs = model::limbs(m);
  std::vector<std::size_t> byHeight(limbs.size());
  for (std::size_t i = 0; i < limbs.size(); ++i) byHeight[i] = i;
  auto leafZ = [&](std::size_t i) { return d.oMi[limbs[i].joints.back() + 1].p.z(); };
  std::sort(byHeight.begin(), byHeight.end(), [&](auto a, auto b) { return leafZ(a) < leafZ(b); });
  std::vector<Leg> legs;
  for (std::size_t k = 0; k < std::min<std::size_t>(2, byHeight.size()); ++k) {
    const model::Limb& limb = limbs[byHeight[k]];
    const int body = limb.joints.back() + 1;
    legs.push_back(Leg{limb, m.bodyName[body], soleOf(*urdf, m.bodyName[body], d.oMi[body])});
  }
  std::sort(legs.begin(), legs.end(), [&](const Leg& a, const Leg& b) {
    return d.oMi[a.limb.joints.back() + 1].p.y() > d.oMi[b.limb.joints.back() + 1].p.y();
  });
  std::vector<std::string> legJoints, armJoints, torsoJoints;
  std::vector<bool> grouped(static_cast<std::size_t>(m.nj()), false);
  for (const Leg& leg : legs)
    for (int j : leg.limb.joints) {
      legJoints.push_back(m.jointName[j + 1]);
      grouped[static_cast<std::size_t>(j)] = true;
    }
  for (std::size_t k = 2; k < byHeight.size(); ++k)
    for (int j : limbs[byHeight[k]].joints) {
      armJoints.push_back(m.jointName[j + 1]);
      grouped[static_cast<std::size_t>(j)] = true;
    }
  for (int j = 0; j < m.nj(); ++j)
    if (!grouped[static_cast<std::size_t>(j)]) torsoJoints.push_back(m.jointName[j + 1]);

  // Standing: the posture, then the base's height over the soles in it.
  std::map<std::string, double> posture;
  for (const Leg& leg : legs) posture.merge(standingPosture(m, d, leg.limb));
  for (const auto& [name, angle] : posture) q[Model::qIndexOfJoint(m.jointId(name))] = angle;
  model::forwardKinematics(m, d, q);
  double sole = std::numeric_limits<double>::infinity();
  for (const Leg& leg : legs) {
    const SE3<double>& oMf = d.oMi[leg.limb.joints.back() + 1];
    sole = std::min({sole, oMf.act(leg.sole.toe).z(), oMf.act(leg.sole.heel).z()});
  }
  const double height = legs.empty() ? 0.9 : d.oMi[0].p.z() - sole;
  int highest = 0;
  double top = -std::numeric_limits<double>::infinity();
  for (const model::Frame& f : m.frames) {
    const double z = (d.oMi[f.body] * f.placement).p.z();
    if (z > top) top = z, highest = static_cast<int>(&f - m.frames.data());
  }

  // The description, as comments.
  double limbMass = 0.0;
  for (const Leg& leg : legs)
    for (int j : leg.limb.joints) limbMass += m.inertia[j + 1].mass;
  for (std::size_t k = 2; k < byHeight.size(); ++k)
    for (int j : limbs[byHeight[k]].joints) limbMass += m.inertia[j + 1].mass;
  std::string o;
  o += fmt::format("# Robot {} ({}), described by ballastd --describe-robot.\n", m.name, urdfPath);
  o += fmt::format("# Mass {:.2f} kg; limbs {:.2f} kg ({:.1f} %); base {} ({:.2f} kg with the links "
                   "fixed to it).\n",
                   m.totalMass(), limbMass, 100.0 * limbMass / m.totalMass(), m.bodyName[0],
                   m.inertia[0].mass);
  o += fmt::format("# {} movable joints{}:\n", m.nj(),
                   m.nj() > 32 ? " (ballast controls at most 32: lock some in " +
                                     std::string(profile::table().keyOf<&profile::Settings::joints,
                                                                        &profile::JointSettings::locked>()) +
                                     ")"
                               : std::string());
  o += "#   joint                          axis (world, zero posture)   lower    upper   effort  velocity\n";
  for (int j = 0; j < m.nj(); ++j) {
    const Vec3<double> axis = d.oMi[j + 1].R * m.jointAxis[j + 1];
    o += fmt::format("#   {:<30} {:<28} {:>7.2f}  {:>7.2f}  {:>7.1f}  {:>8.1f}\n", m.jointName[j + 1],
                     vec(axis), m.lowerPositionLimit[j], m.upperPositionLimit[j],
                     m.effortLimit[j], m.velocityLimit[j]);
  }
  for (const model::LockedJoint& l : m.lockedJoints)
    o += fmt::format("# Held by the URDF: {} at {:.3f}: {}\n", l.name, l.position, l.reason);
  for (const Leg& leg : legs)
    o += fmt::format("# Leg to {} ({} joints); its sole: {}\n", leg.foot, leg.limb.joints.size(),
                     leg.sole.found ? "its collision geometry's bottom, front and back"
                                    : "no collision box or spheres to take it from: the contact "
                                      "points below are a guess (the bottom of the box its "
                                      "inertia would be), measure them");
  for (std::size_t k = 2; k < byHeight.size(); ++k)
    o += fmt::format("# Arm (or other limb) to {} ({} joints)\n",
                     m.bodyName[limbs[byHeight[k]].joints.back() + 1],
                     limbs[byHeight[k]].joints.size());
  if (posture.empty())
    o += "# No standing posture found (a leg without three pitch joints): set nominal_posture.\n";
  o += fmt::format("# Standing: the base {:.3f} m over the soles.\n", height);

  // The starter profile.
  o += "description: " + m.name + " in the Simbody simulation on a flat floor (starter profile)\n";
  o += "robot:\n  urdf: " + std::filesystem::absolute(urdfPath).lexically_normal().string() +
       "\n  contact_frames:\n";
  for (const Leg& leg : legs)
    for (const Vec3<double>* p : {&leg.sole.toe, &leg.sole.heel})
      o += "    - {link: " + leg.foot + ", offset: " + vec(*p) + "}\n";
  o += "  imu_frame: " + m.bodyName[0] + "\n  joint_groups:\n";
  if (!legJoints.empty()) o += "    legs: " + list(legJoints) + "\n";
  if (!armJoints.empty()) o += "    arms: " + list(armJoints) + "\n";
  if (!torsoJoints.empty()) o += "    torso: " + list(torsoJoints) + "\n";
  std::string postureYaml;
  for (const auto& [name, angle] : posture)
    postureYaml += fmt::format("{}{}: {:.3f}", postureYaml.empty() ? "" : ", ", name, angle);
  o += "  nominal_posture: {" + postureYaml + "}\n";
  // Gains per group as the shipped humanoid's (legs and torso stiff, arms soft).
  std::string kp, kd;
  for (const auto& [group, joints, p, dgain] :
       {std::tuple{"legs", &legJoints, 300, 8}, std::tuple{"arms", &armJoints, 80, 2},
        std::tuple{"torso", &torsoJoints, 300, 8}}) {
    if (joints->empty()) continue;
    kp += fmt::format("{}{}: {}", kp.empty() ? "" : ", ", group, p);
    kd += fmt::format("{}{}: {}", kd.empty() ? "" : ", ", group, dgain);
  }
  o += "control:\n  initial_mode: stand-up\n  joint_kp: {" + kp + "}\n  joint_kd: {" + kd + "}\n";
  o += fmt::format("safety:\n  min_pose_height: {:.3f}\n  max_pose_height: {:.3f}\n",
                   height - 0.19, height + 0.04);
  o += "backend:\n  name: simbody\n  simbody:\n    initial_posture: zero\n";
  o += "    initial_joints: {" + postureYaml + "}\n";
  o += "    lidar: {frame: {link: " + m.frames[static_cast<std::size_t>(highest)].name +
       ", offset: [0, 0, 0.1]}}\n";
  return o;
}

}  // namespace ballast::daemon
