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
#include "test/unit/control/telemetry_walk.hpp"

namespace {

using namespace ballast;
using control::TelemetryFrame;
using test::walkFrames;
using test::WalkFrames;

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
  const blog::TextFormat format(control::telemetryColumnsDescribed(w.joints));
  std::string line;
  std::uint64_t bytes = 0, frames = 0;
  std::size_t k = 0;
  double t0 = 0.0;
  for (auto _ : state) {
    TelemetryFrame f = w.frames[k];
    f.t += t0;
    line.clear();
    control::formatTelemetryLine(f, format, line);
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
