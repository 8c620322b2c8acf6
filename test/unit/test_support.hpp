// Shared fixtures for the tests: the robot, random states, finite differences.
#pragma once

#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "model/algorithms.hpp"

namespace ballast::test {

/// A file of the source tree (man/ballastd.8), whole; empty if it is missing.
inline std::string sourceFile(const std::string& relative) {
  std::ifstream in(std::string(BALLAST_SOURCE_DIR) + "/" + relative);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline std::string humanoidUrdf() { return std::string(BALLAST_SOURCE_DIR) + "/urdf/humanoid.urdf"; }

inline const model::Model& humanoid() {
  static const model::Model m = model::loadUrdfFile(humanoidUrdf());
  return m;
}

/// Random configuration, velocity and acceleration with realistic magnitudes.
struct RandomState {
  model::VecX<double> q, v, a;
};

inline RandomState randomState(const model::Model& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  RandomState s;
  s.q = model::randomConfiguration(model, rng);
  s.v = model::VecX<double>::NullaryExpr(model.nv, [&] { return 2.0 * u(rng); });
  s.a = model::VecX<double>::NullaryExpr(model.nv, [&] { return 5.0 * u(rng); });
  return s;
}

/// The humanoid standing on flat ground (z = 0): knees bent, feet flat, arms hanging.
inline model::VecX<double> standingConfiguration(const model::Model& m, double hipPitch = -0.4,
                                                 double knee = 0.8, double anklePitch = -0.4) {
  model::VecX<double> q = model::neutralConfiguration(m);
  for (const char* side : {"left_", "right_"}) {
    q[model::Model::qIndexOfJoint(m.jointId(std::string(side) + "hip_pitch"))] = hipPitch;
    q[model::Model::qIndexOfJoint(m.jointId(std::string(side) + "knee"))] = knee;
    q[model::Model::qIndexOfJoint(m.jointId(std::string(side) + "ankle_pitch"))] = anklePitch;
  }
  model::Data<double> d(m);
  model::forwardKinematics(m, d, q);
  double lowest = 1e9;
  for (const char* f : {"left_toe", "left_heel", "right_toe", "right_heel"})
    lowest = std::min(lowest, model::framePlacement(m, d, m.frameId(f)).p.z());
  q[2] = -lowest;
  return q;
}

/// Central difference of f along t = 0 (f returns an Eigen vector).
template <typename F>
auto centralDifference(F&& f, double h = 1e-6) {
  return ((f(h) - f(-h)) / (2.0 * h)).eval();
}

}  // namespace ballast::test
