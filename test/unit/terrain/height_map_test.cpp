// The height grid: the example maps read back as maps/README.md describes them, generated maps
// column by column against their height functions, the ground default off the map and in
// unknown columns, slopes, and every way a map file is refused (named, with the reason).
#include <gtest/gtest.h>

#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "terrain/height_map.hpp"
#include "terrain/octree_file.hpp"
#include "terrain_maps.hpp"
#include "test/unit/allocation_counter.hpp"

namespace ballast::terrain {
namespace {

constexpr double kRes = 0.02;                  // the example maps' cells
constexpr double kHalfCell = kRes / 2 + 1e-6;  // the maps' quantisation (README: ±res/2)

std::string exampleMap(const std::string& name) {
  return std::string(BALLAST_SOURCE_DIR) + "/maps/" + name;
}

/// The top of a generated column of height h (maps/terrain_maps.hpp: a cell is occupied when
/// its centre is below h), counted independently of the generator.
double quantised(double h, double res) {
  int cells = 0;
  while ((cells + 0.5) * res < h) ++cells;
  return cells * res;
}

TEST(HeightMap, LabStageIsFlatBeforeTheStageAndFifteenCentimetresOnIt) {
  const HeightMap map = HeightMap::fromFile(exampleMap("lab-stage.bt"), 0.0);
  EXPECT_DOUBLE_EQ(map.resolution(), kRes);
  // README: a stage 15 cm high, 2 m deep, 3 m wide, from x = 1.5 m; floor x -2..6, y -2..2.
  for (double y = -1.45; y <= 1.45; y += 0.1) {
    for (double x = -1.9; x < 1.49; x += 0.1)
      EXPECT_NEAR(map.height(x, y), 0.0, 1e-9) << x << ", " << y;
    for (double x = 1.51; x < 3.49; x += 0.1)
      EXPECT_NEAR(map.height(x, y), 0.15, kHalfCell) << x << ", " << y;
    for (double x = 3.51; x < 5.9; x += 0.1)
      EXPECT_NEAR(map.height(x, y), 0.0, 1e-9) << x << ", " << y;
  }
  for (double x = 1.6; x < 3.4; x += 0.1) EXPECT_NEAR(map.height(x, 1.7), 0.0, 1e-9) << x;
  // The edge is a step, where the map has it: no ramp between the two levels.
  EXPECT_NEAR(map.height(1.499, 0.0), 0.0, 1e-9);
  EXPECT_NEAR(map.height(1.501, 0.0), 0.15, kHalfCell);
  EXPECT_NEAR(map.height(3.499, 0.0), 0.15, kHalfCell);
  EXPECT_NEAR(map.height(3.501, 0.0), 0.0, 1e-9);
}

TEST(HeightMap, LabStepsRiseTenCentimetresEveryThirtyThenALanding) {
  const HeightMap map = HeightMap::fromFile(exampleMap("lab-steps.bt"), 0.0);
  // README: three steps up, 10 cm rise, 30 cm run, 2 m wide, from x = 1.5 m, then a landing.
  for (double y : {-0.95, -0.5, 0.0, 0.5, 0.95}) {
    EXPECT_NEAR(map.height(1.45, y), 0.0, 1e-9);
    for (int step = 1; step <= 3; ++step) {
      const double start = 1.5 + (step - 1) * 0.3;
      for (double x = start + 0.01; x < start + 0.3; x += 0.02)
        EXPECT_NEAR(map.height(x, y), 0.1 * step, kHalfCell) << "step " << step << " x " << x;
    }
    for (double x = 2.5; x < 5.9; x += 0.25) EXPECT_NEAR(map.height(x, y), 0.3, kHalfCell) << x;
  }
  EXPECT_NEAR(map.height(2.5, 1.1), 0.0, 1e-9);  // beside the stairs
  EXPECT_NEAR(map.height(1.799, 0.0), 0.1, kHalfCell);
  EXPECT_NEAR(map.height(1.801, 0.0), 0.2, kHalfCell);
}

TEST(HeightMap, EveryColumnOfAGeneratedMapIsItsHeightFunction) {
  // Rough patches at random heights: many leaf sizes after pruning, every column different.
  const maps::HeightFunction h = maps::rough(0.12, 0.1, 3);
  const maps::MapExtent extent{-0.5, 1.1, -0.7, 0.5};
  for (double res : {0.02, 0.05}) {
    const auto tree = maps::makeTerrainMap(h, res, extent);
    const HeightMap map = HeightMap::fromOcTree(*tree, -1.0);
    EXPECT_EQ(map.knownColumns(), map.columnsX() * map.columnsY());
    EXPECT_EQ(map.columnsX(), static_cast<std::size_t>(std::lround(1.6 / res)));
    EXPECT_EQ(map.columnsY(), static_cast<std::size_t>(std::lround(1.2 / res)));
    int checked = 0;
    for (double y = extent.yMin + res / 2; y < extent.yMax; y += res)
      for (double x = extent.xMin + res / 2; x < extent.xMax; x += res, ++checked)
        ASSERT_NEAR(map.height(x, y), quantised(h(x, y), res), 1e-6) << x << ", " << y;
    EXPECT_EQ(checked, static_cast<int>(map.columnsX() * map.columnsY()));
  }
}

TEST(HeightMap, TheGroundDefaultOffTheMapAndWhereNothingIsKnown) {
  const HeightMap map = HeightMap::fromFile(exampleMap("lab-stage.bt"), 0.37);
  EXPECT_NEAR(map.height(0.0, 0.0), 0.0, 1e-9);  // known floor: the map, not the default
  for (const auto& [x, y] :
       {std::pair{-2.01, 0.0}, {6.01, 0.0}, {0.0, 2.01}, {0.0, -2.01}, {100.0, -100.0}})
    EXPECT_EQ(map.height(x, y), 0.37) << x << ", " << y;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(map.height(nan, 0.0), 0.37);
  EXPECT_EQ(map.height(0.0, nan), 0.37);

  // Two blocks with unknown space between them (inside the grid's extent).
  octomap::OcTree tree(0.05);
  for (double x : {0.025, 0.975})
    for (double y = 0.025; y < 0.5; y += 0.05) tree.updateNode(octomap::point3d(x, y, 0.225), true);
  tree.updateNode(octomap::point3d(0.525, 0.025, 0.625), false);  // free: still no ground there
  const HeightMap blocks = HeightMap::fromOcTree(tree, -0.4);
  EXPECT_EQ(blocks.columnsX(), 20u);
  EXPECT_EQ(blocks.knownColumns(), 20u);
  EXPECT_NEAR(blocks.height(0.01, 0.2), 0.25, 1e-6);
  EXPECT_NEAR(blocks.height(0.99, 0.2), 0.25, 1e-6);
  EXPECT_EQ(blocks.height(0.5, 0.2), -0.4);
  EXPECT_EQ(blocks.height(0.53, 0.01), -0.4);
  EXPECT_TRUE(blocks.known(0.01, 0.2));
  EXPECT_FALSE(blocks.known(0.5, 0.2));   // unknown inside the grid
  EXPECT_FALSE(blocks.known(0.53, 0.01));  // free only: observed, but no ground seen
  EXPECT_FALSE(blocks.known(5.0, 0.2));   // off the grid

  EXPECT_FALSE(blocks.floorKnown());

  const HeightMap flat(0.2);  // no map: a flat floor the profile says is there, known
  EXPECT_TRUE(flat.floorKnown());
  EXPECT_TRUE(flat.known(3.0, -4.0));
  EXPECT_EQ(flat.height(3.0, -4.0), 0.2);
  EXPECT_EQ(flat.slope(3.0, -4.0).dzdx, 0.0);
  EXPECT_EQ(flat.normal(3.0, -4.0)[2], 1.0);
}

TEST(HeightMap, OneColumnHolesBetweenObservationsThatAgreeAreFilled) {
  // A floor at 0 from x = 0 to 1 m and a 0.2 m box from 1 to 1.5 m (5 cm cells), observed as
  // a sweeping lidar leaves it: every third column along x never hit.
  constexpr double r = 0.05;
  octomap::OcTree tree(r);
  const auto column = [](int i) { return (i + 0.5) * r; };
  for (int i = 0; i < 30; ++i) {
    // A hole two columns wide in the floor as well: no ground at i = 6 (nor 7).
    if (i % 3 == 1 || i == 6) continue;
    for (int j = 0; j < 10; ++j) {
      tree.updateNode(octomap::point3d(column(i), column(j), -0.025), true);
      if (i >= 20) tree.updateNode(octomap::point3d(column(i), column(j), 0.175), true);
    }
  }
  const HeightMap map = HeightMap::fromOcTree(tree, -1.0);
  ASSERT_EQ(map.columnsX(), 30u);  // the grid's first column is i = 0

  // On the floor and on the box, the lines between observed columns read as they do.
  for (int i : {1, 4, 10, 13, 16, 22, 25, 28})
    for (double y : {0.025, 0.225, 0.475}) {  // the side columns too: a hole between two on one row
      EXPECT_TRUE(map.known(column(i), y)) << i << ", " << y;
      EXPECT_NEAR(map.height(column(i), y), i >= 20 ? 0.2 : 0.0, 1e-9) << i << ", " << y;
    }
  EXPECT_EQ(map.knownColumns(), 190u);  // filled columns are not observed ones
  // Two columns wide: not a line between observations.
  EXPECT_FALSE(map.known(column(6), 0.225));
  EXPECT_FALSE(map.known(column(7), 0.225));
  EXPECT_EQ(map.height(column(7), 0.225), -1.0);
  // Between the floor (i = 18) and the box (i = 20): an edge, not a surface; unknown.
  EXPECT_FALSE(map.known(column(19), 0.225));
  EXPECT_EQ(map.height(column(19), 0.225), -1.0);
  // Never past the observed area: off the grid stays the default.
  EXPECT_FALSE(map.known(-0.025, 0.225));
  EXPECT_FALSE(map.known(column(10), -0.025));
  // The slope across a filled line is the floor's: none.
  EXPECT_EQ(map.slope(column(13), 0.225).dzdx, 0.0);
}

TEST(HeightMap, SlopeOfARampAndOfAStepEdge) {
  // A 45° ramp in x up to 0.5 m, 2 cm cells: one cell of rise per cell of run. (Raised by a
  // quarter cell so that no column's height falls on a cell centre, where rounding decides.)
  const auto tree =
      maps::makeTerrainMap([](double x, double) { return std::clamp(x, 0.0, 0.5) + kRes / 4; },
                           kRes, {-0.5, 1.0, -0.3, 0.3});
  const HeightMap ramp = HeightMap::fromOcTree(*tree, 0.0);
  for (double x = 0.05; x < 0.45; x += 0.04) {
    const Slope s = ramp.slope(x, 0.1);
    EXPECT_NEAR(s.dzdx, 1.0, 1e-6) << x;
    EXPECT_NEAR(s.dzdy, 0.0, 1e-6) << x;
    const auto n = ramp.normal(x, 0.1);
    EXPECT_NEAR(n[0], -std::sqrt(0.5), 1e-6);
    EXPECT_NEAR(n[2], std::sqrt(0.5), 1e-6);
  }
  EXPECT_NEAR(ramp.slope(0.8, 0.0).dzdx, 0.0, 1e-9);
  const HeightMap stage = HeightMap::fromFile(exampleMap("lab-stage.bt"), 0.0);
  EXPECT_GT(stage.slope(1.5, 0.0).dzdx, 3.0);  // 14–16 cm over two cells: an edge
  EXPECT_NEAR(stage.slope(2.5, 0.0).dzdx, 0.0, 1e-9);
}

TEST(HeightMap, QueriesAllocateNothing) {
  const HeightMap map = HeightMap::fromFile(exampleMap("lab-steps.bt"), 0.0);
  double sum = 0;
  EXPECT_EQ(test::allocationsIn([&] {
              for (double x = -3; x < 7; x += 0.01) {
                sum += map.height(x, 0.3);
                sum += map.slope(x, 0.3).dzdx + map.normal(x, 0.3)[2];
              }
            }),
            0);
  EXPECT_GT(sum, 0.0);
}

std::string path(const std::string& name) {
  return ::testing::TempDir() + name;
}

/// Why fromFile refuses `file` ("" if it does not).
std::string errorOf(const std::string& file) {
  std::string what;
  try {
    HeightMap::fromFile(file, 0.0);
  } catch (const MapError& e) {
    what = e.what();
  }
  return what;
}

/// Why fromFile refuses the temporary file `name`, once the message has named it ("map
/// <path>: "); the whole message if it does not.
std::string reason(const std::string& name) {
  const std::string prefix = "map " + path(name) + ": ", what = errorOf(path(name));
  return what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
}

TEST(MapFiles, EveryFailureNamesTheFileAndTheReason) {
  EXPECT_EQ(errorOf("/no/such/map.bt"),
            "map /no/such/map.bt: cannot read it: No such file or directory");
  std::ofstream(path("text.bt")) << "not a map\n";
  EXPECT_EQ(reason("text.bt"), "not a readable OctoMap binary (.bt) file");
  std::ofstream(path("text.ot")) << "not a map\n";
  EXPECT_EQ(reason("text.ot"), "not an OctoMap OcTree (.ot) file");
  octomap::ColorOcTree color(0.1);
  color.updateNode(octomap::point3d(0, 0, 0), true);
  ASSERT_TRUE(color.write(path("color.ot")));
  EXPECT_EQ(reason("color.ot"), "not an OctoMap OcTree (.ot) file (it holds a ColorOcTree)");
  std::ofstream(path("map.png")) << "x";
  EXPECT_EQ(reason("map.png"), "expected an OctoMap file (.bt or .ot)");
  ASSERT_TRUE(octomap::OcTree(0.1).writeBinaryConst(path("empty.bt")));
  EXPECT_EQ(reason("empty.bt"), "the map has no occupied cells");
  octomap::OcTree freeOnly(0.1);
  freeOnly.updateNode(octomap::point3d(0, 0, 0), false);
  ASSERT_TRUE(freeOnly.write(path("free.ot")));
  EXPECT_EQ(reason("free.ot"), "the map has no occupied cells");
}

TEST(MapFiles, BinaryAndFullFilesOfOneMapGiveTheSameHeights) {
  const auto tree =
      maps::makeTerrainMap(maps::steps(2, 0.06, 0.2, 0.1, 0.4), 0.02, {-0.2, 0.8, -0.3, 0.3});
  std::string error;
  ASSERT_TRUE(maps::writeTerrainMap(*tree, path("two.bt"), error)) << error;
  ASSERT_TRUE(maps::writeTerrainMap(*tree, path("two.ot"), error)) << error;
  const HeightMap bt = HeightMap::fromFile(path("two.bt"), 0.0);
  const HeightMap ot = HeightMap::fromFile(path("two.ot"), 0.0);
  const HeightMap direct = HeightMap::fromOcTree(*tree, 0.0);
  for (double x = -0.19; x < 0.8; x += 0.02) {
    EXPECT_NEAR(direct.height(x, 0.0),
                quantised(x < 0.1   ? 0.0
                          : x < 0.3 ? 0.06
                                    : 0.12,
                          0.02),
                1e-6)
        << x;
    EXPECT_EQ(bt.height(x, 0.0), direct.height(x, 0.0)) << x;
    EXPECT_EQ(ot.height(x, 0.0), direct.height(x, 0.0)) << x;
  }
}

/// A room: a floor (top at z = 0) over [-2, 2] × [-1.5, 1.5] and a ceiling slab 10 cm thick
/// from 2.5 m, over all of it but a strip at x > 1.5 (a doorway's height unseen), at `res`.
std::unique_ptr<octomap::OcTree> room(double res) {
  auto tree = std::make_unique<octomap::OcTree>(res);
  for (double x = -2 + res / 2; x < 2; x += res)
    for (double y = -1.5 + res / 2; y < 1.5; y += res) {
      tree->updateNode(octomap::point3d(x, y, -res / 2), true);
      if (x < 1.5)
        for (double z = 2.5 + res / 2; z < 2.6; z += res) tree->updateNode(octomap::point3d(x, y, z), true);
    }
  tree->updateInnerOccupancy();
  tree->prune();
  return tree;
}

TEST(GroundRule, ACeilingIsNotGroundTheFloorUnderItIs) {
  for (double res : {0.02, 0.05, 0.08}) {
    const auto tree = room(res);
    const HeightMap map = HeightMap::fromOcTree(*tree, 0.3);  // reference 0, clearance 0.5
    EXPECT_EQ(map.knownColumns(), map.columnsX() * map.columnsY()) << res;
    for (double x = -1.99; x < 2; x += 0.1)
      for (double y = -1.49; y < 1.5; y += 0.1) {
        ASSERT_NEAR(map.height(x, y), 0.0, 1e-9) << res << ": " << x << ", " << y;
        ASSERT_TRUE(map.known(x, y));
      }
  }
  // Without the floor the ceiling is all there is, and it is still not ground: unknown.
  octomap::OcTree ceiling(0.05);
  for (double x = 0.025; x < 1; x += 0.05) ceiling.updateNode(octomap::point3d(x, 0.025, 2.525), true);
  const HeightMap none = HeightMap::fromOcTree(ceiling, 0.3);
  EXPECT_EQ(none.knownColumns(), 0u);
  EXPECT_EQ(none.height(0.5, 0.0), 0.3);
  EXPECT_FALSE(none.known(0.5, 0.0));
}

TEST(GroundRule, ATableIsNotGroundABoxIsAndAWallIsAnEdge) {
  const double res = 0.05;
  octomap::OcTree tree(res);
  for (double x = res / 2; x < 2; x += res)
    for (double y = res / 2; y < 0.5; y += res) {
      tree.updateNode(octomap::point3d(x, y, -res / 2), true);                 // floor
      if (x > 0.5 && x < 1.0) tree.updateNode(octomap::point3d(x, y, 0.725), true);  // table top
      if (x > 1.0 && x < 1.2)                                                  // a 20 cm box
        for (double z = res / 2; z < 0.2; z += res) tree.updateNode(octomap::point3d(x, y, z), true);
      if (x > 1.5 && x < 1.6)                                                  // a 2 m wall
        for (double z = res / 2; z < 2.0; z += res) tree.updateNode(octomap::point3d(x, y, z), true);
    }
  const HeightMap map = HeightMap::fromOcTree(tree, 0.0);
  EXPECT_NEAR(map.height(0.3, 0.2), 0.0, 1e-9);
  EXPECT_NEAR(map.height(0.7, 0.2), 0.0, 1e-9);   // under the table
  EXPECT_NEAR(map.height(1.1, 0.2), 0.2, 1e-9);   // on the box
  // The wall: up to the cell whose bottom is the limit (0.5 m): an edge of 0.55 m.
  EXPECT_NEAR(map.height(1.55, 0.2), 0.55, 1e-9);
  // Feet 15 cm up (on a step), the table is still not ground.
  const HeightMap high = HeightMap::fromOcTree(tree, 0.0, "", GroundRule{0.15, 0.5});
  EXPECT_NEAR(high.height(0.7, 0.2), 0.0, 1e-9);
  EXPECT_NEAR(high.height(1.55, 0.2), 0.7, 1e-9);
  // Feet at 0.3 m: the table top (bottom 0.7) is within 0.5 m and is ground.
  const HeightMap higher = HeightMap::fromOcTree(tree, 0.0, "", GroundRule{0.3, 0.5});
  EXPECT_NEAR(higher.height(0.7, 0.2), 0.75, 1e-9);
}

TEST(GroundRule, APrunedBlockCountsItsCellsUpToTheLimit) {
  // A solid cube 1.28 m high of 2 cm cells prunes into large leaves: the ground is the cell
  // holding the limit, as it would be cell by cell.
  octomap::OcTree tree(0.02);
  for (double x = 0.01; x < 1.28; x += 0.02)
    for (double y = 0.01; y < 1.28; y += 0.02)
      for (double z = 0.01; z < 1.28; z += 0.02) tree.updateNode(octomap::point3d(x, y, z), true);
  tree.updateInnerOccupancy();
  tree.prune();
  EXPECT_LT(tree.getNumLeafNodes(), 100u);
  const HeightMap map = HeightMap::fromOcTree(tree, 0.0, "", GroundRule{0.0, 0.5});
  EXPECT_NEAR(map.height(0.5, 0.5), 0.52, 1e-9);
  const HeightMap all = HeightMap::fromOcTree(tree, 0.0, "", GroundRule{0.0, 5.0});
  EXPECT_NEAR(all.height(0.5, 0.5), 1.28, 1e-9);
}

TEST(MapFiles, TruncatedCorruptAndEnormousMapsAreRefusedByName) {
  const auto tree = room(0.05);
  std::string error;
  ASSERT_TRUE(maps::writeTerrainMap(*tree, path("room.bt"), error)) << error;
  ASSERT_TRUE(maps::writeTerrainMap(*tree, path("room.ot"), error)) << error;
  for (const std::string name : {"room.bt", "room.ot"}) {
    std::ifstream in(path(name), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 200u);
    for (const double keep : {0.5, 0.9}) {
      const std::string cut = "cut-" + std::to_string(static_cast<int>(keep * 10)) + name;
      std::ofstream(path(cut), std::ios::binary) << bytes.substr(0, static_cast<std::size_t>(bytes.size() * keep));
      EXPECT_EQ(reason(cut).rfind("the file is cut short or corrupt", 0), 0u) << cut << ": " << reason(cut);
    }
    // Only a header.
    const std::string head = "head-" + name;
    std::ofstream(path(head), std::ios::binary) << bytes.substr(0, bytes.find("data\n"));
    EXPECT_NE(reason(head).find("no data in it"), std::string::npos) << reason(head);
  }
  // A .ot file named .bt and the other way round: the wrong kind, by name.
  std::filesystem::copy_file(path("room.ot"), path("ot-as.bt"), std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(reason("ot-as.bt"), "not a readable OctoMap binary (.bt) file");
  std::filesystem::copy_file(path("room.bt"), path("bt-as.ot"), std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(reason("bt-as.ot"), "not an OctoMap OcTree (.ot) file");

  // Two cells 600 m apart at 2 cm: 30 000 × 30 000 columns.
  octomap::OcTree huge(0.02);
  huge.updateNode(octomap::point3d(-300, -300, 0.01f), true);
  huge.updateNode(octomap::point3d(300, 300, 0.01f), true);
  ASSERT_TRUE(maps::writeTerrainMap(huge, path("huge.bt"), error)) << error;
  const std::string why = reason("huge.bt");
  EXPECT_EQ(why.rfind("the map's ground covers 600 m × 600 m", 0), 0u) << why;
  EXPECT_NE(why.find("too large for a height grid"), std::string::npos) << why;
}

}  // namespace
}  // namespace ballast::terrain
