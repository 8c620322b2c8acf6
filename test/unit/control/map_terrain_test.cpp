// The planner's terrain: MapTerrain answers with the height grid's heights, a map published
// from another thread is taken at the planner's next refresh (never in the middle of its reads),
// and MpcPlanner plans its footholds on the map handed to it by setTerrain().
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "control/map_terrain.hpp"
#include "control/mpc_planner.hpp"
#include "profile/settings.hpp"
#include "terrain_maps.hpp"
#include "test/unit/plan_support.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::control {
namespace {

using terrain::HeightMap;

std::shared_ptr<const HeightMap> labStage() {
  return std::make_shared<const HeightMap>(
      HeightMap::fromFile(std::string(BALLAST_SOURCE_DIR) + "/maps/lab-stage.bt", 0.0));
}

TEST(MapTerrain, AnswersWithTheMapsHeights) {
  const std::shared_ptr<const HeightMap> map = labStage();
  const MapTerrain terrain(map);
  for (double x = -1.0; x < 5.0; x += 0.07)
    for (double y : {-1.8, 0.0, 0.9}) EXPECT_EQ(terrain.height(x, y), map->height(x, y));
  EXPECT_NEAR(terrain.height(1.0, 0.0), 0.0, 1e-9);
  EXPECT_NEAR(terrain.height(2.0, 0.0), 0.15, 0.0101);
  // The swing apex looks along the whole swing: a stage between lift-off and touch-down counts.
  EXPECT_NEAR(terrain.maxHeightAlong(1.0, 0.0, 4.0, 0.0), 0.15, 0.0101);
  EXPECT_NEAR(terrain.maxHeightAlong(0.0, 0.0, 1.4, 0.0), 0.0, 1e-9);
  EXPECT_THROW(MapTerrain(nullptr), std::invalid_argument);
}

TEST(MapTerrain, APublishedMapIsTakenAtTheNextRefresh) {
  MapTerrain terrain(std::make_shared<const HeightMap>(0.0));
  EXPECT_FALSE(terrain.refresh());
  terrain.publish(labStage());
  EXPECT_EQ(terrain.height(2.0, 0.0), 0.0);  // the update in progress keeps its map
  EXPECT_TRUE(terrain.refresh());
  EXPECT_NEAR(terrain.height(2.0, 0.0), 0.15, 0.0101);
  EXPECT_FALSE(terrain.refresh());
  EXPECT_THROW(terrain.publish(nullptr), std::invalid_argument);
  EXPECT_NEAR(terrain.height(2.0, 0.0), 0.15, 0.0101);
}

/// Stance contact points at (x, ±0.1, z) and (x - 0.2, ±0.1, z), as a standing robot has.
EstimatedState feetAt(double x, double z) {
  EstimatedState s;
  const double at[kNumContacts][2] = {{x, 0.1}, {x - 0.2, 0.1}, {x, -0.1}, {x - 0.2, -0.1}};
  for (int c = 0; c < kNumContacts; ++c) {
    s.contact[c] = true;
    s.contact_position[c][0] = at[c][0];
    s.contact_position[c][1] = at[c][1];
    s.contact_position[c][2] = z;
  }
  return s;
}

TEST(MapTerrain, AMapThatMovesTheGroundUnderTheFeetIsNotUsedUntilItAgrees) {
  const std::shared_ptr<const HeightMap> stage = labStage();
  MapTerrain terrain(std::make_shared<const HeightMap>(0.0));
  const double tolerance = 0.03, cell = stage->resolution();
  // The first map is compared with the feet: on the floor, it agrees to the millimetre.
  terrain.checkUnderFeet(feetAt(2.5, 0.001), tolerance);
  EXPECT_TRUE(terrain.agrees());
  EXPECT_NEAR(terrain.disagreement(), 0.001, 1e-9);
  // A map that puts the stage where the robot stands on the floor (a wrong map): it moves the
  // ground under the feet by the stage's height, and the planner gets the plane the feet stand
  // on, known everywhere.
  terrain.publish(stage);
  ASSERT_TRUE(terrain.refresh());
  terrain.checkUnderFeet(feetAt(2.5, 0.002), tolerance);
  EXPECT_FALSE(terrain.agrees());
  EXPECT_NEAR(terrain.disagreement(), stage->height(2.5, 0.1), 1e-9);
  for (double x : {0.5, 2.0, 2.5, 40.0}) {
    EXPECT_DOUBLE_EQ(terrain.height(x, 0.0), 0.002) << x;
    EXPECT_TRUE(terrain.known(x, 0.0)) << x;
  }
  // Nothing to compare (every foot in the air): as it was.
  EstimatedState air = feetAt(2.5, 0.3);
  for (bool& c : air.contact) c = false;
  terrain.checkUnderFeet(air, tolerance);
  EXPECT_FALSE(terrain.agrees());
  EXPECT_TRUE(std::isnan(terrain.disagreement()));
  // While it disagrees it is compared with the feet at every update. Hysteresis: back within
  // the limit but not within half of it, it still disagrees ...
  const double limit = tolerance + cell, top = stage->height(2.5, 0.1);
  terrain.checkUnderFeet(feetAt(2.5, top - 0.8 * limit), tolerance);
  EXPECT_FALSE(terrain.agrees());
  // ... and within half it agrees again: the map's heights are back.
  terrain.checkUnderFeet(feetAt(2.5, top - 0.4 * limit), tolerance);
  EXPECT_TRUE(terrain.agrees());
  EXPECT_EQ(terrain.height(2.5, 0.0), stage->height(2.5, 0.0));
  // A map that agrees is not compared with the feet again until it changes: a foot that lands
  // off its foothold is the swing's error, not the map's.
  terrain.checkUnderFeet(feetAt(2.5, top + 0.2), tolerance);
  EXPECT_TRUE(terrain.agrees());
  // A new map with the same ground under the feet (a scan elsewhere) agrees with the one before.
  terrain.publish(labStage());
  ASSERT_TRUE(terrain.refresh());
  terrain.checkUnderFeet(feetAt(2.5, top + 0.2), tolerance);
  EXPECT_TRUE(terrain.agrees());
  EXPECT_NEAR(terrain.disagreement(), 0.0, 1e-12);
  // A first map with a foot by the stage's edge, heel on the floor and toe over the first stage
  // column, agrees: the nearest column within a cell is the floor.
  double edge = 0.5;
  while (stage->height(edge, 0.1) < 0.07) edge += 0.5 * cell;
  MapTerrain byTheEdge(stage);
  byTheEdge.checkUnderFeet(feetAt(edge + 0.5 * cell, 0.0), tolerance);
  EXPECT_TRUE(byTheEdge.agrees()) << "edge at x = " << edge << ", error " << byTheEdge.disagreement();
  // ... and one that has the floor a stage's height above the feet does not.
  MapTerrain onTheStage(stage);
  onTheStage.checkUnderFeet(feetAt(2.5, 0.0), tolerance);
  EXPECT_FALSE(onTheStage.agrees());
  // Tolerance 0: never checked.
  onTheStage.checkUnderFeet(feetAt(2.5, 0.0), 0.0);
  EXPECT_TRUE(onTheStage.agrees());
  EXPECT_TRUE(std::isnan(onTheStage.disagreement()));
}

TEST(MapTerrain, SwapsFromAnotherThreadAreSeenWhole) {
  // The IO thread publishes flat maps at 1, 2, ..., n while the planner thread refreshes and
  // reads: every read is one of the maps, in order, and the last one is seen.
  constexpr int kMaps = 2000;
  MapTerrain terrain(std::make_shared<const HeightMap>(0.0));
  std::atomic<bool> done{false};
  std::thread io([&] {
    for (int i = 1; i <= kMaps; ++i) terrain.publish(std::make_shared<const HeightMap>(i));
    done = true;
  });
  double last = 0.0;
  int changes = 0;
  bool ordered = true, whole = true;
  for (bool finished = false; !finished;) {
    finished = done.load();  // one more round after the last publish
    changes += terrain.refresh();
    const double a = terrain.height(0.3, 0.1), b = terrain.height(-7.0, 2.0);
    whole = whole && a == b && a == std::floor(a);
    ordered = ordered && a >= last;
    last = a;
  }
  io.join();
  EXPECT_TRUE(whole);
  EXPECT_TRUE(ordered);
  EXPECT_EQ(last, kMaps);
  EXPECT_GE(changes, 1);
}

/// The planner's input for the humanoid standing at the origin, walking at vx.
PlannerInput walking(double t, double vx) {
  const model::Model& m = test::humanoid();
  const Eigen::VectorXd q = test::standingConfiguration(m);
  PlannerInput in;
  in.t = t;
  in.mode = Mode::kWalk;
  in.state.t = t;
  for (int i = 0; i < 3; ++i) in.state.base.position[i] = q[i];
  for (int i = 0; i < 4; ++i) in.state.base.orientation[i] = q[3 + i];
  in.state.num_joints = m.nj();
  for (int j = 0; j < m.nj(); ++j) in.state.q[j] = q[model::Model::qIndexOfJoint(j)];
  in.command.vx = vx;
  in.command.velocity_active = true;
  in.command.expires_at = 100.0;
  return in;
}

TEST(MpcPlannerTerrain, FootholdsFollowAMapHandedOverBetweenPlans) {
  const model::Model& m = test::humanoid();
  const ControlSettings settings = profile::buildSettings(
      profile::Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml"), m);
  MpcPlanner planner(m, settings, std::make_shared<const HeightMap>(0.0));
  PlannerOutput out;
  PlannerInput in = walking(0.0, 0.3);
  in.restart = true;
  planner.plan(in, out);
  ASSERT_TRUE(out.valid) << out.message;
  std::vector<test::TouchDown> steps = test::plannedTouchDowns(out.plan);
  ASSERT_FALSE(steps.empty());
  for (const auto& s : steps) EXPECT_EQ(s.position.z(), 0.0) << s.position.x();

  // A 4 cm platform under every step ahead: handed over, then planned on. (Not under the toes
  // alone: a foot across its edge is no foothold, gait/foothold_search.hpp.)
  const auto tree = maps::makeTerrainMap(maps::stage(0.04, -1.0, 3.0, 2.0), 0.02, {-1, 3, -1, 1});
  planner.setTerrain(std::make_shared<const HeightMap>(HeightMap::fromOcTree(*tree, 0.0)));
  planner.plan(walking(0.01, 0.3), out);
  ASSERT_TRUE(out.valid) << out.message;
  steps = test::plannedTouchDowns(out.plan);
  ASSERT_FALSE(steps.empty());
  for (const auto& s : steps) EXPECT_NEAR(s.position.z(), 0.04, 1e-6) << s.position.x();
}

}  // namespace
}  // namespace ballast::control
