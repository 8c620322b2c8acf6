#include "sim_settings.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace ballast::simbody {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kHalfPi = 1.5707963267948966;
constexpr double kNone = 0.0;  // bounds of keys that have none

using S = SimSettings;
using K = KeyType;

// clang-format off
const std::vector<SettingKey> kKeys = {
  // name, type, default, min, max, choices, group, doc, field
  {"friction", K::kNumber, "0.8", 0, 3, "", "Contact and terrain",
   "Coulomb friction coefficient μ between the robot and the terrain", &S::friction},
  {"friction_stiffness", K::kNumber, "5.0e4", 1e2, 1e7, "", "Contact and terrain",
   "tangential stiffness (N/m per contact sphere) of the stick phase: a foot gives μ f_n / k_t before it slides",
   &S::friction_stiffness},
  {"friction_damping", K::kNumber, "200", 0, 1e5, "", "Contact and terrain",
   "tangential damping (N·s/m per contact sphere) of the stick phase", &S::friction_damping},
  {"contact_stiffness", K::kNumber, "2.0e7", 1e4, 1e10, "", "Contact and terrain",
   "Hertz contact modulus E* (Pa) of robot vs terrain; 2e7 gives about 1 mm of sink standing",
   &S::contact_stiffness},
  {"contact_dissipation", K::kNumber, "1.0", 0, 50, "", "Contact and terrain",
   "Hunt-Crossley dissipation c (s/m): normal force k δ^1.5 (1 + 1.5 c dδ/dt)", &S::contact_dissipation},
  {"foot_sphere_radius", K::kNumber, "0.01", 1e-3, 0.05, "", "Contact and terrain",
   "radius (m) of the contact spheres on the soles (two per contact point: the foot has area)",
   &S::foot_sphere_radius},
  {"foot_width", K::kNumber, "0", 0, 0.5, "", "Contact and terrain",
   "distance (m) between the outer edges of a contact point's two spheres; 0: the width of the foot's collision box",
   &S::foot_width},
  {"body_contact", K::kBool, "true", kNone, kNone, "", "Contact and terrain",
   "bodies other than the feet collide with the terrain too (points on their collision shapes), for falls",
   &S::body_contact},
  {"terrain_map", K::kString, "\"\"", kNone, kNone, "", "Contact and terrain",
   "OctoMap file (.bt/.ot) simulated instead of Config::terrain_map (to test mapping); relative: to the working directory, else to the profile's",
   &S::terrain_map},
  {"floor", K::kBool, "true", kNone, kNone, "", "Contact and terrain",
   "an infinite floor plane under the map (or alone, without a map)", &S::floor},
  {"floor_height", K::kNumber, "0", -100, 100, "", "Contact and terrain",
   "height (m) of that floor", &S::floor_height},

  {"integrator", K::kChoice, "semi_explicit_euler2", kNone, kNone,
   "semi_explicit_euler2|rkm|rk3|rkf|verlet", "Simulation",
   "Simbody integrator, error-controlled; semi_explicit_euler2 takes one step per tick standing (rkm: Runge-Kutta-Merson, 2.5x the cost)",
   &S::integrator},
  {"accuracy", K::kNumber, "1.0e-3", 1e-8, 0.1, "", "Simulation",
   "integrator relative accuracy", &S::accuracy},
  {"gravity", K::kVec3, "[0, 0, -9.81]", -100, 100, "", "Simulation",
   "gravity (m/s², world frame)", &S::gravity},

  {"motor_latency_ticks", K::kInteger, "0", 0, 64, "", "Motors",
   "commands written at tick k act from tick k + N (before the first one arrives, motors are off)",
   &S::motor_latency_ticks},
  {"torque_limit_scale", K::kNumber, "1", 0, 10, "", "Motors",
   "multiplies every URDF <limit effort> (the motor torque limit)", &S::torque_limit_scale},
  {"joint_damping", K::kNumber, "0", 0, 100, "", "Motors",
   "viscous friction (N·m·s/rad) in every joint", &S::joint_damping},
  {"joint_limits", K::kBool, "true", kNone, kNone, "", "Motors",
   "spring-damper stops at the URDF position limits", &S::joint_limits},
  {"joint_limit_stiffness", K::kNumber, "1000", 0, 1e6, "", "Motors",
   "stop stiffness (N·m/rad)", &S::joint_limit_stiffness},
  {"joint_limit_damping", K::kNumber, "2", 0, 1e4, "", "Motors",
   "stop damping (N·m·s/rad), only past the limit and moving further into it", &S::joint_limit_damping},

  {"encoder_resolution", K::kNumber, "0", 0, 0.1, "", "Sensors",
   "joint position quantisation (rad); 0: exact", &S::encoder_resolution},
  {"joint_velocity_noise", K::kNumber, "0", 0, 10, "", "Sensors",
   "white noise σ (rad/s) on joint velocities", &S::joint_velocity_noise},
  {"torque_noise", K::kNumber, "0", 0, 100, "", "Sensors",
   "white noise σ (N·m) on measured joint torques", &S::torque_noise},
  {"imu.frame", K::kString, "imu", kNone, kNone, "", "Sensors",
   "URDF link of the IMU", &S::imu_frame},
  {"imu.gyro_noise_density", K::kNumber, "2.4e-4", 0, 1, "", "Sensors",
   "gyro white noise (rad/s/√Hz); σ per sample = density / √period", &S::imu_gyro_noise_density},
  {"imu.gyro_bias", K::kNumber, "0", 0, 1, "", "Sensors",
   "σ (rad/s) of the per-axis gyro bias, drawn once at start", &S::imu_gyro_bias},
  {"imu.accel_noise_density", K::kNumber, "1.5e-3", 0, 10, "", "Sensors",
   "accelerometer white noise (m/s²/√Hz)", &S::imu_accel_noise_density},
  {"imu.accel_bias", K::kNumber, "0", 0, 5, "", "Sensors",
   "σ (m/s²) of the per-axis accelerometer bias, drawn once at start", &S::imu_accel_bias},
  {"imu.orientation_noise", K::kNumber, "0", 0, 0.5, "", "Sensors",
   "σ (rad) of a random small rotation applied to the reported orientation", &S::imu_orientation_noise},

  {"lidar.enabled", K::kBool, "true", kNone, kNone, "", "Lidar",
   "simulate the lidar (Capabilities::lidar)", &S::lidar_enabled},
  {"lidar.frame", K::kString, "lidar", kNone, kNone, "", "Lidar",
   "URDF link of the sensor; rays in its x-forward, z-up frame", &S::lidar_frame},
  {"lidar.rate", K::kNumber, "10", 0.1, 100, "", "Lidar",
   "scans per second (Hz)", &S::lidar_rate},
  {"lidar.horizontal_rays", K::kInteger, "180", 1, 4096, "", "Lidar",
   "rays per scan line", &S::lidar_horizontal_rays},
  {"lidar.vertical_rays", K::kInteger, "16", 1, 256, "", "Lidar",
   "scan lines", &S::lidar_vertical_rays},
  {"lidar.horizontal_fov", K::kNumber, "6.283185307179586", 1e-3, kTwoPi, "", "Lidar",
   "horizontal field of view (rad), centred on x", &S::lidar_horizontal_fov},
  {"lidar.vertical_min", K::kNumber, "-1.0", -kHalfPi, kHalfPi, "", "Lidar",
   "elevation (rad) of the lowest scan line", &S::lidar_vertical_min},
  {"lidar.vertical_max", K::kNumber, "0.25", -kHalfPi, kHalfPi, "", "Lidar",
   "elevation (rad) of the highest scan line (>= vertical_min)", &S::lidar_vertical_max},
  {"lidar.min_range", K::kNumber, "0.1", 0, 100, "", "Lidar",
   "nearer hits are dropped (m)", &S::lidar_min_range},
  {"lidar.max_range", K::kNumber, "10", 0.1, 200, "", "Lidar",
   "farther hits are dropped (m; > min_range)", &S::lidar_max_range},
  {"lidar.range_noise", K::kNumber, "0", 0, 1, "", "Lidar",
   "white noise σ (m) along each ray", &S::lidar_range_noise},

  {"position_fix.rate", K::kNumber, "0", 0, 100, "", "Localisation",
   "fixes per second (Hz) of the base position, as lidar scans matched against the map give "
   "them (Capabilities::position_fix); 0: none",
   &S::position_fix_rate},
  {"position_fix.noise", K::kNumber, "0.01", 1e-5, 1, "", "Localisation",
   "white noise σ (m) per axis on each fix", &S::position_fix_noise},

  {"initial_posture", K::kChoice, "stand", kNone, kNone, "stand|zero", "Initial state (start())",
   "stand: *hip_pitch -0.4, *knee 0.8, *ankle_pitch -(hip_pitch + knee) so the soles are level, others 0; zero: all 0",
   &S::initial_posture},
  {"initial_joints", K::kJointAngles, "{}", -kTwoPi, kTwoPi, "", "Initial state (start())",
   "joint name -> angle (rad) overriding the posture; within the URDF limits", &S::initial_joints},
  {"initial_xy", K::kVec2, "[0, 0]", -1e4, 1e4, "", "Initial state (start())",
   "base position (m) over the terrain", &S::initial_xy},
  {"initial_yaw", K::kNumber, "0", -kTwoPi, kTwoPi, "", "Initial state (start())",
   "base heading (rad)", &S::initial_yaw},
  {"initial_clearance", K::kNumber, "0", 0, 1000, "", "Initial state (start())",
   "gap (m) between the lowest contact sphere and the terrain under it (0: touching)",
   &S::initial_clearance},
};
// clang-format on

const char* typeName(KeyType t) {
  switch (t) {
    case K::kNumber: return "number";
    case K::kInteger: return "integer";
    case K::kBool: return "bool";
    case K::kString: return "string";
    case K::kChoice: return "choice";
    case K::kVec2: return "vec2";
    case K::kVec3: return "vec3";
    case K::kJointAngles: return "joints";
  }
  return "?";
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

/// "file" and its first line from "file:line".
struct Origin {
  std::string file;
  int line = 1;
  bool hasLine = false;
};

Origin splitOrigin(const std::string& origin) {
  Origin o;
  o.file = origin.empty() ? "<backend section>" : origin;
  const auto colon = origin.rfind(':');
  if (colon != std::string::npos && colon + 1 < origin.size() &&
      std::all_of(origin.begin() + static_cast<long>(colon) + 1, origin.end(),
                  [](char c) { return c >= '0' && c <= '9'; })) {
    o.file = origin.substr(0, colon);
    o.line = std::stoi(origin.substr(colon + 1));
    o.hasLine = true;
  }
  return o;
}

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

class Parser {
 public:
  Parser(SimSettings& out, const Origin& origin) : out_(out), origin_(origin) {}

  std::string at(const YAML::Mark& mark) const {
    if (mark.is_null()) return origin_.file + ":" + std::to_string(origin_.line);
    return origin_.file + ":" + std::to_string(origin_.line + mark.line) + ":" +
           std::to_string(mark.column + 1);
  }

  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& key,
                         const std::string& what) const {
    throw SettingsError(at(mark) + ": " + key + ": " + what);
  }

  /// Walks a map of the section; prefix is "" or "imu." etc.
  void walk(const YAML::Node& map, const std::string& prefix) {
    for (const auto& entry : map) {
      const YAML::Node& keyNode = entry.first;
      const std::string name = prefix + keyNode.Scalar();
      if (const SettingKey* key = find(name)) {
        const auto before = out_.location.find(name);
        if (before != out_.location.end())
          fail(keyNode.Mark(), name, "given twice (first at " + before->second + ")");
        out_.location[name] = at(keyNode.Mark());
        assign(*key, entry.second, entry.second.Mark(), name);
        continue;
      }
      if (isGroup(name)) {
        if (!entry.second.IsMap() && !entry.second.IsNull())
          fail(entry.second.Mark(), name, "expected a map of " + name + ".* keys");
        if (entry.second.IsMap()) walk(entry.second, name + ".");
        continue;
      }
      fail(keyNode.Mark(), name, "unknown key" + suggestion(name));
    }
  }

  void assign(const SettingKey& key, const YAML::Node& node, const YAML::Mark& mark,
              const std::string& name) {
    switch (key.type) {
      case K::kNumber:
        out_.*std::get<double S::*>(key.field) = numberIn(key, node, mark, name);
        break;
      case K::kInteger: {
        const double v = numberIn(key, node, mark, name);
        if (v != std::floor(v)) fail(mark, name, "expected an integer, got " + node.Scalar());
        out_.*std::get<int S::*>(key.field) = static_cast<int>(v);
        break;
      }
      case K::kBool: {
        bool v = false;
        if (!node.IsScalar() || !YAML::convert<bool>::decode(node, v))
          fail(mark, name, "expected true or false, got " + describe(node));
        out_.*std::get<bool S::*>(key.field) = v;
        break;
      }
      case K::kString:
        if (!node.IsScalar() && !node.IsNull())
          fail(mark, name, "expected a string, got " + describe(node));
        out_.*std::get<std::string S::*>(key.field) = node.IsNull() ? "" : node.Scalar();
        break;
      case K::kChoice: {
        const std::string v = node.IsScalar() ? node.Scalar() : "";
        std::stringstream choices(key.choices);
        for (std::string c; std::getline(choices, c, '|');)
          if (c == v) {
            out_.*std::get<std::string S::*>(key.field) = v;
            return;
          }
        fail(mark, name, "expected one of " + std::string(key.choices) + ", got " + describe(node));
      }
      case K::kVec2:
      case K::kVec3: {
        const std::size_t n = key.type == K::kVec2 ? 2 : 3;
        if (!node.IsSequence() || node.size() != n)
          fail(mark, name, "expected a list of " + std::to_string(n) + " numbers, got " +
                               describe(node));
        Vec3d v{0, 0, 0};
        for (std::size_t i = 0; i < n; ++i)
          v[i] = numberIn(key, node[i], node[i].Mark(), name + "[" + std::to_string(i) + "]");
        out_.*std::get<Vec3d S::*>(key.field) = v;
        break;
      }
      case K::kJointAngles: {
        if (!node.IsMap() && !node.IsNull())
          fail(mark, name, "expected a map of joint name: angle (rad), got " + describe(node));
        JointAngles angles;
        for (const auto& e : node) {
          const std::string joint = e.first.Scalar();
          const std::string entryName = name + "." + joint;
          angles[joint] = numberIn(key, e.second, e.second.Mark(), entryName);
          out_.location[entryName] = at(e.first.Mark());
        }
        out_.*std::get<JointAngles S::*>(key.field) = angles;
        break;
      }
    }
  }

 private:
  static const SettingKey* find(const std::string& name) {
    for (const auto& k : kKeys)
      if (name == k.name) return &k;
    return nullptr;
  }

  static bool isGroup(const std::string& name) {
    const std::string prefix = name + ".";
    return std::any_of(kKeys.begin(), kKeys.end(), [&](const SettingKey& k) {
      return std::string(k.name).compare(0, prefix.size(), prefix) == 0;
    });
  }

  static std::string suggestion(const std::string& name) {
    const SettingKey* best = nullptr;
    std::size_t bestDistance = 4;  // typos only, not unrelated names
    for (const auto& k : kKeys) {
      const std::size_t d = editDistance(name, k.name);
      if (d < bestDistance) best = &k, bestDistance = d;
    }
    return best ? std::string(" (did you mean ") + best->name + "?)" : "";
  }

  static std::string describe(const YAML::Node& node) {
    if (node.IsNull()) return "nothing";
    if (node.IsSequence()) return "a list of " + std::to_string(node.size());
    if (node.IsMap()) return "a map";
    return "'" + node.Scalar() + "'";
  }

  double numberIn(const SettingKey& key, const YAML::Node& node, const YAML::Mark& mark,
                  const std::string& name) const {
    double v = 0.0;
    if (!node.IsScalar() || !YAML::convert<double>::decode(node, v))
      fail(mark, name, "expected a number, got " + describe(node));
    if (!(v >= key.min && v <= key.max))
      fail(mark, name, node.Scalar() + " is out of range [" + number(key.min) + ", " +
                           number(key.max) + "]");
    return v;
  }

  SimSettings& out_;
  Origin origin_;
};

void checkAcrossKeys(const SimSettings& s) {
  if (s.lidar_vertical_min > s.lidar_vertical_max)
    throw SettingsError(s.where("lidar.vertical_max") + "is below lidar.vertical_min (" +
                        number(s.lidar_vertical_min) + ")");
  if (s.lidar_min_range >= s.lidar_max_range)
    throw SettingsError(s.where("lidar.max_range") + "must be above lidar.min_range (" +
                        number(s.lidar_min_range) + ")");
}

}  // namespace

std::string SimSettings::where(const std::string& key) const {
  const auto it = location.find(key);
  const std::string at = it != location.end() ? it->second : (origin.empty() ? "<backend section>" : origin);
  return at + ": " + key + ": ";
}

const std::vector<SettingKey>& simSettingKeys() { return kKeys; }

SimSettings parseSimSettings(const std::string& yaml, const std::string& origin) {
  SimSettings s;
  s.origin = origin;
  // Defaults first, through the same code as the profile (so they obey the bounds too).
  const Origin builtIn{"<built-in default>", 1, false};
  Parser defaults(s, builtIn);
  for (const auto& key : kKeys)
    defaults.assign(key, YAML::Load(key.defaultYaml), YAML::Mark::null_mark(), key.name);

  const Origin where = splitOrigin(origin);
  Parser parser(s, where);
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw SettingsError(parser.at(e.mark) + ": " + e.msg);
  }
  if (root.IsNull()) return s;
  if (!root.IsMap())
    throw SettingsError(parser.at(root.Mark()) + ": the simbody backend section must be a map of keys");
  s.location.clear();
  parser.walk(root, "");
  checkAcrossKeys(s);
  return s;
}

std::string simSettingsReference() {
  std::string out;
  std::string group;
  char line[512];
  for (const auto& k : kKeys) {
    if (group != k.group) {
      group = k.group;
      out += "\n" + group + "\n";
    }
    std::string bounds;
    if (k.type == K::kChoice)
      bounds = k.choices;
    else if (k.type != K::kBool && k.type != K::kString)
      bounds = "[" + number(k.min) + ", " + number(k.max) + "]";
    std::snprintf(line, sizeof line, "%-29s %-7s %-14s %-14s %s\n", k.name, typeName(k.type),
                  k.defaultYaml, bounds.c_str(), k.doc);
    out += line;
  }
  return out;
}

}  // namespace ballast::simbody
