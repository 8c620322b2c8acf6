#include "simbody_backend.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "simulated_robot.hpp"  // plugins/common
#include "terrain_columns.hpp"  // plugins/common

namespace ballast::simbody {

bool SimbodyBackend::configure(const backend::Config& config, backend::Error& error) {
  started_ = faulted_ = false;
  world_.reset();
  try {
    settings_ = parseSimSettings(config.section_yaml ? config.section_yaml : "",
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
    for (const auto& c : robot.contacts)
      options.contacts.push_back(
          ContactSpec{c.name, c.link, SimTK::Vec3(c.position[0], c.position[1], c.position[2])});
    options.settings = settings_;
    options.armature = robot.armature;
    options.locked = robot.locked;
    options.terrainMap = settings_.terrain_map.empty()
                             ? std::string(config.terrain_map ? config.terrain_map : "")
                             : plugin::resolveTerrainMap(settings_.terrain_map, settings_.origin,
                                                           settings_.where("terrain_map"));
    if (!settings_.terrain_map.empty()) options.terrainMapWhere = settings_.where("terrain_map");
    world_ = std::make_unique<SimbodyWorld>(options);

    period_ = config.period;
    lockstep_ = config.lockstep;
    caps_ = backend::Capabilities{};
    std::snprintf(caps_.name, sizeof caps_.name, "simbody");
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
    copyMessage(error, "simbody: configure failed with an unknown exception");
    return false;
  }
  copyMessage(error, ("foot contact: " + world_->footContactSummary()).c_str());
  return true;
}

bool SimbodyBackend::start(backend::Error& error) {
  if (!world_) {
    copyMessage(error, "simbody: start() before a successful configure()");
    return false;
  }
  try {
    world_->reset();
  } catch (const std::exception& e) {
    copyMessage(error, e.what());
    return false;
  } catch (...) {
    copyMessage(error, "simbody: start failed with an unknown exception");
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

void SimbodyBackend::sampleSensors() {
  sample_.num_joints = world_->numJoints();
  world_->jointState(sample_.q, sample_.dq);
  world_->motorTorques(sample_.tau);
  sample_.has_truth = true;
  world_->truth(sample_.truth);
  const ImuTruth imu = world_->imu();
  plugin::ImuTruth reading;
  const SimTK::Quaternion q = imu.R_GI.convertRotationToQuaternion();
  for (int i = 0; i < 3; ++i) {
    reading.orientation[i] = q[i + 1];
    reading.angular_velocity[i] = imu.angularVelocity[i];
    reading.specific_force[i] = imu.specificForce[i];
  }
  reading.orientation[3] = q[0];
  sensors_.sample(reading, world_->time(), sample_);
  sample_.time = world_->time();
  ++sample_.sequence;
}

void SimbodyBackend::scanLidar() {
  const SimTK::Transform X = world_->lidarPose();
  double origin[3], R[9];
  for (int i = 0; i < 3; ++i) {
    origin[i] = X.p()[i];
    for (int j = 0; j < 3; ++j) R[3 * i + j] = X.R()[i][j];
  }
  const Terrain& terrain = world_->terrain();
  lidar_.tick(world_->time(), origin, R,
              [&](const double* o, const double* d, double maxRange, double& range) {
                return terrain.castRay(SimTK::Vec3(o[0], o[1], o[2]),
                                       SimTK::Vec3(d[0], d[1], d[2]), maxRange, range);
              });
}

bool SimbodyBackend::push(const backend::Push& push, backend::Error& error) {
  if (!started_ || faulted_) {
    copyMessage(error, "simbody: push() needs a started, healthy simulation");
    return false;
  }
  try {
    const std::string body(push.body, strnlen(push.body, sizeof push.body));
    std::string message;
    if (!world_->push(body, SimTK::Vec3(push.force[0], push.force[1], push.force[2]),
                      push.duration, message)) {
      copyMessage(error, ("simbody: " + message).c_str());
      return false;
    }
  } catch (...) {
    copyMessage(error, "simbody: push failed with an unknown exception");
    return false;
  }
  copyMessage(error, "");
  return true;
}

bool SimbodyBackend::lidarScan(backend::PointCloudView& scan) {
  return started_ && lidarEnabled_ && lidar_.take(scan);
}

}  // namespace ballast::simbody
