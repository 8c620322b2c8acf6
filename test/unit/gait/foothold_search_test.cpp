// Footholds on terrain that is not good everywhere: the paper's foothold where toe and heel
// stand on good ground, the nearest good placement in the window where they would straddle a
// step edge or touch unknown columns, and the paper's foothold again when nothing is good.
#include <gtest/gtest.h>

#include "gait/foothold_search.hpp"
#include "test/unit/allocation_counter.hpp"

namespace ballast::gait {
namespace {

/// A 15 cm stage from x = 1.5 m, unknown columns in x ∈ [0.4, 0.5), a 30° ramp from x = 3 m.
class TestTerrain final : public TerrainQuery {
 public:
  double height(double x, double) const override {
    if (x >= 3.0) return 0.15 + 0.577 * (x - 3.0);
    return x >= 1.5 ? 0.15 : 0.0;
  }
  bool known(double x, double y) const override {
    return !(x >= 0.4 && x < 0.5) && !(unknownEverywhere && y < 5.0);
  }
  bool unknownEverywhere = false;
};

Eigen::Vector3d at(double x, double y = 0.1) { return {x, y, 0.0}; }

TEST(FootholdSearch, ThePapersFootholdWhereTheGroundIsGood) {
  const TestTerrain t;
  const FootholdSearchParameters s;
  EXPECT_EQ(footholdOffset(at(1.0), at(0.8), t, s), Eigen::Vector3d::Zero());  // floor
  EXPECT_EQ(footholdOffset(at(1.8), at(1.6), t, s), Eigen::Vector3d::Zero());  // on the stage
  EXPECT_EQ(footholdOffset(at(1.43), at(1.23), t, s), Eigen::Vector3d::Zero());  // toe by the edge
}

TEST(FootholdSearch, AFootStraddlingTheEdgeMovesBackOffIt) {
  const TestTerrain t;
  const FootholdSearchParameters s;
  const Eigen::Vector3d toe = at(1.51), heel = at(1.31);
  ASSERT_FALSE(goodPlacement(toe, heel, 0, 0, t, s));
  const Eigen::Vector3d d = footholdOffset(toe, heel, t, s);
  EXPECT_NEAR(d.x(), -0.08, 1e-9);  // the nearest: the toe's patch (6 cm) before the edge
  EXPECT_NEAR(d.y(), 0.0, 1e-9);
  EXPECT_TRUE(goodPlacement(toe, heel, d.x(), d.y(), t, s));
  // Heel just on the stage, toe on it: already good. Heel by the edge: forward onto it.
  const Eigen::Vector3d on = footholdOffset(at(1.71), at(1.51), t, s);
  EXPECT_NEAR(on.x(), 0.06, 1e-9);
}

TEST(FootholdSearch, AFootWithItsMiddleOverTheEdgeMovesOffIt) {
  // Toe 9 cm over the edge: back off it takes 16 cm (the toe's patch before the edge), forward
  // 18 cm (the heel's past it); both beyond `radius`, within the 20 cm foot's window.
  const TestTerrain t;
  const FootholdSearchParameters s;
  const Eigen::Vector3d toe = at(1.59), heel = at(1.39);
  ASSERT_LT(s.radius, 0.16);
  EXPECT_NEAR(searchRadius(toe, heel, s), 0.1 + s.patch + s.step, 1e-12);
  const Eigen::Vector3d d = footholdOffset(toe, heel, t, s);
  EXPECT_NEAR(d.x(), -0.16, 1e-9);
  EXPECT_NEAR(d.y(), 0.0, 1e-9);
  EXPECT_TRUE(goodPlacement(toe, heel, d.x(), d.y(), t, s));
  // The edge under the foot's middle: off it either way within the window.
  const Eigen::Vector3d m = footholdOffset(at(1.61), at(1.41), t, s);
  EXPECT_TRUE(goodPlacement(at(1.61), at(1.41), m.x(), m.y(), t, s));
  EXPECT_NE(m, Eigen::Vector3d::Zero());
}

TEST(FootholdSearch, UnknownColumnsAreAvoidedAndNothingGoodKeepsThePapers) {
  TestTerrain t;
  const FootholdSearchParameters s;
  const Eigen::Vector3d d = footholdOffset(at(0.45), at(0.25), t, s);
  EXPECT_NE(d, Eigen::Vector3d::Zero());
  EXPECT_TRUE(goodPlacement(at(0.45), at(0.25), d.x(), d.y(), t, s));
  EXPECT_LE(d.norm(), searchRadius(at(0.45), at(0.25), s) + 1e-9);
  t.unknownEverywhere = true;
  EXPECT_EQ(footholdOffset(at(1.0), at(0.8), t, s), Eigen::Vector3d::Zero());
  FootholdSearchParameters off = s;
  off.enabled = false;
  EXPECT_EQ(footholdOffset(at(1.51), at(1.31), TestTerrain{}, off), Eigen::Vector3d::Zero());
}

TEST(FootholdSearch, ARampWithinTheSlopeIsGoodASteeperOneIsNot) {
  const TestTerrain t;
  FootholdSearchParameters s;
  s.maxSlope = 0.7;  // 35°: the 30° ramp is good
  EXPECT_TRUE(goodPlacement(at(3.5), at(3.3), 0, 0, t, s));
  s.maxSlope = 0.35;  // 19°: it is not, anywhere in the window
  EXPECT_FALSE(goodPlacement(at(3.5), at(3.3), 0, 0, t, s));
  EXPECT_EQ(footholdOffset(at(3.5), at(3.3), t, s), Eigen::Vector3d::Zero());
}

/// A 4 cm step at x = 1 m: less than toe and heel may differ on a slope, but an edge.
class LowStep final : public TerrainQuery {
 public:
  double height(double x, double) const override { return x >= 1.0 ? 0.04 : 0.0; }
};

TEST(FootholdSearch, ASoleAcrossALowStepIsNotGood) {
  const FootholdSearchParameters s;
  EXPECT_FALSE(goodPlacement(at(1.1), at(0.9), 0, 0, LowStep{}, s));  // toe up, heel down
  EXPECT_TRUE(goodPlacement(at(1.3), at(1.1), 0, 0, LowStep{}, s));   // both on it
}

/// The same step as a lidar map can hold it: the column in front of the edge half as high
/// (face hits), so that no two neighbouring samples differ by more than edgeTolerance.
class LowStepWithAFace final : public TerrainQuery {
 public:
  double height(double x, double) const override { return x >= 1.0 ? 0.04 : x >= 0.98 ? 0.02 : 0.0; }
};

/// A ramp of slope 0.3 as a 2 cm-cell map holds it: 2 cm stairs every 6.7 cm.
class QuantisedRamp final : public TerrainQuery {
 public:
  double height(double x, double) const override {
    return x < 1.0 ? 0.0 : 0.02 * std::floor(0.3 * (x - 1.0) / 0.02);
  }
};

TEST(FootholdSearch, AStepWhoseEdgeColumnHoldsPartOfItIsNoSlope) {
  const FootholdSearchParameters s;
  // Toe 5 cm past the edge, heel 15 cm before it (the placement MuJoCo's stage walk landed on).
  EXPECT_FALSE(goodPlacement(at(1.05), at(0.85), 0, 0, LowStepWithAFace{}, s));
  EXPECT_FALSE(goodPlacement(at(1.11), at(0.91), 0, 0, LowStepWithAFace{}, s));
  EXPECT_TRUE(goodPlacement(at(1.3), at(1.1), 0, 0, LowStepWithAFace{}, s));  // both on it
  // A ramp within maxSlope stays good wherever the sole's samples fall on its stairs.
  for (double toe = 1.3; toe < 1.5; toe += 0.005)
    EXPECT_TRUE(goodPlacement(at(toe), at(toe - 0.2), 0, 0, QuantisedRamp{}, s)) << toe;
}

/// The 4 cm step as a 2 cm-cell map holds it, heights interpolated between the cells' centres:
/// the rise spans x 0.99-1.01, and x = 1.0 reads 0.02.
class InterpolatedStep final : public TerrainQuery {
 public:
  double height(double x, double) const override {
    return 0.04 * std::clamp((x - 0.99) / 0.02, 0.0, 1.0);
  }
};

TEST(FootholdSearch, APointOnAnInterpolatedEdgeIsNotGood) {
  const FootholdSearchParameters s;
  // The heel on the edge reads 0.02, within edgeTolerance of both sides of its patch and of the
  // toe (MuJoCo's 5 cm stage walk planned a heel at 1.500 there and fell).
  EXPECT_FALSE(goodPlacement(at(1.2), at(1.0), 0, 0, InterpolatedStep{}, s));
  EXPECT_FALSE(goodPlacement(at(1.0), at(0.8), 0, 0, InterpolatedStep{}, s));  // a toe on it
  const Eigen::Vector3d d = footholdOffset(at(1.2), at(1.0), InterpolatedStep{}, s);
  // Forward: the heel's patch off the rise. 6 cm is good (the patch's back end at 1.00 reads
  // 0.02, within edgeTolerance) but the sole would not rest on its heel there (2 cm below the
  // sole's line, supported()); 8 cm clears the rise.
  EXPECT_NEAR(d.x(), 0.08, 1e-9);
  EXPECT_TRUE(goodPlacement(at(1.2), at(1.0), d.x(), d.y(), InterpolatedStep{}, s));
  EXPECT_TRUE(goodPlacement(at(1.2), at(1.0), 0.06, 0, InterpolatedStep{}, s));
}

/// Level patches as sim-rough's 2 cm-cell map holds them: 2 cm up to x = 1 m, the floor after.
class PatchEdge final : public TerrainQuery {
 public:
  double height(double x, double) const override { return x < 1.0 ? 0.02 : 0.0; }
};

TEST(FootholdSearch, ASoleAcrossAPatchEdgeMovesToWhereItRestsOnToeAndHeel) {
  const FootholdSearchParameters s;
  // Heel at 0.93 on the 2 cm patch, toe at 1.13 on the floor: within edgeTolerance and
  // maxSlope, good, but the sole's line from 0.02 at the heel to 0 at the toe runs 0.007 below
  // the patch's corner at x = 1 (0.02 − 0.1 × 0.07) and 0.006 above the floor 6 cm behind the
  // toe: the sole would pivot on the corner (Simbody's 30 s walk on sim-rough fell so).
  const Eigen::Vector3d toe = at(1.13), heel = at(0.93);
  ASSERT_TRUE(goodPlacement(toe, heel, 0, 0, PatchEdge{}, s));
  EXPECT_FALSE(supported(toe, heel, 0, 0, PatchEdge{}, s));
  // The nearest supported placement: forward until the heel's patch (6 cm behind it) clears the
  // edge, heel 0.93 + d − 0.06 >= 1.0, d = 0.14 on the 2 cm grid; back would take the toe's
  // patch before the edge, 1.13 + d + 0.06 < 1.0, d <= −0.20, beyond the 18 cm window.
  const Eigen::Vector3d d = footholdOffset(toe, heel, PatchEdge{}, s);
  EXPECT_NEAR(d.x(), 0.14, 1e-9);
  EXPECT_NEAR(d.y(), 0.0, 1e-9);
  EXPECT_TRUE(supported(toe, heel, d.x(), d.y(), PatchEdge{}, s));
  // Both points on one patch: supported where they are; the floor beyond a heel's patch lower
  // than the sole's line is no harm.
  EXPECT_TRUE(supported(at(0.9), at(0.7), 0, 0, PatchEdge{}, s));
  EXPECT_TRUE(supported(at(1.3), at(1.1), 0, 0, PatchEdge{}, s));
  EXPECT_FALSE(supported(at(1.3), at(1.05), 0, 0, PatchEdge{}, s));  // heel's patch on the edge
  EXPECT_EQ(footholdOffset(at(1.3), at(1.1), PatchEdge{}, s), Eigen::Vector3d::Zero());
  // A ramp's stairs: never supported; the paper's foothold stays where it is good.
  EXPECT_EQ(footholdOffset(at(1.4), at(1.2), QuantisedRamp{}, s), Eigen::Vector3d::Zero());
}

TEST(FootholdSearch, AllocatesNothing) {
  const TestTerrain t;
  const FootholdSearchParameters s;
  Eigen::Vector3d d;
  EXPECT_EQ(test::allocationsIn([&] { d = footholdOffset(at(1.51), at(1.31), t, s); }), 0);
  EXPECT_NE(d, Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace ballast::gait
