// The MuJoCo robot's physics and sensors: the checks the simbody backend's simulation has
// (test/integration/simbody/simulation_test.cpp), through the backend class itself so the tests
// can also look at what the ABI does not carry (energy, momentum, penetration). Lockstep
// throughout: deterministic and faster than real time (the real-time tests: realtime_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include "mujoco_backend.hpp"
#include "terrain_maps.hpp"
#include "test/integration/simbody/sim_test_support.hpp"
#include "test/unit/allocation_counter.hpp"

namespace ballast::mujoco {
namespace {

using backend::Status;
using simbody::test::holdPosture;
using simbody::test::kContactFrames;
using simbody::test::SimConfig;

/// A configured, started backend and the commands that hold its initial posture.
struct Sim {
  explicit Sim(const std::string& yaml, const std::string& map = "", std::uint64_t seed = 1) {
    config.yaml = yaml;
    config.map = map;
    config.seed = seed;
    backend::Error error;
    ok = backend.configure(config.config(), error) && backend.start(error);
    message = error.message;
    if (!ok) return;
    backend.read(sensors);
    holdPosture(backend.capabilities(), sensors.q, hold);
    off.num_joints = backend.capabilities().num_joints;
  }

  ::testing::AssertionResult run(int n, const backend::Commands& commands) {
    for (int k = 0; k < n; ++k) {
      const Status w = backend.write(commands), a = backend.advance(), r = backend.read(sensors);
      if (w != Status::kOk || a != Status::kOk || r != Status::kOk)
        return ::testing::AssertionFailure() << "tick " << k << ": " << backend.lastError().message;
    }
    return ::testing::AssertionSuccess();
  }

  MujocoWorld& world() { return backend.world(); }
  int joint(const std::string& name) const {
    const auto& caps = backend.capabilities();
    for (int j = 0; j < caps.num_joints; ++j)
      if (name == caps.joint_names[j]) return j;
    return -1;
  }

  SimConfig config;
  MujocoBackend backend;
  backend::Sensors sensors;
  backend::Commands hold, off;
  bool ok = false;
  std::string message;
};

double norm(const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

TEST(MujocoSimulation, DropFromFiveCentimetresRestsOnTheFeet) {
  Sim touching("");
  Sim sim("initial_clearance: 0.05");
  ASSERT_TRUE(touching.ok && sim.ok) << touching.message << sim.message;
  const double z0 = sim.sensors.truth.base_position[2];
  EXPECT_NEAR(z0 - touching.sensors.truth.base_position[2], 0.05, 1e-9);
  EXPECT_FALSE(sim.sensors.truth.contact[0]);  // in the air
  double deepest = 0.0;
  for (int k = 0; k < 15; ++k) {
    ASSERT_TRUE(sim.run(100, sim.hold));
    deepest = std::max(deepest, sim.world().maxPenetration());
  }
  const backend::Truth& t = sim.sensors.truth;
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(t.contact[c]) << kContactFrames[c];
  EXPECT_FALSE(t.non_foot_contact);
  const double penetration = sim.world().maxPenetration();
  EXPECT_GT(penetration, 0.0);
  EXPECT_LT(penetration, 0.005);
  EXPECT_LT(deepest, 0.01) << "the landing";
  std::printf("penetration standing %.2f mm, deepest on landing %.2f mm\n", 1e3 * penetration,
              1e3 * deepest);
  EXPECT_LT(std::abs(sim.world().baseVelocity()[2]), 0.005);
  EXPECT_LT(norm(sim.world().baseVelocity()), 0.05);
  EXPECT_NEAR(z0 - t.base_position[2], 0.05, 0.015);
  // The feet carry the robot: the contact forces add up to its weight.
  double fz = 0;
  for (int c = 0; c < 4; ++c) fz += t.contact_force[c][2];
  EXPECT_NEAR(fz, sim.world().mass() * 9.81, 0.02 * sim.world().mass() * 9.81);
}

/// No motor torque, no joint limits, no contact: a free multibody in gravity, tumbling with its
/// limbs flailing. Its energy may only fall (integration error), as the simbody backend's test
/// says; MuJoCo's semi-implicit Euler at 1 ms loses less than 2 % of the kinetic energy in 2 s
/// of violent tumbling, its implicit integrator more (it damps).
TEST(MujocoSimulation, InFreeFlightWithoutTorqueTheEnergyHolds) {
  for (const char* integrator : {"euler", "implicit"}) {
    SCOPED_TRACE(integrator);
    Sim sim(std::string("initial_clearance: 50\njoint_limits: false\nintegrator: ") + integrator);
    ASSERT_TRUE(sim.ok) << sim.message;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-2, 2);
    sim.world().modifyState([&](const mjModel* m, mjData* d) {
      for (int i = 0; i < m->nv; ++i) d->qvel[i] = u(rng);
    });
    const double e0 = sim.world().energy();
    const double kinetic = sim.world().data()->energy[1];
    double highest = e0, lowest = e0;
    const backend::Sensors start = sim.sensors;
    for (int k = 0; k < 20; ++k) {
      ASSERT_TRUE(sim.run(100, sim.off));
      highest = std::max(highest, sim.world().energy());
      lowest = std::min(lowest, sim.world().energy());
      EXPECT_FALSE(sim.sensors.truth.contact[0] || sim.sensors.truth.non_foot_contact);
    }
    EXPECT_LE(highest - e0, 0.01 * kinetic) << "initial kinetic energy " << kinetic << " J";
    if (std::string(integrator) == "euler") {
      EXPECT_LE(e0 - lowest, 0.02 * kinetic) << "initial kinetic energy " << kinetic << " J";
    }
    double moved = 0;
    for (int j = 0; j < sim.sensors.num_joints; ++j) moved += std::abs(sim.sensors.q[j] - start.q[j]);
    EXPECT_GT(moved, 1.0);
    EXPECT_GT(kinetic, 100.0);
  }
}

TEST(MujocoSimulation, JointPdHoldsTheStandingPostureForThreeSeconds) {
  Sim sim("");
  ASSERT_TRUE(sim.ok) << sim.message;
  const double* p0 = sim.sensors.truth.base_position;
  const double x0 = p0[0], y0 = p0[1], z0 = p0[2];
  double farthest = 0;
  for (int k = 0; k < 30; ++k) {
    ASSERT_TRUE(sim.run(100, sim.hold));
    const double* p = sim.sensors.truth.base_position;
    farthest = std::max(farthest, std::hypot(p[0] - x0, p[1] - y0, p[2] - z0));
    for (int c = 0; c < 4; ++c) EXPECT_TRUE(sim.sensors.truth.contact[c]);
  }
  EXPECT_LT(farthest, 0.03);
  EXPECT_FALSE(sim.sensors.truth.non_foot_contact);
}

TEST(MujocoSimulation, APushOnTheTorsoInTheAirChangesMomentumByItsImpulse) {
  Sim sim("initial_clearance: 50");
  ASSERT_TRUE(sim.ok) << sim.message;
  const std::array<double, 3> p0 = sim.world().linearMomentum();
  backend::Push push;
  std::strcpy(push.body, "torso");
  push.force[0] = 40.0;
  push.duration = 1.0;
  backend::Error error;
  ASSERT_TRUE(sim.backend.push(push, error)) << error.message;
  ASSERT_TRUE(sim.run(1200, sim.off));
  const std::array<double, 3> p1 = sim.world().linearMomentum();
  const double weight = sim.world().mass() * 9.81;
  EXPECT_NEAR(p1[0] - p0[0], 40.0, 0.05 * 40.0);
  EXPECT_NEAR(p1[1] - p0[1], 0.0, 1e-6);
  EXPECT_NEAR(p1[2] - p0[2], -weight * 1.2, 1e-3 * weight);
  EXPECT_LT(p1[0] - p0[0], 41.0);  // it was 1 s, not 1.2 s
}

TEST(MujocoSimulation, PushesNameTheirBodyOrFail) {
  Sim sim("initial_clearance: 50");
  ASSERT_TRUE(sim.ok) << sim.message;
  backend::Push push;
  push.force[0] = 10;
  push.duration = 0.1;
  backend::Error error;
  std::strcpy(push.body, "tail");
  EXPECT_FALSE(sim.backend.push(push, error));
  EXPECT_NE(std::string(error.message).find("has no link 'tail'"), std::string::npos) << error.message;
  push.body[0] = '\0';  // the base
  push.duration = -1;
  EXPECT_FALSE(sim.backend.push(push, error));
  EXPECT_STREQ(error.message, "mujoco: push: the force must be finite and the duration positive");
  push.duration = 0.1;
  EXPECT_TRUE(sim.backend.push(push, error)) << error.message;
}

TEST(MujocoSimulation, FeetStickBelowTheFrictionLimitAndSlideAboveIt) {
  // 40 N sideways at the pelvis for 0.5 s against μ m g: 490 N at μ = 0.8, 12 N at μ = 0.02.
  auto slip = [](const std::string& yaml) {
    Sim sim(yaml);
    EXPECT_TRUE(sim.ok) << sim.message;
    EXPECT_TRUE(sim.run(300, sim.hold));
    const MujocoWorld& w = sim.world();
    const int foot = mj_name2id(w.model(), mjOBJ_BODY, "left_foot");
    const double x0 = w.data()->xpos[3 * foot], y0 = w.data()->xpos[3 * foot + 1];
    backend::Push push;
    push.force[1] = 40.0;
    push.duration = 0.5;
    backend::Error error;
    EXPECT_TRUE(sim.backend.push(push, error)) << error.message;
    EXPECT_TRUE(sim.run(500, sim.hold));
    EXPECT_GT(sim.sensors.truth.base_position[2], 0.8);
    return std::hypot(w.data()->xpos[3 * foot] - x0, w.data()->xpos[3 * foot + 1] - y0);
  };
  EXPECT_LT(slip("friction: 0.8"), 0.002);
  EXPECT_GT(slip("friction: 0.02"), 0.02);
}

TEST(MujocoSimulation, StandingStillTheImuFeelsGravityAndFallingItFeelsNothing) {
  const std::string quiet = "imu: {gyro_noise_density: 0, accel_noise_density: 0}\n";
  Sim standing(quiet);
  Sim falling(quiet + "initial_clearance: 50\n");
  ASSERT_TRUE(standing.ok && falling.ok);
  ASSERT_TRUE(standing.run(500, standing.hold));
  ASSERT_TRUE(falling.run(100, falling.hold));
  const backend::Imu& a = standing.sensors.imu;
  const double f = std::sqrt(a.linear_acceleration[0] * a.linear_acceleration[0] +
                             a.linear_acceleration[1] * a.linear_acceleration[1] +
                             a.linear_acceleration[2] * a.linear_acceleration[2]);
  EXPECT_NEAR(f, 9.81, 0.2);
  EXPECT_LT(std::acos(a.linear_acceleration[2] / f), 0.03);
  EXPECT_NEAR(std::abs(a.orientation[3]), 1.0, 1e-3);
  const backend::Imu& b = falling.sensors.imu;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(b.linear_acceleration[i], 0.0, 0.05);
  EXPECT_TRUE(standing.sensors.imu_valid && standing.sensors.has_truth);
  // The IMU on the pelvis turns with the base: the gyro reads the truth in the IMU frame.
  const double* q = standing.sensors.truth.base_orientation;
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(std::abs(a.orientation[i]), std::abs(q[i]), 1e-9);
}

TEST(MujocoSimulation, TheSharedSensorModelGivesBiasSpreadAndQuantisation) {
  Sim biased("imu: {gyro_noise_density: 0, gyro_bias: 0.05}\nencoder_resolution: 0.001\n");
  Sim exact("imu: {gyro_noise_density: 0}\n");
  ASSERT_TRUE(biased.ok && exact.ok) << biased.message << exact.message;
  ASSERT_TRUE(biased.run(10, biased.hold));
  ASSERT_TRUE(exact.run(10, exact.hold));
  double bias[3];
  for (int i = 0; i < 3; ++i) bias[i] = biased.sensors.imu.angular_velocity[i] - exact.sensors.imu.angular_velocity[i];
  const double b = std::sqrt(bias[0] * bias[0] + bias[1] * bias[1] + bias[2] * bias[2]);
  EXPECT_GT(b, 0.005);
  EXPECT_LT(b, 0.5);
  for (int j = 0; j < biased.sensors.num_joints; ++j) {
    const double steps = biased.sensors.q[j] / 0.001;
    EXPECT_NEAR(steps, std::round(steps), 1e-6) << biased.backend.capabilities().joint_names[j];
  }
  // White noise: σ per sample = density / √period = 0.01 / √0.001 = 0.316 rad/s.
  Sim noisy("imu: {gyro_noise_density: 0.01}\n");
  Sim quiet("imu: {gyro_noise_density: 0}\n");
  ASSERT_TRUE(noisy.ok && quiet.ok);
  double sum = 0, sum2 = 0;
  const int n = 1000;
  for (int k = 0; k < n; ++k) {
    ASSERT_TRUE(noisy.run(1, noisy.hold));
    ASSERT_TRUE(quiet.run(1, quiet.hold));
    const double e = noisy.sensors.imu.angular_velocity[0] - quiet.sensors.imu.angular_velocity[0];
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(sigma, 0.316, 0.316 * 0.07);
  EXPECT_NEAR(mean, 0.0, 4 * 0.316 / std::sqrt(n));
}

TEST(MujocoSimulation, PositionFixesComeAtTheirRateWithTheirNoise) {
  Sim fixed("position_fix: {rate: 50, noise: 0.02}\n");
  ASSERT_TRUE(fixed.ok) << fixed.message;
  EXPECT_TRUE(fixed.backend.capabilities().position_fix);
  int fixes = 0;
  double sum2 = 0, lastTime = -1;
  for (int k = 0; k < 4000; ++k) {
    ASSERT_TRUE(fixed.run(1, fixed.hold));
    const backend::PositionFix& f = fixed.sensors.position_fix;
    if (!f.fresh) continue;
    ++fixes;
    if (lastTime >= 0) {
      EXPECT_NEAR(f.time - lastTime, 0.02, 1e-6);
    }
    lastTime = f.time;
    const double e = f.position[0] - fixed.sensors.truth.base_position[0];
    sum2 += e * e;
  }
  EXPECT_EQ(fixes, 200);
  EXPECT_NEAR(std::sqrt(sum2 / fixes), 0.02, 0.02 * 0.15);
}

TEST(MujocoSimulation, MotorsKeepTheirTorqueLimitAndLatency) {
  Sim sim("initial_clearance: 50\nmotor_latency_ticks: 3\n");
  ASSERT_TRUE(sim.ok) << sim.message;
  const int elbow = sim.joint("left_elbow"), knee = sim.joint("left_knee");
  ASSERT_GE(elbow, 0);
  ASSERT_GE(knee, 0);
  backend::Commands cmd = sim.off;
  cmd.joint[elbow].tau_ff = 5.0;
  cmd.joint[knee].tau_ff = 1000.0;  // the URDF says 250 N·m
  std::vector<double> elbowTorque;
  for (int k = 0; k < 5; ++k) {
    ASSERT_TRUE(sim.run(1, cmd));
    elbowTorque.push_back(sim.sensors.tau[elbow]);
  }
  EXPECT_EQ(elbowTorque, (std::vector<double>{0, 0, 0, 5, 5}));  // written at tick 0, acts at 3
  EXPECT_DOUBLE_EQ(sim.sensors.tau[knee], 250.0);
}

TEST(MujocoSimulation, TheMotorsDampingActsInEveryStepAsTheCommandSays) {
  // An elbow in the air (the elbow bends to -2.5 rad), kd only, from -2 rad/s towards
  // dq_des = -1 rad/s: it settles there, and the torque is the command's, at one and at four
  // steps per tick.
  for (int substeps : {1, 4}) {
    SCOPED_TRACE(substeps);
    Sim sim("initial_clearance: 50\ngravity: [0, 0, 0]\nsubsteps: " + std::to_string(substeps));
    ASSERT_TRUE(sim.ok) << sim.message;
    const int j = sim.joint("left_elbow");
    const int dof = sim.world().model()->jnt_dofadr[mj_name2id(sim.world().model(), mjOBJ_JOINT, "left_elbow")];
    sim.world().modifyState([&](const mjModel*, mjData* d) { d->qvel[dof] = -2.0; });
    backend::Commands cmd = sim.off;
    cmd.joint[j].kd = 0.5;
    cmd.joint[j].dq_des = -1.0;
    ASSERT_TRUE(sim.run(300, cmd));
    // The elbow's speed settles at dq_des (the free-floating rest of the robot turns a little).
    EXPECT_NEAR(sim.sensors.dq[j], -1.0, 0.05);
    EXPECT_NEAR(sim.sensors.tau[j], 0.5 * (-1.0 - sim.sensors.dq[j]), 1e-9);
  }
}

TEST(MujocoSimulation, BadCommandsAreRefusedAndTheOldOnesKept) {
  Sim sim("");
  ASSERT_TRUE(sim.ok) << sim.message;
  ASSERT_TRUE(sim.run(10, sim.hold));
  backend::Commands bad = sim.hold;
  bad.joint[3].q_des = std::nan("");
  EXPECT_EQ(sim.backend.write(bad), Status::kFault);
  EXPECT_STREQ(sim.backend.lastError().message,
               "mujoco: joint 3 (left_knee): q_des is not finite; commands ignored");
  bad = sim.hold;
  bad.num_joints = 12;
  EXPECT_EQ(sim.backend.write(bad), Status::kFault);
  EXPECT_STREQ(sim.backend.lastError().message,
               "mujoco: commands for 12 joints, the robot has 24; ignored");
  EXPECT_EQ(sim.backend.advance(), Status::kOk);
  ASSERT_TRUE(sim.run(500, sim.hold));
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(sim.sensors.truth.contact[c]);
}

TEST(MujocoSimulation, ASampleIsReadOnceThenItIsStale) {
  Sim sim("");
  ASSERT_TRUE(sim.ok) << sim.message;
  backend::Sensors s;
  EXPECT_EQ(sim.backend.read(s), Status::kStale);
  EXPECT_EQ(sim.backend.advance(), Status::kOk);
  EXPECT_EQ(sim.backend.read(s), Status::kOk);
  EXPECT_EQ(sim.backend.read(s), Status::kStale);
  EXPECT_EQ(s.sequence, 2u);
  EXPECT_DOUBLE_EQ(s.time, 0.001);
}

TEST(MujocoSimulation, TicksAllocateNothing) {
  Sim sim("lidar: {rate: 50}\nposition_fix: {rate: 10}\n");
  ASSERT_TRUE(sim.ok) << sim.message;
  ASSERT_TRUE(sim.run(2, sim.hold));
  backend::Sensors s;
  Status w, a, r;
  EXPECT_EQ(ballast::test::allocationsIn([&] {
              for (int k = 0; k < 200; ++k) {
                w = sim.backend.write(sim.hold);
                a = sim.backend.advance();
                r = sim.backend.read(s);
              }
            }),
            0);
  EXPECT_EQ(w, Status::kOk);
  EXPECT_EQ(a, Status::kOk);
  EXPECT_EQ(r, Status::kOk);
}

TEST(MujocoSimulation, AFallingRobotTouchesWithMoreThanItsFeetAndStaysAboveTheFloor) {
  Sim sim("");
  ASSERT_TRUE(sim.ok) << sim.message;
  bool nonFoot = false;
  for (int k = 0; k < 30 && !nonFoot; ++k) {
    ASSERT_TRUE(sim.run(100, sim.off));  // motors off: it collapses
    nonFoot = sim.sensors.truth.non_foot_contact;
  }
  EXPECT_TRUE(nonFoot);
  ASSERT_TRUE(sim.run(1000, sim.off));
  EXPECT_GT(sim.sensors.truth.base_position[2], 0.04);  // lies on the floor, not in it
  EXPECT_LT(sim.world().maxPenetration(), 0.01);
}

class MujocoStageMap : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // 10 cm stage from x = 0.6 m to 2.0 m, 2 m wide, on a 2 cm map with a floor.
    path_ = ::testing::TempDir() + "mujoco-stage10.bt";
    const auto tree = maps::makeTerrainMap(
        maps::stage(kStage.height, kStage.x0, kStage.x1 - kStage.x0, 2 * kStage.halfWidth), kRes,
        {-1, 3, -1.5, 1.5});
    std::string error;
    ASSERT_TRUE(maps::writeTerrainMap(*tree, path_, error)) << error;
  }
  static constexpr double kRes = 0.02;
  static constexpr simbody::test::Stage kStage{0.10, 0.6, 2.0, 1.0};
  static std::string path_;
};
std::string MujocoStageMap::path_;

TEST_F(MujocoStageMap, TheLidarSeesTheStageTopAtItsHeight) {
  // On its link, and mounted off it (offset and tilt in the link's frame): the points, placed
  // by the pose the sensor reports, lie on the stage and the floor either way.
  double originOnLink[3] = {0, 0, 0};
  for (const char* mount : {"", ", frame: {link: lidar, offset: [0.05, 0, 0.1], rpy: [0, 0.2, 0.3]}"}) {
    SCOPED_TRACE(mount);
    Sim sim(std::string("lidar: {vertical_min: -1.2, vertical_max: 0.0") + mount + "}\n", path_);
    ASSERT_TRUE(sim.ok) << sim.message;
    backend::PointCloudView scan;
    EXPECT_FALSE(sim.backend.lidarScan(scan));
    int ticks = 0;
    while (!sim.backend.lidarScan(scan) && ticks < 200) {
      ASSERT_TRUE(sim.run(1, sim.hold));
      ++ticks;
    }
    ASSERT_EQ(ticks, 100);  // 10 Hz
    EXPECT_DOUBLE_EQ(scan.time, 0.1);
    // In the sensor frame at the sweep's end (ABI 6): placed here by the sensor's true pose then.
    ASSERT_EQ(scan.frame, backend::ScanFrame::kSensor);
    EXPECT_STREQ(scan.sensor_link, "lidar");
    double o[3], R[9];
    sim.backend.world().lidarPose(o, R);
    EXPECT_GT(o[2], 1.3);  // the head
    if (*mount == 0) {
      std::copy(o, o + 3, originOnLink);
    } else {
      EXPECT_NEAR(o[2] - originOnLink[2], 0.1, 0.01);  // the head stands level
      EXPECT_NEAR(R[6], -std::sin(0.2), 0.02);          // the x axis pitched down by 0.2 rad
    }
    const auto sorted = simbody::test::sortScanOnStage(scan, o, R, kStage, 0.05, -0.9, 2.9);
    EXPECT_GT(sorted.onStage, 100);
    EXPECT_GT(sorted.onFloor, 100);
    EXPECT_LT(std::max(sorted.stageError, sorted.floorError), kRes)
        << "worst point " << sorted.worst[0] << " " << sorted.worst[1] << " " << sorted.worst[2];
    EXPECT_FALSE(sim.backend.lidarScan(scan));  // taken
  }
}

TEST_F(MujocoStageMap, TheRobotStandsOnTheStage) {
  Sim floor("", path_);
  Sim stage("initial_xy: [1.3, 0]\n", path_);
  ASSERT_TRUE(floor.ok && stage.ok) << floor.message << stage.message;
  ASSERT_TRUE(floor.run(1000, floor.hold));
  ASSERT_TRUE(stage.run(1000, stage.hold));
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(stage.sensors.truth.contact[c]);
  EXPECT_FALSE(stage.sensors.truth.non_foot_contact);
  EXPECT_NEAR(stage.sensors.truth.base_position[2] - floor.sensors.truth.base_position[2], 0.10, 1e-3);
  EXPECT_LT(stage.world().maxPenetration(), 0.005);
  EXPECT_LT(std::abs(stage.world().baseVelocity()[2]), 0.005);
}

}  // namespace
}  // namespace ballast::mujoco
