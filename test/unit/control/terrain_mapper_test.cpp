// The live map beside the loop: MapTerrain's ring gives the planner the map of the scan it
// asks for; the mapper places a sensor-frame scan by the pose handed off with it (the estimated
// base and the joints, through the lidar link of the model), publishes the grid to the planner
// and measures the scan-to-planner latency.
#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>
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

/// How this process's thread named `name` (/proc/self/task) is scheduled.
struct ThreadPriority {
  bool found = false;
  int nice = 0;
  int policy = SCHED_OTHER;
  int fifo = 0;  ///< its real-time priority (SCHED_FIFO)
};
ThreadPriority priorityOfThread(const std::string& name) {
  ThreadPriority p;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string n;
    std::getline(comm, n);
    if (n != name) continue;
    const pid_t tid = std::stoi(task.path().filename());
    errno = 0;
    p.nice = getpriority(PRIO_PROCESS, static_cast<id_t>(tid));
    sched_param param{};
    p.policy = sched_getscheduler(tid);
    p.found = errno == 0 && p.policy >= 0 && sched_getparam(tid, &param) == 0;
    p.fifo = param.sched_priority;
    return p;
  }
  return p;
}

/// Starts the mapping thread from a thread scheduled SCHED_FIFO at `fifo` (0: as this one is),
/// and says how it ends up scheduled once it waits for scans.
ThreadPriority mappingThreadWhenStarted(TerrainMapper& mapper, bool background, int fifo = 0) {
  std::thread starter([&] {
    if (fifo > 0) {
      sched_param param{};
      param.sched_priority = fifo;
      pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    }
    mapper.start(background);
  });
  starter.join();
  // The thread names itself and sets its priority first; it is then waiting for a scan.
  ThreadPriority p;
  for (int i = 0; i < 2000; ++i) {
    p = priorityOfThread("ballast-mapping");
    const bool settled = background ? p.nice == TerrainMapper::kBackgroundNice
                                    : fifo == 0 || p.fifo != fifo;
    if (p.found && settled) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  mapper.stop();
  return p;
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
  EXPECT_EQ(mappingThreadWhenStarted(lockstep, false).nice, own);
  TerrainMapper realtime(m, MappingSettings{}, nullptr);
  EXPECT_EQ(mappingThreadWhenStarted(realtime, true).nice, TerrainMapper::kBackgroundNice);
}

// A daemon under chrt: real time drops the mapping thread to the normal policy (nice 19);
// lockstep keeps it real time, one priority below the planner's team, which it must not hold
// off a core (at an equal FIFO priority nothing preempts it).
TEST(TerrainMapper, UnderChrtLockstepMapsOnePriorityBelowThePlanner) {
  sched_param param{};
  param.sched_priority = 20;
  bool fifoGranted = false;
  std::thread([&] { fifoGranted = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0; })
      .join();
  if (!fifoGranted) GTEST_SKIP() << "SCHED_FIFO not permitted here (needs CAP_SYS_NICE)";
  const model::Model& m = test::humanoid();
  TerrainMapper lockstep(m, MappingSettings{}, nullptr);
  const ThreadPriority l = mappingThreadWhenStarted(lockstep, false, 20);
  ASSERT_TRUE(l.found);
  EXPECT_EQ(l.policy, SCHED_FIFO);
  EXPECT_EQ(l.fifo, 19);
  TerrainMapper realtime(m, MappingSettings{}, nullptr);
  const ThreadPriority r = mappingThreadWhenStarted(realtime, true, 20);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.policy, SCHED_OTHER);
  EXPECT_EQ(r.nice, TerrainMapper::kBackgroundNice);
}

}  // namespace
}  // namespace ballast::control
