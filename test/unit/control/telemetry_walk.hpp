// Telemetry frames of a synthetic walk of the humanoid (24 joints, 170 columns): the motion
// and the sensor noise of test/unit/estimation/synthetic_walk.hpp (14-bit encoders, velocity and
// torque noise), so the low digits are as noisy as a robot's; the estimate a little off the
// truth, solve times jittering. What BM_TelemetryWrite writes and the control tests hold the
// .blog's size to.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "control/telemetry.hpp"
#include "test/unit/estimation/synthetic_walk.hpp"
#include "test/unit/settings_support.hpp"

namespace ballast::test {

struct WalkFrames {
  std::vector<control::TelemetryFrame> frames;
  std::vector<std::string> joints;
};

/// 2000 frames (2 s at 1 kHz), made once.
inline const WalkFrames& walkFrames() {
  static const WalkFrames w = [] {
    WalkFrames out;
    const model::Model& m = humanoid();
    for (int b = 1; b < m.nbodies(); ++b)
      if (!m.jointName[b].empty()) out.joints.push_back(m.jointName[b]);
    SyntheticWalk motion(m);
    SyntheticSensors sensors(motion, SensorNoise{}, 3);
    estimation::StateEstimator est(m, estimatorSettings());
    estimation::EstimatorInput in = est.makeInput();
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 1.0);
    Eigen::VectorXd q, v;
    const int nj = static_cast<int>(out.joints.size());
    for (int k = 0; k < 2000; ++k) {
      const double t = 0.5 + k * 0.001;
      sensors.sample(t, in, q, v);
      control::TelemetryFrame f;
      f.t = t;
      f.mode = control::Mode::kWalk;
      for (int i = 0; i < 3; ++i) {
        f.truth.position[i] = q[i];
        f.truth.linear_velocity[i] = v[i];
        f.truth.angular_velocity[i] = v[3 + i];
        f.base.position[i] = q[i] + 1e-3 * noise(rng);
        f.base.linear_velocity[i] = v[i] + 0.01 * noise(rng);
        f.base.angular_velocity[i] = v[3 + i] + 0.005 * noise(rng);
        f.truth.rpy[i] = f.base.rpy[i] = 0.01 * std::sin(6.0 * t + i) + 1e-3 * noise(rng);
      }
      f.has_truth = true;
      f.command.vx = 0.5;
      f.command.height = 0.84;
      int stance = 0;
      for (int c = 0; c < control::kNumContacts; ++c) {
        f.contact[c] = ((k / 350) + c / 2) % 2 == 0;
        stance += f.contact[c];
      }
      for (int c = 0; c < control::kNumContacts; ++c) {  // the weight on the stance points
        const double fz = f.contact[c] ? 800.0 / stance + 30 * noise(rng) : 0.0;
        f.contact_force[c][0] = f.contact[c] ? 0.1 * fz + 5 * noise(rng) : 0.0;
        f.contact_force[c][1] = f.contact[c] ? 5 * noise(rng) : 0.0;
        f.contact_force[c][2] = fz;
      }
      for (int l = 0; l < control::kNumPriorityLevels; ++l)
        f.task_error[l] = std::abs(1e-3 * (l + 1) * noise(rng));
      f.mpc_ms = 2.1 + 0.2 * std::abs(noise(rng));
      f.wbc_ms = 0.3 + 0.05 * std::abs(noise(rng));
      f.tick_ms = 0.45 + 0.05 * std::abs(noise(rng));
      f.lateness_ms = 0.02 * std::abs(noise(rng));
      f.num_joints = nj;
      for (int j = 0; j < nj && j < in.q.size(); ++j) {
        f.q[j] = in.q[j];
        f.dq[j] = in.dq[j];
        f.tau[j] = in.tau.size() > j ? in.tau[j] : 0.0;
        f.q_ref[j] = q[7 + j];
        f.tau_ff[j] = f.tau[j] + 0.5 * noise(rng);
      }
      out.frames.push_back(f);
    }
    return out;
  }();
  return w;
}

}  // namespace ballast::test
