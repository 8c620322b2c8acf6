// The live map: made-up scans inserted with ray casting (hits occupied, rays clear), the grid
// updated column by column equal to one built from the whole tree, a ceiling seen by the lidar
// not taken for ground, clearing, seeding from a file and saving.
#include <gtest/gtest.h>

#include <octomap/OcTree.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "terrain/live_map.hpp"
#include "terrain/octree_file.hpp"

namespace ballast::terrain {
namespace {

/// A scan of a world made of a floor at z = 0, a box [bx0, bx1] × [-0.5, 0.5] of height bh, and
/// a ceiling at z = ceiling (0: none), from a sensor at `origin`: rays in a fan of directions,
/// each hitting the first surface (world-frame points).
struct World {
  double bx0 = 1.0, bx1 = 1.5, bh = 0.15;
  double ceiling = 0.0;
};

std::vector<float> scan(const World& w, const std::array<double, 3>& o, int azimuths = 360,
                        int elevations = 96) {
  std::vector<float> points;
  for (int i = 0; i < azimuths; ++i)
    for (int j = 0; j < elevations; ++j) {
      const double az = 2 * M_PI * i / azimuths;
      const double el = -1.2 + 1.9 * j / (elevations - 1);
      const double d[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
      double r = 1e9;
      if (d[2] < 0) r = std::min(r, -o[2] / d[2]);
      if (w.ceiling > 0 && d[2] > 0) r = std::min(r, (w.ceiling - o[2]) / d[2]);
      // The box by slabs: the ray's entry is the largest of the axes' near distances.
      const double lo[3] = {w.bx0, -0.5, 0.0}, hi[3] = {w.bx1, 0.5, w.bh};
      double enter = 0.0, leave = 1e9;
      for (int k = 0; k < 3 && w.bh > 0; ++k) {
        if (std::abs(d[k]) < 1e-12) {
          if (o[k] < lo[k] || o[k] > hi[k]) enter = 2e9;
          continue;
        }
        const double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        enter = std::max(enter, std::min(a, b));
        leave = std::min(leave, std::max(a, b));
      }
      if (w.bh > 0 && enter <= leave) r = std::min(r, enter);
      if (r > 9.0) continue;
      for (int k = 0; k < 3; ++k) points.push_back(static_cast<float>(o[k] + r * d[k]));
    }
  return points;
}

LiveMapSettings settings(double res = 0.04) {
  LiveMapSettings s;
  s.resolution = res;
  s.maxRange = 6.0;
  s.ground = -1.0;  // unknown columns read this: visible in the checks
  return s;
}

void expectSameGrid(const LiveMap& live) {
  const HeightMap full = HeightMap::fromOcTree(live.tree(), -1.0, "", live.grid().rule());
  const HeightMap& grid = live.grid();
  EXPECT_EQ(grid.knownColumns(), full.knownColumns());
  const double res = grid.resolution();
  int compared = 0;
  for (double y = grid.yMin() + res / 2; y < grid.yMin() + grid.columnsY() * res; y += res)
    for (double x = grid.xMin() + res / 2; x < grid.xMin() + grid.columnsX() * res; x += res) {
      ASSERT_EQ(grid.known(x, y), full.known(x, y)) << x << ", " << y;
      ASSERT_NEAR(grid.height(x, y), full.height(x, y), 1e-9) << x << ", " << y;
      ++compared;
    }
  EXPECT_GT(compared, 0);
}

TEST(LiveMap, AScanMakesTheFloorAndTheBoxAndTheColumnsMatchAFullBuild) {
  LiveMap live(settings());
  const World w;
  const auto points = scan(w, {0.0, 0.0, 1.2});
  const ScanUpdate u = live.insert(points.data(), static_cast<int>(points.size() / 3), {}, {0.0, 0.0, 1.2});
  EXPECT_LE(u.points, static_cast<int>(points.size() / 3));
  EXPECT_GT(u.points, static_cast<int>(points.size() / 4));
  EXPECT_GT(u.changedColumns, 100u);
  const HeightMap& g = live.grid();
  // The floor reads 0 (the hits lowered a quarter cell: not the cell above), the box its top
  // within one cell, where the rays reached.
  EXPECT_TRUE(g.known(0.6, 0.0));
  EXPECT_NEAR(g.height(0.6, 0.0), 0.0, 1e-9);
  EXPECT_NEAR(g.height(-1.0, 0.5), 0.0, 1e-9);
  EXPECT_TRUE(g.known(1.1, 0.0));
  EXPECT_NEAR(g.height(1.1, 0.0), 0.15, 0.04);
  // Behind the box, in its shadow: not seen.
  EXPECT_FALSE(g.known(1.6, 0.0));
  EXPECT_EQ(g.height(1.6, 0.0), -1.0);
  // Under the sensor nothing was seen either (the lowest ray is 1.2 rad down).
  EXPECT_FALSE(g.known(0.0, 0.0));
  expectSameGrid(live);

  // A second scan from beyond the box fills its shadow, column by column.
  const auto more = scan(w, {2.5, 0.0, 1.2});
  live.insert(more.data(), static_cast<int>(more.size() / 3), {}, {2.5, 0.0, 1.2});
  EXPECT_TRUE(live.grid().known(1.6, 0.0));
  EXPECT_NEAR(live.grid().height(1.6, 0.0), 0.0, 1e-9);
  expectSameGrid(live);
}

TEST(LiveMap, WithoutAMapFileTheFloorIsKnownWhereNoScanFoundGround) {
  // A profile without a map file says the world is a flat floor (here at the ground default,
  // -1): the live map grown from it knows that floor where the lidar has not looked, and what
  // the lidar saw where it did.
  LiveMap live(settings());
  EXPECT_FALSE(live.grid().floorKnown());  // new: nothing known
  EXPECT_FALSE(live.grid().known(0.0, 0.0));
  live.clear(-1.0, true);
  EXPECT_TRUE(live.grid().known(0.0, 0.0));
  EXPECT_TRUE(live.heights()->known(30.0, -7.0));
  EXPECT_EQ(live.heights()->height(30.0, -7.0), -1.0);
  const auto p = scan(World{}, {0.0, 0.0, 1.2});
  live.insert(p.data(), static_cast<int>(p.size() / 3), {}, {0.0, 0.0, 1.2});
  const auto heights = live.heights();
  EXPECT_NEAR(heights->height(0.6, 0.0), 0.0, 1e-9);   // seen: the floor where it is
  EXPECT_NEAR(heights->height(1.1, 0.0), 0.15, 0.04);  // seen: the box
  for (const auto& [x, y] : {std::pair{1.6, 0.0}, {0.0, 0.0}, {20.0, 0.0}}) {
    EXPECT_TRUE(heights->known(x, y)) << x;  // the box's shadow, under the sensor, far off
    EXPECT_EQ(heights->height(x, y), -1.0) << x;
  }
  // A rebuild (the feet moved up) keeps it; `map clear` knows nothing again.
  EXPECT_TRUE(live.setReference(0.2));
  EXPECT_TRUE(live.grid().known(1.6, 0.0));
  live.clear(-1.0);
  EXPECT_FALSE(live.grid().known(1.6, 0.0));
  EXPECT_FALSE(live.heights()->known(30.0, -7.0));
  // A profile switch to another floor height: the floor is there from then on.
  live.clear(-2.0, true);
  EXPECT_TRUE(live.heights()->known(30.0, -7.0));
  EXPECT_EQ(live.heights()->height(30.0, -7.0), -2.0);
}

TEST(LiveMap, RaysClearWhatIsNoLongerThere) {
  LiveMap live(settings());
  World w;
  w.bh = 0.3;
  for (int i = 0; i < 3; ++i) {
    const auto p = scan(w, {0.0, 0.0, 1.2});
    live.insert(p.data(), static_cast<int>(p.size() / 3), {}, {0.0, 0.0, 1.2});
  }
  EXPECT_NEAR(live.grid().height(1.1, 0.0), 0.3, 0.04);
  w.bh = 0.0;  // the box is taken away: rays now pass where it was and hit the floor
  for (int i = 0; i < 10; ++i) {
    const auto p = scan(w, {0.0, 0.0, 1.2});
    live.insert(p.data(), static_cast<int>(p.size() / 3), {}, {0.0, 0.0, 1.2});
  }
  EXPECT_NEAR(live.grid().height(1.1, 0.0), 0.0, 1e-9);
  EXPECT_NEAR(live.grid().height(1.45, 0.3), 0.0, 1e-9);
  expectSameGrid(live);
}

TEST(LiveMap, ACeilingTheLidarSeesIsNotGround) {
  LiveMap live(settings(0.05));
  World w;
  w.ceiling = 2.6;
  const auto p = scan(w, {0.0, 0.0, 1.2});
  live.insert(p.data(), static_cast<int>(p.size() / 3), {}, {0.0, 0.0, 1.2});
  // Columns where only the ceiling was hit (the lidar looks up 0.7 rad): unknown, not 2.6 m.
  int ceilingOnly = 0, known = 0;
  for (double x = -3; x < 3; x += 0.05)
    for (double y = -3; y < 3; y += 0.05) {
      if (live.grid().known(x, y)) {
        ++known;
        ASSERT_LT(live.grid().height(x, y), 0.2) << x << ", " << y;
      } else if (live.tree().search(x, y, 2.575) && live.tree().isNodeOccupied(live.tree().search(x, y, 2.575))) {
        ++ceilingOnly;
      }
    }
  EXPECT_GT(known, 1000);
  EXPECT_GT(ceilingOnly, 100);
  expectSameGrid(live);
}

TEST(LiveMap, TheScanIsMovedIntoTheWorldByItsPose) {
  // The same scan in the sensor's frame, with the sensor 1 m further along x and turned 90°.
  LiveMap world(settings()), moved(settings());
  const World w;
  const auto p = scan(w, {0.0, 0.0, 1.2});
  world.insert(p.data(), static_cast<int>(p.size() / 3), {}, {0.0, 0.0, 1.2});
  // Sensor frame: p_s = Rᵀ (p_w - t), R a quarter turn about z, t = (0, 0, 1.2).
  std::vector<float> local(p.size());
  for (std::size_t i = 0; i < p.size(); i += 3) {
    local[i] = p[i + 1];
    local[i + 1] = -p[i];
    local[i + 2] = static_cast<float>(p[i + 2] - 1.2);
  }
  ScanPose pose;
  pose.R = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  pose.t = {0.0, 0.0, 1.2};
  moved.insert(local.data(), static_cast<int>(local.size() / 3), pose, {0.0, 0.0, 1.2});
  for (double x = -2; x < 2; x += 0.13)
    for (double y = -2; y < 2; y += 0.13) {
      ASSERT_EQ(moved.grid().known(x, y), world.grid().known(x, y)) << x << ", " << y;
      ASSERT_NEAR(moved.grid().height(x, y), world.grid().height(x, y), 1e-9) << x << ", " << y;
    }
}

TEST(LiveMap, ClearSeedSaveAndTheReference) {
  LiveMap live(settings());
  const auto p = scan(World{}, {0.0, 0.0, 1.2});
  live.insert(p.data(), static_cast<int>(p.size() / 3), {}, {0.0, 0.0, 1.2});
  ASSERT_GT(live.grid().knownColumns(), 0u);
  const std::string file = ::testing::TempDir() + "live.bt";
  std::string error;
  ASSERT_TRUE(live.save(file, error)) << error;
  const auto read = readOcTree(file);
  EXPECT_EQ(read->getNumLeafNodes(), live.tree().getNumLeafNodes());

  live.clear(-1.0);
  EXPECT_EQ(live.grid().knownColumns(), 0u);
  EXPECT_EQ(live.heights()->height(0.6, 0.0), -1.0);

  live.seed(*read, -1.0, file);
  EXPECT_NEAR(live.grid().height(1.1, 0.0), 0.15, 0.04);
  EXPECT_GT(live.grid().knownColumns(), 1000u);
  // Scans go on into the seeded map.
  live.insert(p.data(), static_cast<int>(p.size() / 3), {}, {0.0, 0.0, 1.2});
  expectSameGrid(live);

  // The feet on the 15 cm box: the reference moves, not enough for a rebuild; 0.2 m is.
  EXPECT_FALSE(live.setReference(0.1));
  EXPECT_TRUE(live.setReference(0.2));
  expectSameGrid(live);

  EXPECT_FALSE(live.save("/no/such/dir/live.bt", error));
  EXPECT_EQ(error, "map /no/such/dir/live.bt: cannot write it");
  LiveMapSettings noCells;
  noCells.resolution = 0.0;
  EXPECT_THROW(LiveMap{noCells}, MapError);
}

}  // namespace
}  // namespace ballast::terrain
