// The simulated terrain: distances and normals at a stage's top, side and edge; rays against an
// independent ray march; maps read from OctoMap files and every way that can fail.
#include <gtest/gtest.h>

#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <fstream>
#include <random>

#include "terrain.hpp"
#include "terrain_maps.hpp"

namespace ballast::simbody {
namespace {

constexpr double kRes = 0.02;

/// Floor at 0 and a 10 cm stage over x in [0.4, 1.0), y in [-0.5, 0.5), on a 2 cm grid.
Terrain stageTerrain() {
  const int nx = 100, ny = 100;  // x, y in [-1, 1)
  std::vector<float> tops(nx * ny, -std::numeric_limits<float>::infinity());
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const double x = -1 + (ix + 0.5) * kRes, y = -1 + (iy + 0.5) * kRes;
      tops[ix + nx * iy] = (x > 0.4 && x < 1.0 && std::abs(y) < 0.5) ? 0.1f : 0.0f;
    }
  return Terrain::fromHeights(-1, -1, kRes, nx, ny, tops, true, 0.0);
}

void expectContact(const Terrain& t, SimTK::Vec3 p, double distance, SimTK::Vec3 normal) {
  double d;
  SimTK::Vec3 n;
  ASSERT_TRUE(t.signedDistance(p, 0.02, d, n)) << p;
  EXPECT_NEAR(d, distance, 1e-7) << p;  // heights are floats
  EXPECT_NEAR((n - normal).norm(), 0.0, 1e-6) << p << " normal " << n;
}

TEST(Terrain, DistanceAndNormalOnTopSideAndEdgeOfAStage) {
  const Terrain t = stageTerrain();
  const double s = 1 / std::sqrt(2.0);
  expectContact(t, {0, 0, 0.005}, 0.005, {0, 0, 1});          // floor
  expectContact(t, {0.6, 0, 0.105}, 0.005, {0, 0, 1});        // stage top
  expectContact(t, {0.6, 0, 0.095}, -0.005, {0, 0, 1});       // sunk into the top
  expectContact(t, {0.395, 0, 0.05}, 0.005, {-1, 0, 0});      // beside the riser
  expectContact(t, {0.395, 0, 0.105}, 0.005 * std::sqrt(2.0), {-s, 0, s});  // at the edge
  expectContact(t, {0.6, 0.505, 0.05}, 0.005, {0, 1, 0});     // side face along y
  double d;
  SimTK::Vec3 n;
  EXPECT_FALSE(t.signedDistance({0, 0, 0.05}, 0.02, d, n));   // out of reach
  EXPECT_FALSE(t.signedDistance({0.6, 0, 0.15}, 0.02, d, n));
}

TEST(Terrain, HeightAtReadsColumnsAndFloor) {
  const Terrain t = stageTerrain();
  EXPECT_DOUBLE_EQ(t.heightAt(0.7, 0.0), 0.1f);
  EXPECT_DOUBLE_EQ(t.heightAt(0.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(t.heightAt(5.0, 5.0), 0.0);  // off the grid: the floor
  EXPECT_DOUBLE_EQ(t.maxHeight(), 0.1f);
  const Terrain noFloor = Terrain::fromHeights(0, 0, 1, 1, 1, {0.5f}, false, 0.0);
  EXPECT_TRUE(std::isinf(noFloor.heightAt(5, 5)));
}

TEST(Terrain, RaysHitTopsSidesAndFloor) {
  const Terrain t = stageTerrain();
  double range;
  ASSERT_TRUE(t.castRay({0.6, 0, 1}, {0, 0, -1}, 10, range));
  EXPECT_NEAR(range, 0.9, 1e-6);
  ASSERT_TRUE(t.castRay({0, 0, 1}, {0, 0, -1}, 10, range));
  EXPECT_NEAR(range, 1.0, 1e-12);
  ASSERT_TRUE(t.castRay({0, 0, 0.05}, {1, 0, 0}, 10, range));  // into the riser
  EXPECT_NEAR(range, 0.4, 1e-9);
  EXPECT_FALSE(t.castRay({0, 0, 0.05}, {-1, 0, 0}, 10, range));  // along the floor, away
  EXPECT_FALSE(t.castRay({0, 0, 1}, {0, 0, -1}, 0.5, range));    // beyond max range
  EXPECT_FALSE(t.castRay({0, 0, 1}, {0, 0, 1}, 10, range));      // up into the sky
}

TEST(Terrain, RaysAgreeWithARayMarchOverRoughGround) {
  // Rough 4 cm patches; the reference walks the ray in 0.1 mm steps and asks heightAt().
  const maps::HeightFunction h = maps::rough(0.08, 0.1, 7);
  const int n = 60;
  std::vector<float> tops(n * n);
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix)
      tops[ix + n * iy] = static_cast<float>(h(-0.6 + (ix + 0.5) * kRes, -0.6 + (iy + 0.5) * kRes));
  const Terrain t = Terrain::fromHeights(-0.6, -0.6, kRes, n, n, tops, true, -0.2);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int k = 0; k < 200; ++k) {
    const SimTK::Vec3 o(0.5 * u(rng), 0.5 * u(rng), 0.5 + 0.3 * u(rng));
    const SimTK::Vec3 d = SimTK::UnitVec3(u(rng), u(rng), -0.2 - std::abs(u(rng)));
    double range;
    const bool hit = t.castRay(o, d, 3.0, range);
    double marched = -1;
    for (double s = 0; s <= 3.0; s += 1e-4) {
      const SimTK::Vec3 p = o + s * d;
      if (p[2] <= t.heightAt(p[0], p[1])) {
        marched = s;
        break;
      }
    }
    ASSERT_EQ(hit, marched >= 0) << "ray " << k;
    if (hit) {
      ++hits;
      EXPECT_NEAR(range, marched, 2e-4) << "ray " << k;
    }
  }
  EXPECT_GT(hits, 150);
}

class TerrainFiles : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return ::testing::TempDir() + name; }
  std::string errorOf(const std::string& file) const {
    try {
      Terrain::fromOctomap(file, true, 0.0, 0.5);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(TerrainFiles, AnIndoorMapIsItsFloorAndWallsNotItsCeiling) {
  // An indoor lidar map at 8 cm: a floor two cells thick (top at 0), a ceiling at 2.4-2.56 m, a
  // wall from the floor to the ceiling with one cell the lidar missed, a table top at 0.72 m seen
  // without its legs, and a box whose lower half is a floor cell, a gap of two cells, its top.
  const double r = 0.08;
  octomap::OcTree tree(r);
  auto fill = [&](double x0, double x1, double y0, double y1, double z0, double z1) {
    for (double x = x0 + r / 2; x < x1; x += r)
      for (double y = y0 + r / 2; y < y1; y += r)
        for (double z = z0 + r / 2; z < z1; z += r) tree.updateNode(x, y, z, true);
  };
  fill(-1.6, 1.6, -1.6, 1.6, -0.16, 0.0);   // floor
  fill(-1.6, 1.6, -1.6, 1.6, 2.4, 2.56);    // ceiling
  fill(0.8, 0.96, -1.6, 1.6, 0.0, 1.2);     // wall, up to a missed cell
  fill(0.8, 0.96, -1.6, 1.6, 1.28, 2.4);    // and on to the ceiling
  fill(-0.8, -0.32, -0.8, -0.32, 0.64, 0.72);  // table top
  fill(-1.2, -1.04, 0.8, 0.96, 0.16, 0.32);   // a box above a two-cell gap (starts at 0.16)
  const std::string file = path("indoor.bt");
  ASSERT_TRUE(tree.writeBinaryConst(file));
  const Terrain t = Terrain::fromOctomap(file, false, 0.0, 0.5);
  EXPECT_NEAR(t.heightAt(0.0, 0.0), 0.0, 1e-6);       // under the ceiling: the floor
  EXPECT_NEAR(t.heightAt(0.88, 0.0), 2.56, 1e-6);     // the wall, to the ceiling it meets
  EXPECT_NEAR(t.heightAt(-0.56, -0.56), 0.0, 1e-6);   // under the table top: the floor
  EXPECT_NEAR(t.heightAt(-1.12, 0.88), 0.32, 1e-6);   // the box starts below 0.5 m: kept
  // With the overhang height below the box, it hangs over the floor too.
  const Terrain low = Terrain::fromOctomap(file, false, 0.0, 0.1);
  EXPECT_NEAR(low.heightAt(-1.12, 0.88), 0.0, 1e-6);
  EXPECT_NEAR(low.heightAt(0.88, 0.0), 2.56, 1e-6);
}

TEST_F(TerrainFiles, AStageMapKeepsItsHeightExactly) {
  const auto tree = maps::makeTerrainMap(maps::stage(0.10, 0.5, 1.0, 1.0), kRes, {-1, 2, -1, 1});
  std::string error;
  for (const std::string& file : {path("stage.bt"), path("stage.ot")}) {
    ASSERT_TRUE(maps::writeTerrainMap(*tree, file, error)) << error;
    const Terrain t = Terrain::fromOctomap(file, false, 0.0, 0.5);
    EXPECT_NEAR(t.heightAt(1.0, 0.0), 0.10, 1e-6) << file;
    EXPECT_NEAR(t.heightAt(0.2, 0.0), 0.0, 1e-6) << file;
    EXPECT_NEAR(t.heightAt(1.0, 0.7), 0.0, 1e-6) << file;
    EXPECT_TRUE(std::isinf(t.heightAt(3.0, 0.0))) << file;  // off the map, no floor
    EXPECT_NEAR(t.resolution(), kRes, 1e-9);
  }
}

TEST_F(TerrainFiles, BadFilesSayWhatIsWrong) {
  EXPECT_EQ(errorOf("/no/such/map.bt"), "/no/such/map.bt: cannot read the terrain map");
  std::ofstream(path("text.bt")) << "not a map\n";
  EXPECT_EQ(errorOf(path("text.bt")), path("text.bt") + ": not a binary OctoMap file (.bt)");
  std::ofstream(path("text.ot")) << "not a map\n";
  EXPECT_EQ(errorOf(path("text.ot")), path("text.ot") + ": not an OctoMap file (.ot)");
  std::ofstream(path("map.png")) << "x";
  EXPECT_EQ(errorOf(path("map.png")),
            path("map.png") + ": a terrain map is an OctoMap file ending in .bt or .ot");
  octomap::ColorOcTree color(0.1);
  color.updateNode(octomap::point3d(0, 0, 0), true);
  ASSERT_TRUE(color.write(path("color.ot")));
  EXPECT_EQ(errorOf(path("color.ot")),
            path("color.ot") + ": holds a ColorOcTree, the simulation reads an OcTree");
  octomap::OcTree empty(0.1);
  ASSERT_TRUE(empty.writeBinaryConst(path("empty.bt")));
  try {
    Terrain::fromOctomap(path("empty.bt"), false, 0.0, 0.5);
    ADD_FAILURE() << "an empty map without a floor was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path("empty.bt") + ": the map has no occupied cells and the "
                                                        "floor is off: there is no terrain");
  }
}

TEST_F(TerrainFiles, AMapWhoseGroundIsFarAboveTheFloorHeightIsRefusedNotDropped) {
  // A building map whose floor is at 3 m (a map frame at the lidar's mount, say): with
  // floor_height 0 every cell starts above the 0.5 m overhang limit. Dropping them all would
  // leave the simulation on the bare floor while the planner plans on the map.
  octomap::OcTree tree(0.1);
  for (double x = -0.95; x < 1.0; x += 0.1)
    for (double y = -0.95; y < 1.0; y += 0.1) tree.updateNode(x, y, 2.95, true);
  const std::string file = path("high.bt");
  ASSERT_TRUE(tree.writeBinaryConst(file));
  for (const bool floor : {true, false}) {
    try {
      Terrain::fromOctomap(file, floor, 0.0, 0.5);
      ADD_FAILURE() << "a map with no ground near floor_height was taken, floor " << floor;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()),
                file + ": every occupied cell starts more than overhang_height (0.5 m) above "
                       "floor_height (0 m), the lowest at z = 2.900 m: nothing in the map would "
                       "be ground; set floor_height to the map's ground");
    }
  }
  // With the floor height at the map's ground it is terrain.
  EXPECT_NEAR(Terrain::fromOctomap(file, false, 3.0, 0.5).heightAt(0.05, 0.05), 3.0, 1e-6);
}

}  // namespace
}  // namespace ballast::simbody
