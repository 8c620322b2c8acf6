// The planner's terrain queries (daemon/terrain HeightMap): one height(x, y) on the lab-steps
// map at points spread over it and beyond its edges (a query is an index and a load; compare
// with OctoMap's downward ray, ≈ 1–2 µs), and building the grid from a map file (the IO thread
// does it on `map load`).
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "terrain/height_map.hpp"

namespace {

using ballast::terrain::HeightMap;

std::string labMap(const char* name) {
  return std::string(BALLAST_SOURCE_DIR) + "/maps/" + name;
}

void BM_TerrainHeight(benchmark::State& st) {
  const HeightMap map = HeightMap::fromFile(labMap("lab-steps.bt"), 0.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-3.0, 7.0), y(-3.0, 3.0);
  std::vector<double> points(2 * 4096);
  for (double& p : points) p = (&p - points.data()) % 2 ? y(rng) : x(rng);
  std::size_t i = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(map.height(points[i], points[i + 1]));
    i = (i + 2) % points.size();
  }
}
BENCHMARK(BM_TerrainHeight);

void BM_TerrainBuildFromFile(benchmark::State& st) {
  const std::string file = labMap("lab-stage.bt");
  for (auto _ : st) benchmark::DoNotOptimize(HeightMap::fromFile(file, 0.0));
}
BENCHMARK(BM_TerrainBuildFromFile)->Unit(benchmark::kMillisecond);

}  // namespace
