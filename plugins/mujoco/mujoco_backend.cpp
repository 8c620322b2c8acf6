#include "mujoco_backend.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "simulated_robot.hpp"  // plugins/common
#include "terrain_columns.hpp"  // plugins/common

namespace ballast::mujoco {

bool MujocoBackend::configure(const backend::Config& config, backend::Error& error) {
  started_ = faulted_ = false;
  world_.reset();
  try {
    settings_ = parseMujocoSettings(config.section_yaml ? config.section_yaml : "",
                                 config.section_origin ? config.section_origin : "");
    if (!(config.period > 0.0 && config.period <= 0.1))
      throw std::runtime_error("Config::period " + std::to_string(config.period) +
                               " s: the control period must be in (0, 0.1] s");
    if (!config.urdf_path || !*config.urdf_path)
      throw std::runtime_error("Config::urdf_path is empty: the simulation needs the robot's URDF");
    WorldOptions options;
    options.urdfPath = config.urdf_path;
    const plugin::SimulatedRobot robot = plugin::simulatedRobot(config);
    plugin::placeImuAsTheRobotsUnlessGiven(settings_, robot);
    options.contacts = robot.contacts;
    options.settings = settings_;
    options.armature = robot.armature;
    options.locked = robot.locked;
    options.terrainMap = settings_.terrain_map.empty()
                             ? std::string(config.terrain_map ? config.terrain_map : "")
                             : plugin::resolveTerrainMap(settings_.terrain_map, settings_.origin,
                                                           settings_.where("terrain_map"));
    if (!settings_.terrain_map.empty()) options.terrainMapWhere = settings_.where("terrain_map");
    options.period = config.period;
    world_ = std::make_unique<MujocoWorld>(options);

    period_ = config.period;
    lockstep_ = config.lockstep;
    caps_ = backend::Capabilities{};
    std::snprintf(caps_.name, sizeof caps_.name, "mujoco");
    caps_.simulation = true;
    caps_.lockstep = true;
    caps_.ground_truth = true;
    caps_.lidar = lidarEnabled_ = settings_.lidar_enabled;
    caps_.disturbance = true;
    caps_.position_fix = settings_.position_fix_rate > 0.0;
    caps_.num_joints = world_->numJoints();
    for (int j = 0; j < caps_.num_joints; ++j)
      std::snprintf(caps_.joint_names[j], backend::kNameLength, "%s",
                    world_->jointNames()[static_cast<std::size_t>(j)].c_str());
    sensors_.configure(plugin::sensorNoise(settings_), period_, config.seed);
    if (lidarEnabled_) lidar_.configure(plugin::lidarSettings(settings_), config.seed);
    host_.configure(settings_.host_stall_at, settings_.host_stall, settings_.host_jitter_from,
                    settings_.host_jitter_fraction, settings_.host_jitter, config.seed);
    configureCommands(settings_.motor_latency_ticks);
  } catch (const std::exception& e) {
    world_.reset();
    copyMessage(error, e.what());
    return false;
  } catch (...) {  // nothing may cross the plugin boundary
    world_.reset();
    copyMessage(error, "mujoco: configure failed with an unknown exception");
    return false;
  }
  copyMessage(error, "");
  return true;
}

bool MujocoBackend::start(backend::Error& error) {
  if (!world_) {
    copyMessage(error, "mujoco: start() before a successful configure()");
    return false;
  }
  try {
    world_->reset();
  } catch (const std::exception& e) {
    copyMessage(error, e.what());
    return false;
  } catch (...) {
    copyMessage(error, "mujoco: start failed with an unknown exception");
    return false;
  }
  restartTicks();
  sensors_.start();
  if (lidarEnabled_) lidar_.start(0.0);
  sampleSensors();
  started_ = true;
  faulted_ = false;
  copyMessage(lastError_, "");
  copyMessage(error, "");
  return true;
}

void MujocoBackend::sampleSensors() {
  sample_.num_joints = world_->numJoints();
  world_->jointState(sample_.q, sample_.dq);
  world_->motorTorques(sample_.tau);
  sample_.has_truth = true;
  world_->truth(sample_.truth);
  sensors_.sample(world_->imu(), world_->time(), sample_);
  sample_.time = world_->time();
  ++sample_.sequence;
}

void MujocoBackend::scanLidar() {
  double origin[3], R[9];
  world_->lidarPose(origin, R);
  const MujocoWorld& world = *world_;
  lidar_.tick(world_->time(), origin, R,
              [&](const double* o, const double* d, double maxRange, double& range) {
                return world.castRay(o, d, maxRange, range);
              });
}

bool MujocoBackend::push(const backend::Push& push, backend::Error& error) {
  if (!started_ || faulted_) {
    copyMessage(error, "mujoco: push() needs a started, healthy simulation");
    return false;
  }
  try {
    const std::string body(push.body, strnlen(push.body, sizeof push.body));
    std::string message;
    if (!world_->push(body, push.force, push.duration, message)) {
      copyMessage(error, ("mujoco: " + message).c_str());
      return false;
    }
  } catch (...) {
    copyMessage(error, "mujoco: push failed with an unknown exception");
    return false;
  }
  copyMessage(error, "");
  return true;
}

bool MujocoBackend::lidarScan(backend::PointCloudView& scan) {
  return started_ && lidarEnabled_ && lidar_.take(scan);
}

}  // namespace ballast::mujoco
