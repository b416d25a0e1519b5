// Terrain query and loading speed (issue: Foundation and terrain).
// Run: ./build/bench/terrain_bench   (figures and the exact command in docs/benchmarks.md)

#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>
#include <vector>

#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/tangent_plane_patch.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace {

using terratraj::terrain::ElevationMap;
using terratraj::terrain::GeneratorOptions;
using terratraj::terrain::Interpolation;
using terratraj::terrain::TerrainKind;
using terratraj::terrain::TerrainSurface;

const ElevationMap& hills1024() {
  static const ElevationMap map = [] {
    GeneratorOptions options;
    options.kind = TerrainKind::kHills;
    options.rows = options.cols = 1024;
    options.cell = 0.25;
    return terratraj::terrain::generateTerrain(options);
  }();
  return map;
}

// Random query points over the whole map, so that caches see a realistic spread.
std::vector<Eigen::Vector2d> queryPoints(const ElevationMap& map, std::size_t count) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> x(0.0, map.geometry().width());
  std::uniform_real_distribution<double> y(0.0, map.geometry().height());
  std::vector<Eigen::Vector2d> points(count);
  for (Eigen::Vector2d& p : points) p = {x(rng), y(rng)};
  return points;
}

// `query(surface, point)` at the random points in turn.
template <typename Query>
void queryAtRandomPoints(benchmark::State& state, Interpolation method, const Query& query) {
  const ElevationMap& map = hills1024();
  const TerrainSurface surface(map, method);
  const std::vector<Eigen::Vector2d> points = queryPoints(map, 4096);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(query(surface, points[i]));
    i = (i + 1) & 4095;
  }
  state.SetItemsProcessed(state.iterations());
}

void sampleHeightAndGradient(benchmark::State& state, Interpolation method) {
  queryAtRandomPoints(state, method, [](const TerrainSurface& surface, const Eigen::Vector2d& p) {
    return surface.sample(p);
  });
}

void BM_SampleNearest(benchmark::State& state) {
  sampleHeightAndGradient(state, Interpolation::kNearest);
}
void BM_SampleBilinear(benchmark::State& state) {
  sampleHeightAndGradient(state, Interpolation::kBilinear);
}
void BM_SampleBicubic(benchmark::State& state) {
  sampleHeightAndGradient(state, Interpolation::kBicubic);
}
void BM_SampleBSpline(benchmark::State& state) {
  sampleHeightAndGradient(state, Interpolation::kCubicBSpline);
}
// Height, gradient and Hessian, as the point model's attitude takes them.
void sampleWithHessian(benchmark::State& state, Interpolation method) {
  queryAtRandomPoints(state, method, [](const TerrainSurface& surface, const Eigen::Vector2d& p) {
    return surface.sampleWithHessian(p);
  });
}
void BM_SampleBicubicWithHessian(benchmark::State& state) {
  sampleWithHessian(state, Interpolation::kBicubic);
}
void BM_SampleBSplineWithHessian(benchmark::State& state) {
  sampleWithHessian(state, Interpolation::kCubicBSpline);
}
BENCHMARK(BM_SampleNearest);
BENCHMARK(BM_SampleBilinear);
BENCHMARK(BM_SampleBicubic);
BENCHMARK(BM_SampleBSpline);
BENCHMARK(BM_SampleBicubicWithHessian);
BENCHMARK(BM_SampleBSplineWithHessian);

// Consecutive queries along a path, the access pattern of an integrator.
void sampleAlongPath(benchmark::State& state, Interpolation method) {
  const ElevationMap& map = hills1024();
  const TerrainSurface surface(map, method);
  double x = 1.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(surface.sample({x, 0.37 * x + 1.0}));
    x += 0.01;
    if (x > 150.0) x = 1.0;
  }
}
void BM_SampleBicubicAlongPath(benchmark::State& state) {
  sampleAlongPath(state, Interpolation::kBicubic);
}
void BM_SampleBSplineAlongPath(benchmark::State& state) {
  sampleAlongPath(state, Interpolation::kCubicBSpline);
}
BENCHMARK(BM_SampleBicubicAlongPath);
BENCHMARK(BM_SampleBSplineAlongPath);

void BM_TangentPlanePatch(benchmark::State& state) {
  const ElevationMap& map = hills1024();
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const std::vector<Eigen::Vector2d> points = queryPoints(map, 4096);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(terratraj::terrain::TangentPlanePatch::at(surface, points[i], 0.7));
    i = (i + 1) & 4095;
  }
}
BENCHMARK(BM_TangentPlanePatch);

void BM_LoadGeoTiff1024(benchmark::State& state) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "terratraj_bench_hills_1024.tif";
  terratraj::terrain::saveGeoTiff(hills1024(), file);
  for (auto _ : state) {
    benchmark::DoNotOptimize(terratraj::terrain::loadElevationMap(file));
  }
  std::filesystem::remove(file);
}
BENCHMARK(BM_LoadGeoTiff1024)->Unit(benchmark::kMillisecond);

// Building the default surface: the spline's coefficient grid over the whole map.
void BM_BuildBSplineSurface1024(benchmark::State& state) {
  const ElevationMap& map = hills1024();
  for (auto _ : state) benchmark::DoNotOptimize(TerrainSurface(map, Interpolation::kCubicBSpline));
}
BENCHMARK(BM_BuildBSplineSurface1024)->Unit(benchmark::kMillisecond);

void BM_GenerateHills1024(benchmark::State& state) {
  GeneratorOptions options;
  options.kind = TerrainKind::kHills;
  options.rows = options.cols = 1024;
  for (auto _ : state) benchmark::DoNotOptimize(terratraj::terrain::generateTerrain(options));
}
BENCHMARK(BM_GenerateHills1024)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
