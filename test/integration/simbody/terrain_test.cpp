// The simulated terrain: distances and normals at a stage's top, side and edge; rays against an
// independent ray march; maps read from OctoMap files and every way that can fail.
#include <gtest/gtest.h>

#include <octomap/ColorOcTree.h>

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
      Terrain::fromOctomap(file, true, 0.0);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(TerrainFiles, AStageMapKeepsItsHeightExactly) {
  const auto tree = maps::makeTerrainMap(maps::stage(0.10, 0.5, 1.0, 1.0), kRes, {-1, 2, -1, 1});
  std::string error;
  for (const std::string& file : {path("stage.bt"), path("stage.ot")}) {
    ASSERT_TRUE(maps::writeTerrainMap(*tree, file, error)) << error;
    const Terrain t = Terrain::fromOctomap(file, false, 0.0);
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
    Terrain::fromOctomap(path("empty.bt"), false, 0.0);
    ADD_FAILURE() << "an empty map without a floor was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path("empty.bt") + ": the map has no occupied cells and the "
                                                        "floor is off: there is no terrain");
  }
}

}  // namespace
}  // namespace ballast::simbody
