// The live map beside the loop: MapTerrain's ring gives the planner the map of the scan it
// asks for; the mapper places a sensor-frame scan by the pose handed off with it (the estimated
// base and the joints, through the lidar link of the model), publishes the grid to the planner
// and measures the scan-to-planner latency.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <octomap/OcTree.h>

#include "control/control_loop.hpp"
#include "control/map_terrain.hpp"
#include "control/mpc_planner.hpp"
#include "control/terrain_mapper.hpp"
#include "model/forward_kinematics.hpp"
#include "model/frames.hpp"
#include "profile/settings.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::control {
namespace {

std::shared_ptr<const terrain::HeightMap> flat(double z) {
  return std::make_shared<const terrain::HeightMap>(z);
}

TEST(MapTerrainRing, ThePlannerGetsTheNewestMapOfTheScansItAsksFor) {
  MapTerrain terrain(flat(0.0));
  terrain.publish(flat(1.0), 1);
  terrain.publish(flat(2.0), 2);
  terrain.publish(flat(3.0), 3);
  EXPECT_TRUE(terrain.refresh(2));
  EXPECT_EQ(terrain.height(0, 0), 2.0);
  EXPECT_EQ(terrain.scanInUse(), 2u);
  EXPECT_FALSE(terrain.refresh(2));
  EXPECT_TRUE(terrain.refresh());
  EXPECT_EQ(terrain.height(0, 0), 3.0);
  terrain.publish(flat(3.5), 3);  // an edit (map clear) after scan 3 wins over scan 3's map
  EXPECT_TRUE(terrain.refresh(3));
  EXPECT_EQ(terrain.height(0, 0), 3.5);
  // Never back to an older map, even one asked for.
  EXPECT_FALSE(terrain.refresh(1));
  EXPECT_EQ(terrain.height(0, 0), 3.5);
}

/// A scan of a floor at z = 0 with a 0.15 m box from x = 1 m, in the frame of the model's lidar
/// link with the robot's base at `base`, level, the joints at zero.
LidarScan scanOfTheBox(const model::Model& m, const double base[3]) {
  model::VecX<double> q = model::VecX<double>::Zero(m.nq);
  for (int k = 0; k < 3; ++k) q[k] = base[k];
  q[6] = 1.0;
  model::Data<double> data(m);
  model::forwardKinematics(m, data, q);
  const model::SE3<double> X = model::framePlacement(m, data, m.frameId("lidar"));
  LidarScan scan;
  scan.index = 1;
  scan.sensor_frame = true;
  std::snprintf(scan.sensor_link, sizeof(scan.sensor_link), "lidar");
  for (int k = 0; k < 3; ++k) scan.state.base.position[k] = base[k];
  scan.state.num_joints = m.nj();
  int n = 0;
  for (double x = 0.3; x < 2.0; x += 0.02)
    for (double y = -0.5; y < 0.5; y += 0.02) {
      const model::Vec3<double> w(x, y, x >= 1.0 ? 0.15 : 0.0);
      const model::Vec3<double> p = X.actInv(w);
      for (int k = 0; k < 3; ++k) scan.xyz[3 * n + k] = static_cast<float>(p[k]);
      ++n;
    }
  scan.count = n;
  for (int c = 0; c < kNumContacts; ++c) scan.state.contact[c] = true;  // feet at z = 0
  return scan;
}

TEST(TerrainMapper, PlacesSensorFrameScansByTheHandedOffPoseAndFeedsThePlanner) {
  const model::Model& m = test::humanoid();
  const profile::Settings all = profile::defaultSettings();
  MpcPlanner planner(m, profile::buildSettings(profile::Profile::load(std::string(BALLAST_SOURCE_DIR) +
                                                                     "/profiles/sim-flat.yaml"),
                                               m),
                     flat(0.0));
  MappingSettings settings = all.mapping;
  TerrainMapper mapper(m, settings, &planner);
  mapper.start();
  const double base[3] = {0.2, 0.1, 0.9};
  LidarScan& slot = mapper.back();
  slot = scanOfTheBox(m, base);
  slot.handoff_ns = monotonicNs();
  mapper.handOff();
  for (int i = 0; i < 2000 && mapper.done() < 1; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_EQ(mapper.done(), 1u);
  mapper.stop();

  // The planner's next update takes the grid; its heights are the box's and the floor's.
  PlannerInput in;
  MapTerrain& terrain = const_cast<MapTerrain&>(planner.terrain());
  ASSERT_TRUE(terrain.refresh(in.map_scan));
  EXPECT_EQ(terrain.scanInUse(), 1u);
  EXPECT_NEAR(terrain.height(1.5, 0.0), 0.15, settings.map.resolution);
  EXPECT_NEAR(terrain.height(0.6, 0.0), 0.0, settings.map.resolution);
  EXPECT_TRUE(terrain.known(1.5, 0.0));
  EXPECT_FALSE(terrain.known(1.5, 2.0));
  EXPECT_GE(terrain.lastLatencyMs(), 0.0);
  const nlohmann::json info = mapper.info();
  EXPECT_EQ(info["scans"]["inserted"], 1);
  EXPECT_TRUE(info.contains("latency_ms"));

  // Cleared: nothing known; the planner gets that map too.
  mapper.clear(0.0);
  ASSERT_TRUE(terrain.refresh());
  EXPECT_FALSE(terrain.known(1.5, 0.0));
}

TEST(TerrainMapper, AScanInALinkTheModelLacksIsRefusedAndSaid) {
  const model::Model& m = test::humanoid();
  TerrainMapper mapper(m, MappingSettings{}, nullptr);
  mapper.start();
  const double base[3] = {0, 0, 0.9};
  LidarScan& slot = mapper.back();
  slot = scanOfTheBox(m, base);
  std::snprintf(slot.sensor_link, sizeof(slot.sensor_link), "velodyne");
  mapper.handOff();
  for (int i = 0; i < 2000 && mapper.done() < 1; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  mapper.stop();
  const nlohmann::json info = mapper.info();
  EXPECT_EQ(info["heights"]["known"], 0);
  EXPECT_NE(info.value("problem", "").find("'velodyne'"), std::string::npos) << info.dump();
}

/// The nice of this process's thread named `name` (/proc/self/task), or -100 if none is.
int niceOfThread(const std::string& name) {
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string n;
    std::getline(comm, n);
    if (n != name) continue;
    errno = 0;
    const int nice = getpriority(PRIO_PROCESS, static_cast<id_t>(std::stoi(task.path().filename())));
    return errno == 0 ? nice : -100;
  }
  return -100;
}

int niceOfMappingThreadWhenStarted(TerrainMapper& mapper, bool background) {
  mapper.start(background);
  // The thread names itself and sets its priority first; it is then waiting for a scan.
  int nice = -100;
  for (int i = 0; i < 2000; ++i) {
    nice = niceOfThread("ballast-mapping");
    if (nice != -100 && (!background || nice == TerrainMapper::kBackgroundNice)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  mapper.stop();
  return nice;
}

// Real time: the mapping thread takes only the CPU the loop, the planner and its team leave
// (nice 19), whatever the priority of the thread that starts it; lockstep, where the loop
// waits for its maps, keeps the normal priority.
TEST(TerrainMapper, InRealTimeTheMappingThreadRunsAtTheLowestNormalPriority) {
  const model::Model& m = test::humanoid();
  errno = 0;
  const int own = getpriority(PRIO_PROCESS, 0);
  ASSERT_EQ(errno, 0);
  ASSERT_LT(own, TerrainMapper::kBackgroundNice) << "the test runs at nice 19 already";
  TerrainMapper lockstep(m, MappingSettings{}, nullptr);
  EXPECT_EQ(niceOfMappingThreadWhenStarted(lockstep, false), own);
  TerrainMapper realtime(m, MappingSettings{}, nullptr);
  EXPECT_EQ(niceOfMappingThreadWhenStarted(realtime, true), TerrainMapper::kBackgroundNice);
}

}  // namespace
}  // namespace ballast::control
