// ballast-mkmap: writes an OctoMap terrain map (flat, stage, steps, rough) for the simulation and
// the planner. See ballast-mkmap.1 and README.md in this directory.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>

#include "terrain_maps.hpp"

int main(int argc, char** argv) {
  using namespace ballast::maps;
  CLI::App app{"ballast-mkmap: write an OctoMap terrain map (.bt or .ot)"};
  std::string shape, output;
  double resolution = 0.02, height = 0.15, start = 1.5, depth = 2.0, width = 3.0;
  double rise = 0.10, run = 0.30, amplitude = 0.04, patch = 0.2;
  int count = 3;
  std::uint64_t seed = 1;
  std::vector<double> extentValues{-2.0, 4.0, -2.0, 2.0};
  app.add_option("shape", shape, "flat, stage, steps or rough")
      ->required()
      ->check(CLI::IsMember({"flat", "stage", "steps", "rough"}));
  app.add_option("-o,--output", output, "map file to write (.bt binary, .ot full)")->required();
  app.add_option("-r,--resolution", resolution, "cell size, m")->capture_default_str()
      ->check(CLI::Range(0.005, 1.0));
  app.add_option("--extent", extentValues, "x_min x_max y_min y_max of the floor, m")
      ->expected(4)->capture_default_str();
  app.add_option("--height", height, "stage: height, m")->capture_default_str()
      ->check(CLI::Range(0.0, 2.0));
  app.add_option("--start", start, "stage, steps: x where it begins, m")->capture_default_str();
  app.add_option("--depth", depth, "stage: length along x, m")->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--width", width, "stage, steps: width across y, m")->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--count", count, "steps: number of steps")->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("--rise", rise, "steps: rise of each step, m")->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--run", run, "steps: depth of each step, m")->capture_default_str()
      ->check(CLI::Range(0.01, 10.0));
  app.add_option("--amplitude", amplitude, "rough: highest patch, m")->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--patch", patch, "rough: patch side, m")->capture_default_str()
      ->check(CLI::Range(0.005, 10.0));
  app.add_option("--seed", seed, "rough: random seed")->capture_default_str();
  double ceiling = 0.0;
  app.add_option("--ceiling", ceiling,
                 "any shape: a ceiling slab 10 cm thick from this height over the floor, m (0: none)")
      ->capture_default_str()->check(CLI::Range(0.0, 100.0));
  CLI11_PARSE(app, argc, argv);

  const auto endsWith = [&](const char* tail) {
    const std::string t(tail);
    return output.size() >= t.size() && output.compare(output.size() - t.size(), t.size(), t) == 0;
  };
  if (!endsWith(".bt") && !endsWith(".ot")) {
    std::fprintf(stderr, "ballast-mkmap: %s: a map file ends in .bt (binary) or .ot (full)\n",
                 output.c_str());
    return 2;
  }
  const MapExtent extent{extentValues[0], extentValues[1], extentValues[2], extentValues[3]};
  if (!(extent.xMin < extent.xMax && extent.yMin < extent.yMax)) {
    std::fprintf(stderr, "ballast-mkmap: --extent: x_min < x_max and y_min < y_max, please\n");
    return 2;
  }
  HeightFunction terrain = [](double, double) { return 0.0; };
  if (shape == "stage") terrain = stage(height, start, depth, width);
  if (shape == "steps") terrain = steps(count, rise, run, start, width);
  if (shape == "rough") terrain = rough(amplitude, patch, seed);

  const auto tree = makeTerrainMap(terrain, resolution, extent);
  if (ceiling > 0.0) {  // cells whose centres lie in [ceiling, ceiling + 0.1)
    for (double x = extent.xMin + resolution / 2; x < extent.xMax; x += resolution)
      for (double y = extent.yMin + resolution / 2; y < extent.yMax; y += resolution)
        for (double z = std::ceil(ceiling / resolution - 0.5) * resolution + resolution / 2;
             z < ceiling + 0.1; z += resolution)
          tree->updateNode(octomap::point3d(static_cast<float>(x), static_cast<float>(y),
                                            static_cast<float>(z)), true, true);
    tree->updateInnerOccupancy();
    tree->prune();
  }
  std::string error;
  if (!writeTerrainMap(*tree, output, error)) {
    std::fprintf(stderr, "ballast-mkmap: %s\n", error.c_str());
    return 1;
  }
  std::printf("%s: %s map, %zu leaves at %g m\n", output.c_str(), shape.c_str(),
              tree->getNumLeafNodes(), resolution);
  return 0;
}
