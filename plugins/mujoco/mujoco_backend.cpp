#include "mujoco_backend.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "simulated_robot.hpp"  // plugins/common
#include "terrain_columns.hpp"  // plugins/common

namespace ballast::mujoco {

void MujocoBackend::makeWorld(const backend::Config& config) {
  settings_ = parseMujocoSettings(config.section_yaml ? config.section_yaml : "",
                               config.section_origin ? config.section_origin : "");
  WorldOptions options;
  options.urdfPath = config.urdf_path;
  const plugin::SimulatedRobot robot = plugin::simulatedRobot(config);
  plugin::placeImuAsTheRobotsUnlessGiven(settings_, robot);
  options.contacts = robot.contacts;
  options.settings = settings_;
  options.armature = robot.armature;
  options.locked = robot.locked;
  options.terrainMap =
      plugin::terrainMapToLoad(settings_, config.terrain_map, options.terrainMapWhere);
  options.period = config.period;
  world_ = std::make_unique<MujocoWorld>(options);
}

std::string MujocoBackend::configuredMessage() const { return ""; }

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

}  // namespace ballast::mujoco
