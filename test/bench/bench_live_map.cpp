// The live terrain map (daemon/terrain LiveMap): one lidar scan of the simulated sensor's size
// (sim settings' defaults: 180 × 16 rays, elevation -1.0 to 0.25 rad, 10 Hz, from 1.45 m up)
// of the lab stage (15 cm, 1.5 m ahead), the sensor moving 4 cm per scan (0.4 m/s): ray
// casting into the OcTree, and the grid columns the scan changed. Counters: points per second
// of insertion, and the two parts' time per scan (ms). The first scans of an empty map change
// every cell they see; the steady state is a robot walking into a map it has mostly seen.
#include <benchmark/benchmark.h>

#include <octomap/OcTree.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "terrain/live_map.hpp"

namespace {

using ballast::terrain::LiveMap;
using ballast::terrain::LiveMapSettings;

/// World-frame hits of a scan of the floor and the stage from `o`.
std::vector<float> stageScan(const std::array<double, 3>& o, int azimuths = 180, int lines = 16) {
  std::vector<float> points;
  points.reserve(3 * azimuths * lines);
  for (int i = 0; i < azimuths; ++i)
    for (int j = 0; j < lines; ++j) {
      const double az = 2 * M_PI * i / azimuths, el = -1.0 + 1.25 * j / (lines - 1);
      const double d[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
      double r = d[2] < 0 ? -o[2] / d[2] : 1e9;
      const double lo[3] = {1.5, -1.5, 0.0}, hi[3] = {3.5, 1.5, 0.15};
      double enter = 0.0, leave = 1e9;
      for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < 1e-12) continue;
        const double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        enter = std::max(enter, std::min(a, b));
        leave = std::min(leave, std::max(a, b));
      }
      if (enter <= leave) r = std::min(r, enter);
      if (r > 10.0) continue;
      for (int k = 0; k < 3; ++k) points.push_back(static_cast<float>(o[k] + r * d[k]));
    }
  return points;
}

void BM_LiveMapScan(benchmark::State& st) {
  LiveMapSettings s;
  s.resolution = static_cast<double>(st.range(0)) / 100.0;
  LiveMap map(s);
  std::vector<std::vector<float>> scans;
  for (int k = 0; k < 50; ++k) scans.push_back(stageScan({0.04 * k, 0.0, 1.45}));
  // Steady state: the first 10 scans (0.4 m of walking) are in before timing starts.
  for (int k = 0; k < 10; ++k)
    map.insert(scans[k].data(), static_cast<int>(scans[k].size() / 3), {}, {0.04 * k, 0.0, 1.45});
  double insert = 0, grid = 0, points = 0, columns = 0, scansDone = 0;
  int k = 10;
  for (auto _ : st) {
    const auto u = map.insert(scans[k].data(), static_cast<int>(scans[k].size() / 3), {},
                              {0.04 * k, 0.0, 1.45});
    insert += u.insertSeconds, grid += u.gridSeconds;
    points += u.points, columns += static_cast<double>(u.changedColumns), ++scansDone;
    k = k + 1 < 50 ? k + 1 : 10;
  }
  st.counters["points_per_s"] = points / insert;
  st.counters["insert_ms"] = 1e3 * insert / scansDone;
  st.counters["grid_ms"] = 1e3 * grid / scansDone;
  st.counters["columns"] = columns / scansDone;
}
BENCHMARK(BM_LiveMapScan)->Arg(2)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond);

void BM_LiveMapHeightsCopy(benchmark::State& st) {
  LiveMapSettings s;
  LiveMap map(s);
  for (int k = 0; k < 50; ++k) {
    const auto p = stageScan({0.04 * k, 0.0, 1.45});
    map.insert(p.data(), static_cast<int>(p.size() / 3), {}, {0.04 * k, 0.0, 1.45});
  }
  for (auto _ : st) benchmark::DoNotOptimize(map.heights());
  st.counters["columns"] = static_cast<double>(map.grid().columnsX() * map.grid().columnsY());
}
BENCHMARK(BM_LiveMapHeightsCopy)->Unit(benchmark::kMicrosecond);

}  // namespace
