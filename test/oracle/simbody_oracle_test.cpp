// Our rigid-body algorithms against Simbody, at many random states, on the humanoid and on the
// generator's other robots as vendors write them (test/CMakeLists.txt: hips in another order,
// 5-joint legs, a 29-joint robot with its waist and a wrist per arm locked, a 35 kg one; each
// with CRLF, a mimic finger per hand and a massless camera on a joint, which the loader locks).
//
// Simbody's system is built from the URDF by plugins/simbody (urdfdom directly, not our loader).
// Its coordinates differ from ours only at the base: Simbody's Free mobilizer has
// u_b = [ω; v] with world axes, ours v_b = [v; ω] in the base frame (model.hpp). With u = T v
// (T built below) and u̇ = T v̇ + Ṫ v, where Ṫ v = [0; R (ω_b × v_b)]:
//   M = Tᵀ M_sb T,   τ(q, v, a) = Tᵀ residual_sb(u̇ = T a + Ṫ v),   J = J_sb T,
//   J̇ v = J̇_sb u + J_sb Ṫ v,   and CoM and centroidal momentum compare directly.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "test/unit/test_support.hpp"
#include "urdf_multibody.hpp"

namespace ballast::test {
namespace {

using model::Data;
using model::Mat3;
using model::MatX;
using model::Model;
using model::Vec3;
using model::VecX;

constexpr double kRelTol = 1e-8;
constexpr int kStates = 120;
const char* const kContacts[] = {"left_toe", "left_heel", "right_toe", "right_heel"};

Eigen::MatrixXd toEigen(const SimTK::Matrix& m) {
  Eigen::MatrixXd out(m.nrow(), m.ncol());
  for (int r = 0; r < m.nrow(); ++r)
    for (int c = 0; c < m.ncol(); ++c) out(r, c) = m(r, c);
  return out;
}
Eigen::VectorXd toEigen(const SimTK::Vector& v) {
  Eigen::VectorXd out(v.size());
  for (int i = 0; i < v.size(); ++i) out[i] = v[i];
  return out;
}
Vec3<double> toEigen(const SimTK::Vec3& v) { return {v[0], v[1], v[2]}; }
SimTK::Vec3 toSimTK(const Vec3<double>& v) { return {v[0], v[1], v[2]}; }

double worstRelativeError = 0.0;  // reported when the suite ends

/// ‖a − b‖ ≤ tol·max(‖b‖, 1): relative for entries of order one and above.
template <typename A, typename B>
::testing::AssertionResult closeTo(const A& a, const B& b, double tol = kRelTol) {
  const double err = (a - b).norm();
  const double scale = std::max(b.norm(), 1.0);
  worstRelativeError = std::max(worstRelativeError, err / scale);
  if (err <= tol * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "error " << err << " > " << tol << " * " << scale;
}

/// A robot: its URDF and the joints the profile locks.
struct Robot {
  const char* name;
  std::string urdf;
  std::map<std::string, double> locked;
};

std::string generated(const char* name) { return std::string(TEST_URDF_DIR) + "/" + name + ".urdf"; }

class SimbodyOracle : public ::testing::TestWithParam<Robot> {
 protected:
  static void TearDownTestSuite() {
    std::printf("worst relative error against Simbody: %.2e\n", worstRelativeError);
  }
  void SetUp() override {
    model::UrdfOptions options;
    options.locked = GetParam().locked;
    model_ = model::loadUrdfFile(GetParam().urdf, options);
    // Simbody welds what the daemon tells it to: every joint the model holds (Config::joints).
    std::map<std::string, double> welded;
    for (const model::LockedJoint& j : model_.lockedJoints) welded[j.name] = j.position;
    mb_ = simbody::buildUrdfMultibody(GetParam().urdf, {}, welded);
    state_ = mb_->system.realizeTopology();
    mb_->system.realizeModel(state_);
  }

  /// Puts (q, v) into the Simbody state and returns T with u = T v.
  MatX<double> setState(const Model& model, const VecX<double>& q, const VecX<double>& v) {
    const Mat3<double> R = model::quaternionToRotation<double>(q.segment<4>(3));
    const auto& base = mb_->body(mb_->base);
    const SimTK::Quaternion quat(q[6], q[3], q[4], q[5]);
    base.setQToFitTransform(state_, SimTK::Transform(SimTK::Rotation(quat), toSimTK(q.head<3>())));
    base.setUToFitVelocity(state_, SimTK::SpatialVec(toSimTK(R * v.segment<3>(3)),
                                                     toSimTK(R * v.head<3>())));
    MatX<double> T = MatX<double>::Zero(model.nv, model.nv);
    const int ub = static_cast<int>(base.getFirstUIndex(state_));
    T.block<3, 3>(ub, 3) = R;
    T.block<3, 3>(ub + 3, 0) = R;
    for (int j = 0; j < model.nj(); ++j) {
      const auto& body = mb_->body(mb_->jointBody.at(model.jointName[j + 1]));
      body.setOneQ(state_, 0, q[Model::qIndexOfJoint(j)]);
      body.setOneU(state_, 0, v[Model::vIndexOfJoint(j)]);
      T(static_cast<int>(body.getFirstUIndex(state_)), Model::vIndexOfJoint(j)) = 1.0;
    }
    mb_->system.realize(state_, SimTK::Stage::Velocity);
    return T;
  }

  /// Ṫ v in Simbody's u coordinates.
  VecX<double> TdotV(const Model& model, const VecX<double>& q, const VecX<double>& v) const {
    const Mat3<double> R = model::quaternionToRotation<double>(q.segment<4>(3));
    VecX<double> out = VecX<double>::Zero(model.nv);
    const int ub = static_cast<int>(mb_->body(mb_->base).getFirstUIndex(state_));
    out.segment<3>(ub + 3) = R * v.segment<3>(3).cross(v.head<3>());
    return out;
  }

  /// Gravity as Simbody applied body forces.
  SimTK::Vector_<SimTK::SpatialVec> gravityForces(const Vec3<double>& g) const {
    SimTK::Vector_<SimTK::SpatialVec> F(mb_->matter.getNumBodies());
    F.setToZero();
    for (SimTK::MobilizedBodyIndex b(1); b < mb_->matter.getNumBodies(); ++b) {
      const auto& body = mb_->body(b);
      const double m = body.getBodyMass(state_);
      const SimTK::Vec3 comInG =
          body.getBodyRotation(state_) * body.getBodyMassCenterStation(state_);
      F[b] = SimTK::SpatialVec(comInG % (m * toSimTK(g)), m * toSimTK(g));
    }
    return F;
  }

  VecX<double> residual(const VecX<double>& udot, const Vec3<double>& g) const {
    SimTK::Vector knownUdot(static_cast<int>(udot.size()));
    for (int i = 0; i < udot.size(); ++i) knownUdot[i] = udot[i];
    SimTK::Vector r;
    mb_->matter.calcResidualForceIgnoringConstraints(state_, SimTK::Vector(), gravityForces(g),
                                                     knownUdot, r);
    return toEigen(r);
  }

  Model model_;
  std::unique_ptr<simbody::UrdfMultibody> mb_;
  SimTK::State state_;
};

TEST_P(SimbodyOracle, SameJointsInTheSameOrder) {
  const Model& model = model_;
  ASSERT_EQ(static_cast<int>(mb_->jointNames.size()), model.nj());
  for (int j = 0; j < model.nj(); ++j) EXPECT_EQ(mb_->jointNames[j], model.jointName[j + 1]);
  EXPECT_EQ(mb_->system.realizeTopology().getNU(), model.nv);
}

TEST_P(SimbodyOracle, MassMatrixNonlinearEffectsAndInverseDynamics) {
  const Model& model = model_;
  Data<double> data(model);
  std::mt19937 rng(7);
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(model, rng);
    const MatX<double> T = setState(model, s.q, s.v);
    SCOPED_TRACE("state " + std::to_string(k));

    SimTK::Matrix Msb;
    mb_->matter.calcM(state_, Msb);
    EXPECT_TRUE(closeTo(model::crba(model, data, s.q), T.transpose() * toEigen(Msb) * T));

    const VecX<double> tdv = TdotV(model, s.q, s.v);
    EXPECT_TRUE(closeTo(model::nonLinearEffects(model, data, s.q, s.v),
                        T.transpose() * residual(tdv, model.gravity)));
    EXPECT_TRUE(closeTo(model::rnea(model, data, s.q, s.v, s.a),
                        T.transpose() * residual(T * s.a + tdv, model.gravity)));
  }
}

TEST_P(SimbodyOracle, ContactJacobiansAndBias) {
  const Model& model = model_;
  Data<double> data(model);
  std::mt19937 rng(11);
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(model, rng);
    const MatX<double> T = setState(model, s.q, s.v);
    const VecX<double> tdv = TdotV(model, s.q, s.v);
    model::forwardKinematicsBias(model, data, s.q, s.v);
    SCOPED_TRACE("state " + std::to_string(k));
    for (const char* name : kContacts) {
      SCOPED_TRACE(name);
      const auto& lf = mb_->linkFrame.at(name);
      SimTK::Matrix Jsb;
      mb_->matter.calcStationJacobian(state_, lf.body, lf.inBody.p(), Jsb);
      model::Mat3X<double> J(3, model.nv);
      const int frame = model.frameId(name);
      model::frameJacobian(model, data, frame, J);
      EXPECT_TRUE(closeTo(J, toEigen(Jsb) * T));

      const Vec3<double> biasSb =
          toEigen(mb_->matter.calcBiasForStationJacobian(state_, lf.body, lf.inBody.p())) +
          toEigen(Jsb) * tdv;
      EXPECT_TRUE(closeTo(model::frameClassicalAcceleration(model, data, frame).linear, biasSb));
      // Position too: the station in Ground.
      const SimTK::Vec3 pSb = mb_->body(lf.body).findStationLocationInGround(state_, lf.inBody.p());
      EXPECT_TRUE(closeTo(model::framePlacement(model, data, frame).p, toEigen(pSb)));
    }
  }
}

TEST_P(SimbodyOracle, FootFrameJacobiansWithAngularRows) {
  const Model& model = model_;
  Data<double> data(model);
  std::mt19937 rng(13);
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(model, rng);
    const MatX<double> T = setState(model, s.q, s.v);
    model::forwardKinematics(model, data, s.q);
    for (const char* name : {"left_foot", "right_hand", "pelvis", "imu"}) {
      SCOPED_TRACE(name);
      const auto& lf = mb_->linkFrame.at(name);
      SimTK::Matrix JFsb;  // rows [ω; v]
      mb_->matter.calcFrameJacobian(state_, lf.body, lf.inBody.p(), JFsb);
      Eigen::MatrixXd ref = toEigen(JFsb) * T;
      Eigen::MatrixXd swapped(6, model.nv);
      swapped << ref.bottomRows(3), ref.topRows(3);
      model::Mat6X<double> J(6, model.nv);
      model::frameJacobian(model, data, model.frameId(name), J);
      EXPECT_TRUE(closeTo(J, swapped));
    }
  }
}

TEST_P(SimbodyOracle, CenterOfMassAndCentroidalMomentum) {
  const Model& model = model_;
  Data<double> data(model);
  std::mt19937 rng(17);
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(model, rng);
    setState(model, s.q, s.v);
    SCOPED_TRACE("state " + std::to_string(k));
    EXPECT_TRUE(closeTo(model::centerOfMass(model, data, s.q),
                        toEigen(mb_->matter.calcSystemMassCenterLocationInGround(state_))));
    EXPECT_NEAR(data.mass, mb_->matter.calcSystemMass(state_), 1e-12);

    model::ccrba(model, data, s.q, s.v);
    const SimTK::SpatialVec h = mb_->matter.calcSystemCentralMomentum(state_);  // [angular; linear]
    model::Vec6<double> ref;
    ref << toEigen(h[1]), toEigen(h[0]);
    EXPECT_TRUE(closeTo(data.hg, ref));
    EXPECT_TRUE(closeTo(model::Vec6<double>(data.Ag * s.v), ref));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Robots, SimbodyOracle,
    ::testing::Values(
        Robot{"humanoid", humanoidUrdf(), {}},
        Robot{"hips_pitch_roll_yaw", generated("hips_pitch_roll_yaw"), {}},
        Robot{"legs_of_5", generated("legs_of_5"), {}},
        Robot{"joints_29", generated("joints_29"),
              {{"waist_yaw", 0.0}, {"waist_roll", 0.0}, {"waist_pitch", 0.1},
               {"left_wrist_yaw", 0.0}, {"right_wrist_yaw", 0.0}}},
        Robot{"mass_35", generated("mass_35"), {}}),
    [](const ::testing::TestParamInfo<Robot>& info) { return std::string(info.param.name); });

TEST(SimbodyOracleRobots, TheGeneratedRobotsAreWhatTheirOptionsSay) {
  // So that the suite above compares what it claims to: each variant's joints as generated, the
  // mimic fingers and the cameras locked by the loader, the profile's locks on top.
  auto load = [](const char* name, std::map<std::string, double> locked = {}) {
    model::UrdfOptions options;
    options.locked = std::move(locked);
    return model::loadUrdfFile(generated(name), options);
  };
  const Model pry = load("hips_pitch_roll_yaw");
  EXPECT_EQ(pry.nj(), 24);
  EXPECT_EQ(pry.jointName[1], "left_hip_pitch");
  EXPECT_EQ(pry.jointName[3], "left_hip_yaw");
  EXPECT_EQ(pry.jointName[5], "left_ankle_roll");
  EXPECT_EQ(pry.lockedJoints.size(), 3u);  // two fingers, the camera
  EXPECT_EQ(load("legs_of_5").nj(), 22);
  const Model all29 = load("joints_29");
  EXPECT_EQ(all29.nj(), 29);
  const Model locked29 = load("joints_29", {{"waist_yaw", 0.0}, {"waist_roll", 0.0},
                                            {"waist_pitch", 0.1}, {"left_wrist_yaw", 0.0},
                                            {"right_wrist_yaw", 0.0}});
  EXPECT_EQ(locked29.nj(), 24);
  EXPECT_EQ(locked29.lockedJoints.size(), 8u);
  EXPECT_NEAR(load("mass_35").totalMass(), 35.0, 1e-3);
}

}  // namespace
}  // namespace ballast::test
