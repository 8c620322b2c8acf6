// State estimator speed (issue 7). It runs every control tick, before the controller: goal well
// under 50 µs per update. The paper runs its Kalman filter at about 800 Hz alongside the rest.
// Inputs: a synthetic walk (test/unit/estimation/synthetic_walk.hpp) with sensor noise, so the
// ticks go through stance, swing, touch-down and lift-off.
#include <benchmark/benchmark.h>

#include <vector>

#include "test/unit/estimation/synthetic_walk.hpp"
#include "test/unit/settings_support.hpp"

namespace {

using namespace ballast;
using namespace ballast::estimation;

const std::vector<EstimatorInput>& walkInputs() {
  static const std::vector<EstimatorInput> inputs = [] {
    const model::Model& m = test::humanoid();
    test::SyntheticWalk motion(m);
    test::SyntheticSensors sensors(motion, test::SensorNoise{}, 3);
    StateEstimator est(m, test::estimatorSettings());
    std::vector<EstimatorInput> in(2000, est.makeInput());
    Eigen::VectorXd q, v;
    for (int k = 0; k < 2000; ++k) sensors.sample(0.5 + k * motion.period, in[k], q, v);
    return in;
  }();
  return inputs;
}

/// One full update (attitude filter, kinematics + M + n, contact forces, Kalman filter).
void BM_EstimatorUpdate(benchmark::State& st) {
  const model::Model& m = test::humanoid();
  EstimatorSettings settings = test::estimatorSettings();
  settings.contactForceCheck = false;  // the schedule decides; the observer still runs
  StateEstimator est(m, settings);
  std::vector<EstimatorInput> inputs = walkInputs();
  EstimatorOutput out;
  std::size_t k = 0;
  double t = 0.0;
  for (auto _ : st) {
    EstimatorInput& in = inputs[k];
    in.time = t;
    benchmark::DoNotOptimize(est.update(in, out));
    t += 0.001;
    k = (k + 1) % inputs.size();
  }
  benchmark::DoNotOptimize(out.basePosition);
}
BENCHMARK(BM_EstimatorUpdate);

/// The attitude filter alone: predict with a gyro sample, correct with an orientation.
void BM_AttitudeFilter(benchmark::State& st) {
  AttitudeFilter f;
  AttitudeFilter::Noise noise;
  f.reset(Eigen::Matrix3d::Identity(), noise);
  const Eigen::Vector3d gyro(0.1, -0.2, 0.3);
  const Eigen::Matrix3d measured = rotationExp(Eigen::Vector3d(0.01, 0.02, -0.01));
  for (auto _ : st) {
    f.predict(gyro, 0.001, noise);
    benchmark::DoNotOptimize(f.correct(measured, noise));
  }
}
BENCHMARK(BM_AttitudeFilter);

/// The Kalman filter alone: one predict and the 28 scalar updates of four stance points.
void BM_KalmanFilterFourStance(benchmark::State& st) {
  BaseKalmanFilter kf;
  kf.reset(BaseKalmanFilter::Vector(BaseKalmanFilter::Vector::Zero()),
           BaseKalmanFilter::Vector(BaseKalmanFilter::Vector::Constant(1e-4)));
  const std::array<double, kContactPoints> drift{0.002, 0.002, 0.002, 0.002};
  const Eigen::Vector3d a(0.1, 0.0, -0.1), d(0.1, 0.1, -0.9), w(0.01, 0.0, 0.0);
  for (auto _ : st) {
    kf.predict(a, 0.001, 0.02, drift);
    for (int c = 0; c < kContactPoints; ++c) {
      kf.updateRelativePosition(c, d, 9e-6);
      kf.updateVelocity(w, 2.5e-3);
      kf.updateContactHeight(c, 0.0, 2.5e-5);
    }
    benchmark::DoNotOptimize(kf.state());
  }
}
BENCHMARK(BM_KalmanFilterFourStance);

}  // namespace
