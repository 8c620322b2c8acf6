// Everything a profile sets, as its schema (schema.cpp) fills it, and the settings built from it
// against the robot model: what ballastd hands the loop, the planner, the backend and the
// server. Building checks what needs the model (joint and frame names exist, every actuated joint
// is in exactly one group, every group has gains, the nominal posture is within the joint limits
// and stands the robot at a height `pose` may ask for) and runs the libraries' own checks.
// Problems name the key of the field they concern and read like the loader's:
// "file:line:column: key: what is wrong".
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/settings_schema.hpp"  // plugins/common
#include "control/settings.hpp"
#include "model/contact_points.hpp"
#include "control/terrain_mapper.hpp"
#include "model/model.hpp"
#include "profile/profile.hpp"
#include "server/server_config.hpp"

namespace ballast::profile {

/// The backend plugin, where to find it, and the seed of what it draws at random.
struct BackendSettings {
  std::string name;
  std::vector<std::string> plugin_dirs;
  std::uint64_t seed;
};

/// What a profile gives by joint group or joint name; building resolves it against the model
/// into ControlSettings' per-joint values.
struct JointSettings {
  schema::NamedLists groups;              ///< name -> URDF joints
  schema::NamedNumbers armature;          ///< group or joint -> reflected rotor inertia
  schema::NamedNumbers locked;            ///< joint -> the angle it is fixed at
  schema::NamedNumbers posture;           ///< joint -> standing angle
  schema::NamedNumbers kp, kd;            ///< group -> motor PD gains
  std::vector<std::string> joint_space;   ///< the WBC's joint-space joints: joints or groups
  double torque_limit_scale;              ///< of the URDF effort limits, for the WBC
};

struct Settings {
  std::string extends, description;
  std::string urdf;
  /// The profile's frames; the model's frames made from them are control.contact_frames and
  /// control.imu_frame (robotFrames()).
  std::array<schema::FrameRef, model::kNumContacts> contact_points;
  schema::FrameRef imu;
  JointSettings joints;
  double planner_horizon;  ///< s; the planner's nodes are horizon / dt
  BackendSettings backend;
  std::string terrain_map;
  control::MappingSettings mapping;  ///< the live map from the lidar
  std::size_t telemetry_ring_frames;
  std::string record_on_start;
  server::ServerConfig server;
  control::ControlSettings control;
};

/// The schema applied to an empty profile, and what follows from it without a model: every
/// setting's default.
Settings defaultSettings();

/// The profile's values as the schema reads them, without the model (nothing resolved per joint,
/// nothing checked beyond the loader's checks).
Settings readSettings(const Profile& profile);
/// The profile's settings, checked against the model. Throws ProfileError listing every problem.
Settings settingsFor(const Profile& profile, const model::Model& model);
/// settingsFor(...).control: what the control loop takes.
control::ControlSettings buildSettings(const Profile& profile, const model::Model& model);

/// Loads the profile's robot model; a model error becomes a ProfileError naming the key.
model::Model loadModel(const Profile& profile);

/// The profile key that fills `field` (an address inside `settings`), nullptr if none.
const char* keyOf(const Settings& settings, const void* field);
/// The same for a field of the server's configuration (a copy of Settings::server).
const char* keyOf(const server::ServerConfig& config, const void* field);

}  // namespace ballast::profile
