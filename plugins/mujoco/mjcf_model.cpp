#include "mjcf_model.hpp"

#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "terrain_collision.hpp"
#include "urdf_joints.hpp"  // plugins/common

namespace ballast::mujoco {

Transform Transform::operator*(const Transform& b) const {
  Transform c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c.R[3 * i + j] = R[3 * i] * b.R[j] + R[3 * i + 1] * b.R[3 + j] + R[3 * i + 2] * b.R[6 + j];
  c.p = apply(b.p);
  return c;
}

std::array<double, 3> Transform::rotate(const std::array<double, 3>& v) const {
  return {R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
          R[6] * v[0] + R[7] * v[1] + R[8] * v[2]};
}

std::array<double, 3> Transform::apply(const std::array<double, 3>& v) const {
  std::array<double, 3> r = rotate(v);
  for (int i = 0; i < 3; ++i) r[i] += p[i];
  return r;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Transform fromPose(const urdf::Pose& pose) {
  double x = pose.rotation.x, y = pose.rotation.y, z = pose.rotation.z, w = pose.rotation.w;
  const double n = std::sqrt(x * x + y * y + z * z + w * w);
  x /= n, y /= n, z /= n, w /= n;
  Transform t;
  t.R = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
         2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
         2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
  t.p = {pose.position.x, pose.position.y, pose.position.z};
  return t;
}

/// Quaternion (w, x, y, z) of a rotation matrix (row-major).
std::array<double, 4> quaternion(const std::array<double, 9>& R) {
  const double trace = R[0] + R[4] + R[8];
  std::array<double, 4> q;
  if (trace > 0) {
    const double s = 0.5 / std::sqrt(trace + 1.0);
    q = {0.25 / s, (R[7] - R[5]) * s, (R[2] - R[6]) * s, (R[3] - R[1]) * s};
  } else if (R[0] > R[4] && R[0] > R[8]) {
    const double s = 2.0 * std::sqrt(1.0 + R[0] - R[4] - R[8]);
    q = {(R[7] - R[5]) / s, 0.25 * s, (R[1] + R[3]) / s, (R[2] + R[6]) / s};
  } else if (R[4] > R[8]) {
    const double s = 2.0 * std::sqrt(1.0 + R[4] - R[0] - R[8]);
    q = {(R[2] - R[6]) / s, (R[1] + R[3]) / s, 0.25 * s, (R[5] + R[7]) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + R[8] - R[0] - R[4]);
    q = {(R[3] - R[1]) / s, (R[2] + R[6]) / s, (R[5] + R[7]) / s, 0.25 * s};
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q) c /= n;
  return q;
}

}  // namespace

Transform Transform::placed(const std::array<double, 3>& p, const std::array<double, 3>& rpy) {
  urdf::Pose pose;
  pose.position = urdf::Vector3(p[0], p[1], p[2]);
  pose.rotation.setFromRPY(rpy[0], rpy[1], rpy[2]);
  return fromPose(pose);
}

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

template <std::size_t N>
std::string nums(const std::array<double, N>& v) {
  std::string s;
  for (std::size_t i = 0; i < N; ++i) s += (i ? " " : "") + num(v[i]);
  return s;
}

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string placement(const Transform& t) {
  return "pos=\"" + nums(t.p) + "\" quat=\"" + nums(quaternion(t.R)) + "\"";
}

struct Shape {
  std::string link;
  Transform inBody;
  int type = urdf::Geometry::BOX;
  std::array<double, 3> size{0, 0, 0};  ///< box half extents; sphere radius; cylinder radius, half length
};

struct Node {
  std::string link;
  int parent = -1;
  Transform inParent;                     ///< this body's frame in its parent body's frame
  urdf::JointConstSharedPtr joint;        ///< the joint that moves it; null: root or welded
  urdf::InertialSharedPtr inertial;
  std::vector<Shape> shapes;
  std::vector<int> children;
  std::vector<int> contacts;              ///< contact points (indices) on this body
};

/// Half the extent of a shape along unit vector u (both in the body frame).
double halfExtentAlong(const Shape& shape, const std::array<double, 3>& u) {
  if (shape.type == urdf::Geometry::SPHERE) return shape.size[0];
  std::array<double, 3> half = shape.size;
  if (shape.type == urdf::Geometry::CYLINDER) half = {shape.size[0], shape.size[0], shape.size[1]};
  double e = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double axis = shape.inBody.R[k] * u[0] + shape.inBody.R[3 + k] * u[1] +
                        shape.inBody.R[6 + k] * u[2];  // column k of R . u
    e += std::abs(axis) * half[k];
  }
  return e;
}

/// What MuJoCo gets for a massless body that moves (it refuses none): small beside any link.
constexpr double kLeastMass = 1e-6;     // kg
constexpr double kLeastInertia = 1e-9;  // kg m²

class Builder {
 public:
  Builder(const urdf::ModelInterface& urdf, const ModelInput& input, std::map<std::string, int> order,
          BuiltModel& out)
      : urdf_(urdf), in_(input), s_(input.settings), order_(std::move(order)), out_(out) {}

  void build() {
    urdf::LinkConstSharedPtr root = urdf_.getRoot();
    if (!root->inertial && root->child_joints.size() == 1 &&
        root->child_joints[0]->type == urdf::Joint::FLOATING)
      root = urdf_.getLink(root->child_joints[0]->child_link_name);
    if (!root->inertial)
      throw std::runtime_error("the root link '" + root->name + "' has no <inertial>: the "
                               "floating base needs a mass");
    out_.robotName = urdf_.getName();
    out_.baseBody = root->name;
    Node base;
    base.link = root->name;
    base.inertial = root->inertial;
    nodes_.push_back(base);
    walk(*root, 0, Transform());
    std::stable_sort(out_.jointNames.begin(), out_.jointNames.end(),
                     [&](const auto& a, const auto& b) { return order_.at(a) < order_.at(b); });
    placeContacts();
    out_.xml = document();
  }

 private:
  void walk(const urdf::Link& link, int node, const Transform& X) {
    out_.links[link.name] = BuiltModel::LinkFrame{nodes_[static_cast<std::size_t>(node)].link, X};
    parentLink_[link.name] = link.getParent() ? link.getParent()->name : "";
    addShapes(link, node, X);
    std::vector<urdf::JointSharedPtr> children = link.child_joints;
    std::stable_sort(children.begin(), children.end(), [&](const auto& a, const auto& b) {
      return order_.at(a->name) < order_.at(b->name);
    });
    for (const auto& joint : children) {
      const urdf::LinkConstSharedPtr child = urdf_.getLink(joint->child_link_name);
      Transform X_PJ = X * fromPose(joint->parent_to_joint_origin_transform);
      const auto lock = in_.locked.find(joint->name);
      if (lock != in_.locked.end()) X_PJ = X_PJ * lockedMotion(*joint, lock->second);
      const bool locked = lock != in_.locked.end();
      const bool massless = !child->inertial || !(child->inertial->mass > 0.0);
      if ((joint->type == urdf::Joint::FIXED || locked) && massless) {
        walk(*child, node, X_PJ);
        continue;
      }
      const bool movable = !locked && (joint->type == urdf::Joint::REVOLUTE ||
                                       joint->type == urdf::Joint::CONTINUOUS ||
                                       joint->type == urdf::Joint::PRISMATIC);
      if (!movable && !locked && joint->type != urdf::Joint::FIXED)
        throw std::runtime_error("joint '" + joint->name +
                                 "': only revolute, continuous, prismatic and fixed joints are "
                                 "simulated (the root's floating joint aside)");
      Node n;
      n.link = child->name;
      n.parent = node;
      n.inParent = X_PJ;
      n.inertial = child->inertial;
      if (movable) {
        n.joint = joint;
        out_.jointNames.push_back(joint->name);
        out_.effortLimit[joint->name] = joint->limits ? joint->limits->effort : 0.0;
        const bool bounded = joint->type != urdf::Joint::CONTINUOUS && joint->limits &&
                             joint->limits->lower < joint->limits->upper;
        out_.positionLimits[joint->name] =
            bounded ? std::make_pair(joint->limits->lower, joint->limits->upper)
                    : std::make_pair(-kInf, kInf);
      }
      nodes_.push_back(n);
      const int index = static_cast<int>(nodes_.size()) - 1;
      nodes_[static_cast<std::size_t>(node)].children.push_back(index);
      walk(*child, index, Transform());
    }
  }

  void addShapes(const urdf::Link& link, int node, const Transform& X) {
    std::vector<urdf::CollisionSharedPtr> elements = link.collision_array;
    if (elements.empty() && link.collision) elements.push_back(link.collision);
    for (const auto& c : elements) {
      if (!c || !c->geometry) continue;
      Shape shape;
      shape.link = link.name;
      shape.inBody = X * fromPose(c->origin);
      shape.type = c->geometry->type;
      switch (c->geometry->type) {
        case urdf::Geometry::BOX: {
          const auto& box = static_cast<const urdf::Box&>(*c->geometry);
          shape.size = {box.dim.x / 2, box.dim.y / 2, box.dim.z / 2};
          break;
        }
        case urdf::Geometry::SPHERE:
          shape.size[0] = static_cast<const urdf::Sphere&>(*c->geometry).radius;
          break;
        case urdf::Geometry::CYLINDER: {
          const auto& cyl = static_cast<const urdf::Cylinder&>(*c->geometry);
          shape.size = {cyl.radius, cyl.length / 2, 0};
          break;
        }
        default:
          ++out_.skippedShapes;
          continue;
      }
      nodes_[static_cast<std::size_t>(node)].shapes.push_back(shape);
    }
  }

  /// The child's frame in the joint frame of a joint held at `position`.
  static Transform lockedMotion(const urdf::Joint& joint, double position) {
    const double n = std::sqrt(joint.axis.x * joint.axis.x + joint.axis.y * joint.axis.y +
                               joint.axis.z * joint.axis.z);
    const std::array<double, 3> u{joint.axis.x / n, joint.axis.y / n, joint.axis.z / n};
    Transform t;
    if (joint.type == urdf::Joint::PRISMATIC) {
      for (int k = 0; k < 3; ++k) t.p[static_cast<std::size_t>(k)] = position * u[static_cast<std::size_t>(k)];
      return t;
    }
    const double c = std::cos(position), s = std::sin(position), v = 1.0 - c;  // Rodrigues
    t.R = {c + u[0] * u[0] * v,        u[0] * u[1] * v - u[2] * s, u[0] * u[2] * v + u[1] * s,
           u[1] * u[0] * v + u[2] * s, c + u[1] * u[1] * v,        u[1] * u[2] * v - u[0] * s,
           u[2] * u[0] * v - u[1] * s, u[2] * u[1] * v + u[0] * s, c + u[2] * u[2] * v};
    return t;
  }

  int nodeOf(const std::string& link) const {
    const std::string& body = out_.links.at(link).body;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (nodes_[i].link == body) return static_cast<int>(i);
    return -1;
  }

  void placeContacts() {
    out_.footGeoms.assign(in_.contacts.size(), {});
    for (std::size_t i = 0; i < in_.contacts.size(); ++i) {
      const ModelInput::ContactPoint& c = in_.contacts[i];
      if (!out_.links.count(c.link))
        throw std::runtime_error("no link '" + c.link + "' (contact frame " + std::to_string(i) + ")");
      nodes_[static_cast<std::size_t>(nodeOf(c.link))].contacts.push_back(static_cast<int>(i));
    }
  }

  /// The spheres of contact point i on its body: (centre in the body frame).
  std::vector<std::array<double, 3>> contactSpheres(int i, const Node& node) const {
    const ModelInput::ContactPoint& c = in_.contacts[static_cast<std::size_t>(i)];
    Transform frame = out_.links.at(c.link).inBody;
    frame.p = frame.apply(c.position);
    const double r = s_.foot_sphere_radius;
    const std::array<double, 3> across = frame.rotate({0, 1, 0}), up = frame.rotate({0, 0, 1});
    double width = s_.foot_width;
    if (width == 0.0) {
      // The sole's collision box: the point's own link's, or (a frame link on the foot) its
      // parent's.
      const std::string& parent = parentLink_.at(c.link);
      for (const Shape& shape : node.shapes)
        if (shape.link == c.link || shape.link == parent)
          width = std::max(width, 2.0 * halfExtentAlong(shape, across));
    }
    std::array<double, 3> centre;
    for (int k = 0; k < 3; ++k) centre[k] = frame.p[k] + r * up[k];
    if (!(width > 2.0 * r)) return {centre};
    const double offset = width / 2.0 - r;
    std::array<double, 3> a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = centre[k] - offset * across[k];
      b[k] = centre[k] + offset * across[k];
    }
    return {a, b};
  }

  std::string contactAttributes(const std::string& group, const std::string& affinity) const {
    const std::string friction = num(s_.friction);
    return " group=\"" + group + "\" " + affinity + " condim=\"3\" friction=\"" + friction +
           " 0 0\" solref=\"" + num(s_.contact_timeconst) + " " + num(s_.contact_dampratio) +
           "\" solimp=\"" + nums(s_.contact_impedance) + "\"";
  }

  void emitBody(int index, std::ostringstream& x, const std::string& indent) {
    const Node& n = nodes_[static_cast<std::size_t>(index)];
    x << indent << "<body name=\"" << escape(n.link) << "\" " << placement(n.inParent) << ">\n";
    const std::string in = indent + "  ";
    if (n.parent < 0) x << in << "<freejoint name=\"floating_base\"/>\n";
    if (n.joint) emitJoint(*n.joint, x, in);
    if (!n.inertial || !(n.inertial->mass > 0.0)) {
      // Massless, carrying moving links: MuJoCo wants mass and inertia on every moving body.
      x << in << "<inertial pos=\"0 0 0\" mass=\"" << num(kLeastMass) << "\" diaginertia=\""
        << num(kLeastInertia) << " " << num(kLeastInertia) << " " << num(kLeastInertia)
        << "\"/>\n";
    } else {
      emitInertial(*n.inertial, x, in);
    }
    const std::string robot = contactAttributes("1", "contype=\"1\" conaffinity=\"0\"");
    if (!n.contacts.empty()) {
      for (int c : n.contacts) {
        const std::vector<std::array<double, 3>> spheres = contactSpheres(c, n);
        for (std::size_t k = 0; k < spheres.size(); ++k) {
          const std::string name = in_.contacts[static_cast<std::size_t>(c)].name + "_sphere" + std::to_string(k);
          out_.footGeoms[static_cast<std::size_t>(c)].push_back(name);
          x << in << "<geom name=\"" << escape(name) << "\" type=\"sphere\" size=\""
            << num(s_.foot_sphere_radius) << "\" pos=\"" << nums(spheres[k]) << "\"" << robot
            << "/>\n";
        }
      }
    } else if (s_.body_contact) {
      int k = 0;
      for (const Shape& shape : n.shapes) {
        const std::string type = shape.type == urdf::Geometry::BOX      ? "box"
                                 : shape.type == urdf::Geometry::SPHERE ? "sphere"
                                                                        : "cylinder";
        const std::string size = shape.type == urdf::Geometry::BOX ? nums(shape.size)
                                 : shape.type == urdf::Geometry::SPHERE
                                     ? num(shape.size[0])
                                     : num(shape.size[0]) + " " + num(shape.size[1]);
        x << in << "<geom name=\"" << escape(shape.link) << "_collision" << k++ << "\" type=\""
          << type << "\" size=\"" << size << "\" " << placement(shape.inBody) << robot << "/>\n";
        ++out_.bodyGeoms;
      }
    }
    for (int child : n.children) emitBody(child, x, in);
    x << indent << "</body>\n";
  }

  /// The URDF inertia is about the centre of mass in the <inertial> frame; MJCF's fullinertia
  /// takes no orientation with it: I = R I' Rᵀ in the body frame. A point mass (zero inertia,
  /// which the controller's model takes) gets MuJoCo's least inertia.
  void emitInertial(const urdf::Inertial& m, std::ostringstream& x, const std::string& in) {
    const Transform X = fromPose(m.origin);
    const double I[9] = {m.ixx, m.ixy, m.ixz, m.ixy, m.iyy, m.iyz, m.ixz, m.iyz, m.izz};
    double RI[9], J[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        RI[3 * i + j] = 0;
        for (int k = 0; k < 3; ++k) RI[3 * i + j] += X.R[static_cast<std::size_t>(3 * i + k)] * I[3 * k + j];
      }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        J[3 * i + j] = 0;
        for (int k = 0; k < 3; ++k) J[3 * i + j] += RI[3 * i + k] * X.R[static_cast<std::size_t>(3 * j + k)];
      }
    for (const int d : {0, 4, 8}) J[d] = std::max(J[d], kLeastInertia);
    x << in << "<inertial pos=\"" << nums(X.p) << "\" mass=\"" << num(m.mass)
      << "\" fullinertia=\"" << num(J[0]) << " " << num(J[4]) << " " << num(J[8]) << " "
      << num(J[1]) << " " << num(J[2]) << " " << num(J[5]) << "\"/>\n";
  }

  void emitJoint(const urdf::Joint& joint, std::ostringstream& x, const std::string& in) {
    const bool prismatic = joint.type == urdf::Joint::PRISMATIC;
    const std::array<double, 3> axis{joint.axis.x, joint.axis.y, joint.axis.z};
    if (!(std::abs(axis[0]) + std::abs(axis[1]) + std::abs(axis[2]) > 0))
      throw std::runtime_error("joint '" + joint.name + "': <axis> is zero");
    const auto [lower, upper] = out_.positionLimits.at(joint.name);
    const auto a = in_.armature.find(joint.name);
    x << in << "<joint name=\"" << escape(joint.name) << "\" type=\""
      << (prismatic ? "slide" : "hinge") << "\" axis=\"" << nums(axis) << "\"";
    if (std::isfinite(lower) && s_.joint_limits)
      x << " limited=\"true\" range=\"" << num(lower) << " " << num(upper) << "\" solreflimit=\""
        << num(s_.joint_limit_timeconst) << " 1\"";
    else
      x << " limited=\"false\"";
    x << " armature=\"" << num(a != in_.armature.end() ? a->second : 0.0) << "\" damping=\""
      << num(s_.joint_damping) << "\"/>\n";
  }

  std::string document() {
    std::ostringstream x;
    x << "<mujoco model=\"" << escape(out_.robotName) << "\">\n";
    x << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
    const std::string integrator = s_.integrator == "implicit" ? "implicit" : "Euler";
    const std::string solver = s_.solver == "pgs" ? "PGS" : s_.solver == "cg" ? "CG" : "Newton";
    x << "  <option timestep=\"" << num(in_.timestep) << "\" gravity=\"" << nums(s_.gravity)
      << "\" integrator=\"" << integrator << "\" cone=\"" << s_.cone << "\" solver=\"" << solver
      << "\" iterations=\"" << s_.solver_iterations << "\" tolerance=\""
      << num(s_.solver_tolerance) << "\">\n";
    x << "    <flag energy=\"enable\"/>\n  </option>\n";
    x << "  <size njmax=\"600\" nconmax=\"200\"/>\n";
    const plugin::TerrainColumns& c = in_.columns;
    const auto boxes = terrainBoxes(c, s_.floor, s_.floor_height, &out_.terrainBoxOfColumn);
    // Columns are solid from their top down: the boxes reach 1 m below the lowest of them.
    double bottom = s_.floor ? s_.floor_height : kInf, highest = -kInf;
    for (const auto& b : boxes) bottom = std::min(bottom, b[4]), highest = std::max(highest, b[4]);
    bottom -= 1.0;
    if (!boxes.empty()) {  // the grid and the boxes (terrain_collision.hpp), filled once compiled
      const std::array<double, 4> extent{c.nx * c.resolution / 2, c.ny * c.resolution / 2,
                                         highest - bottom, 1.0};
      x << "  <asset>\n    <hfield name=\"" << kTerrainIndex << "\" nrow=\"" << c.ny << "\" ncol=\""
        << c.nx << "\" size=\"" << nums(extent) << "\"/>\n    <hfield name=\"" << kTerrainBoxes
        << "\" nrow=\"" << boxes.size() << "\" ncol=\"5\" size=\"1 1 1 1\"/>\n  </asset>\n";
    }
    x << "  <worldbody>\n";
    const std::string terrain = contactAttributes("2", "contype=\"0\" conaffinity=\"1\"");
    if (s_.floor)
      x << "    <geom name=\"floor\" type=\"plane\" size=\"0 0 1\" pos=\"0 0 "
        << num(s_.floor_height) << "\"" << terrain << "/>\n";
    if (!boxes.empty()) {
      const std::array<double, 3> middle{c.x0 + c.nx * c.resolution / 2,
                                         c.y0 + c.ny * c.resolution / 2, bottom};
      x << "    <geom name=\"terrain\" type=\"hfield\" hfield=\"" << kTerrainIndex << "\" pos=\""
        << nums(middle) << "\"" << terrain << "/>\n";
      x << "    <geom name=\"terrain_probe\" type=\"box\" size=\"1 1 1\" group=\"3\" "
           "contype=\"0\" conaffinity=\"0\"/>\n";
    }
    out_.terrainBoxes = static_cast<int>(boxes.size());
    emitBody(0, x, "    ");
    x << "  </worldbody>\n</mujoco>\n";
    return x.str();
  }

  const urdf::ModelInterface& urdf_;
  const ModelInput& in_;
  const MujocoSettings& s_;
  std::map<std::string, int> order_;
  BuiltModel& out_;
  std::vector<Node> nodes_;
  std::map<std::string, std::string> parentLink_;
};

}  // namespace

std::vector<std::array<double, 5>> terrainBoxes(const plugin::TerrainColumns& c, bool floor,
                                                double floorHeight, std::vector<int>* boxOfColumn) {
  std::vector<std::array<double, 5>> boxes;
  std::vector<int> boxOf(c.tops.size(), -1);
  constexpr float kFloorTolerance = 1e-6f;
  auto wanted = [&](int ix, int iy) {
    const float top = c.top(ix, iy);
    return top != plugin::TerrainColumns::kNone &&
           boxOf[static_cast<std::size_t>(ix + c.nx * iy)] < 0 && !(floor && top <= floorHeight + kFloorTolerance);
  };
  for (int iy = 0; iy < c.ny; ++iy)
    for (int ix = 0; ix < c.nx; ++ix) {
      if (!wanted(ix, iy)) continue;
      const float top = c.top(ix, iy);
      // Greedy rectangle: as far along x as the top stays, then as far along y as whole rows do.
      int x1 = ix + 1;
      while (x1 < c.nx && wanted(x1, iy) && c.top(x1, iy) == top) ++x1;
      int y1 = iy + 1;
      for (; y1 < c.ny; ++y1) {
        bool row = true;
        for (int x = ix; x < x1 && row; ++x) row = wanted(x, y1) && c.top(x, y1) == top;
        if (!row) break;
      }
      for (int y = iy; y < y1; ++y)
        for (int x = ix; x < x1; ++x)
          boxOf[static_cast<std::size_t>(x + c.nx * y)] = static_cast<int>(boxes.size());
      boxes.push_back({c.x0 + ix * c.resolution, c.y0 + iy * c.resolution,
                       c.x0 + x1 * c.resolution, c.y0 + y1 * c.resolution,
                       static_cast<double>(top)});
    }
  if (boxOfColumn) *boxOfColumn = std::move(boxOf);
  return boxes;
}

BuiltModel buildMjcf(const ModelInput& input) {
  std::ifstream file(input.urdfPath);
  if (!file) throw std::runtime_error(input.urdfPath + ": cannot read the URDF");
  std::stringstream text;
  text << file.rdbuf();
  const urdf::ModelInterfaceSharedPtr parsed = urdf::parseURDF(text.str());
  if (!parsed) throw std::runtime_error(input.urdfPath + ": urdfdom could not parse the URDF");
  BuiltModel out;
  try {
    Builder(*parsed, input, plugin::jointFileOrder(text.str()), out).build();
  } catch (const std::exception& e) {
    throw std::runtime_error(input.urdfPath + ": " + e.what());
  }
  return out;
}

}  // namespace ballast::mujoco
