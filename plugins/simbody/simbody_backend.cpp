#include "simbody_backend.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "simulated_robot.hpp"  // plugins/common
#include "terrain_columns.hpp"  // plugins/common

namespace ballast::simbody {

void SimbodyBackend::makeWorld(const backend::Config& config) {
  settings_ = parseSimSettings(config.section_yaml ? config.section_yaml : "",
                               config.section_origin ? config.section_origin : "");
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
  options.terrainMap =
      plugin::terrainMapToLoad(settings_, config.terrain_map, options.terrainMapWhere);
  world_ = std::make_unique<SimbodyWorld>(options);
}

std::string SimbodyBackend::configuredMessage() const {
  return "foot contact: " + world_->footContactSummary();
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

}  // namespace ballast::simbody
