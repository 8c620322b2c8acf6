// Telemetry writing (issue 18): what a recording costs the writer thread per frame and the disk
// per frame, as text (.tsv) and as the binary log (.blog). Goal: a 10-minute 1 kHz recording of
// every column <= 150 MB (<= 250 bytes per frame), the writer under 5 % of one core (< 50 µs of
// writer time per 1 ms frame). Frames: a synthetic walk of the humanoid (24 joints, 170 columns)
// with the sensor noise of test/unit/estimation/synthetic_walk.hpp (14-bit encoders, velocity
// and torque noise), so the low digits are as noisy as a robot's. Counters: bytes_per_frame,
// MB_per_10min (600 000 frames).
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "blog/blog.hpp"
#include "control/telemetry.hpp"
#include "test/unit/estimation/synthetic_walk.hpp"
#include "test/unit/settings_support.hpp"

namespace {

using namespace ballast;
using control::TelemetryFrame;

struct WalkFrames {
  std::vector<TelemetryFrame> frames;
  std::vector<std::string> joints;
};

const WalkFrames& walkFrames() {
  static const WalkFrames w = [] {
    WalkFrames out;
    const model::Model& m = test::humanoid();
    for (int b = 1; b < m.nbodies(); ++b)
      if (!m.jointName[b].empty()) out.joints.push_back(m.jointName[b]);
    test::SyntheticWalk motion(m);
    test::SyntheticSensors sensors(motion, test::SensorNoise{}, 3);
    estimation::StateEstimator est(m, test::estimatorSettings());
    estimation::EstimatorInput in = est.makeInput();
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 1.0);
    Eigen::VectorXd q, v;
    const int nj = static_cast<int>(out.joints.size());
    for (int k = 0; k < 2000; ++k) {
      const double t = 0.5 + k * 0.001;
      sensors.sample(t, in, q, v);
      TelemetryFrame f;
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
      for (int c = 0; c < control::kNumContacts; ++c) f.contact[c] = ((k / 350) + c / 2) % 2 == 0;
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

std::string tempFile(const char* ext) {
  return std::filesystem::temp_directory_path() /
         ("ballast-bench-telemetry-" + std::to_string(getpid()) + ext);
}

void report(benchmark::State& state, std::uint64_t bytes, std::uint64_t frames) {
  const double per_frame = frames ? double(bytes) / double(frames) : 0.0;
  state.counters["bytes_per_frame"] = per_frame;
  state.counters["MB_per_10min"] = per_frame * 600000 / 1e6;
  state.counters["columns"] = double(control::telemetryColumns(walkFrames().joints).size());
}

/// The writer thread's work per frame for a .blog: the values, the block, zstd, the write.
void BM_TelemetryWrite_Blog(benchmark::State& state) {
  const WalkFrames& w = walkFrames();
  const std::string path = tempFile(".blog");
  blog::Writer writer;
  blog::Header h;
  h.profile = "sim-flat";
  h.robot = "humanoid";
  h.columns = control::telemetryColumnsDescribed(w.joints);
  std::string error;
  if (!writer.open(path, h, error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  std::vector<double> values(control::kMaxTelemetryColumns);
  std::size_t k = 0;
  double t0 = 0.0;
  for (auto _ : state) {
    TelemetryFrame f = w.frames[k];
    f.t += t0;
    control::telemetryValues(f, values.data());
    writer.append(values.data());
    if (++k == w.frames.size()) {
      k = 0;
      t0 += 2.0;
    }
  }
  const std::uint64_t frames = writer.frames(), bytes = writer.close();
  report(state, bytes, frames);
  std::filesystem::remove(path);
}
BENCHMARK(BM_TelemetryWrite_Blog)->Name("BM_TelemetryWrite/blog")->Unit(benchmark::kMicrosecond);

/// The same for the text recording: a formatted line, written.
void BM_TelemetryWrite_Tsv(benchmark::State& state) {
  const WalkFrames& w = walkFrames();
  const std::string path = tempFile(".tsv");
  std::FILE* file = std::fopen(path.c_str(), "w");
  std::string line;
  std::uint64_t bytes = 0, frames = 0;
  std::size_t k = 0;
  double t0 = 0.0;
  for (auto _ : state) {
    TelemetryFrame f = w.frames[k];
    f.t += t0;
    line.clear();
    control::formatTelemetryLine(f, line);
    std::fwrite(line.data(), 1, line.size(), file);
    bytes += line.size();
    ++frames;
    if (++k == w.frames.size()) {
      k = 0;
      t0 += 2.0;
    }
  }
  std::fclose(file);
  report(state, bytes, frames);
  std::filesystem::remove(path);
}
BENCHMARK(BM_TelemetryWrite_Tsv)->Name("BM_TelemetryWrite/tsv")->Unit(benchmark::kMicrosecond);

}  // namespace
