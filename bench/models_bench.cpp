// Vehicle-model speed (issue: Vehicle models on terrain).
// Run: ./build/bench/models_bench   (figures and the exact command in docs/benchmarks.md)

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "terratraj/models/four_wheel_attitude_model.hpp"
#include "terratraj/models/kinodynamic_tables.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/models/rover_integrator.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace {

using namespace terratraj;

const terrain::ElevationMap& hills() {
  static const terrain::ElevationMap map = [] {
    terrain::GeneratorOptions options;
    options.kind = terrain::TerrainKind::kHills;
    options.rows = options.cols = 256;
    options.cell = 0.25;
    return terrain::generateTerrain(options);
  }();
  return map;
}

const terrain::TerrainSurface& surface() {
  static const terrain::TerrainSurface s(hills(), terrain::Interpolation::kBicubic);
  return s;
}

// Random poses over the map (cold: every query is somewhere else).
std::vector<models::PlanarPose> randomPoses() {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> position(2.0, 62.0), heading(-3.14, 3.14);
  std::vector<models::PlanarPose> poses(4096);
  for (models::PlanarPose& p : poses) p = {position(rng), position(rng), heading(rng)};
  return poses;
}

void attitudeAtRandomPoses(benchmark::State& state, const models::TerrainFollowingModel& model) {
  const std::vector<models::PlanarPose> poses = randomPoses();
  models::AttitudeWorkspace workspace;
  models::AttitudeResult result;
  std::size_t i = 0;
  for (auto _ : state) {
    workspace.has_warm_start = false;
    benchmark::DoNotOptimize(model.compute(poses[i], workspace, result));
    i = (i + 1) & 4095;
  }
}

// Consecutive poses 1 cm apart along a curve: the warm-started case of an integrator.
void attitudeAlongPath(benchmark::State& state, const models::TerrainFollowingModel& model) {
  models::AttitudeWorkspace workspace;
  models::AttitudeResult result;
  double s = 0.0;
  for (auto _ : state) {
    const models::PlanarPose pose{5.0 + s, 20.0 + 5.0 * std::sin(0.1 * s), 0.5 * std::cos(0.1 * s)};
    benchmark::DoNotOptimize(model.compute(pose, workspace, result));
    s += 0.01;
    if (s > 50.0) s = 0.0;
  }
}

void BM_AttitudePoint(benchmark::State& state) {
  const models::PointAttitudeModel model(surface());
  attitudeAtRandomPoses(state, model);
}
void BM_AttitudeFourWheel(benchmark::State& state) {
  const models::FourWheelAttitudeModel model(surface(), models::FourWheelGeometry{});
  attitudeAtRandomPoses(state, model);
}
void BM_AttitudeRockerBogieCold(benchmark::State& state) {
  const models::RockerBogieAttitudeModel model(surface());
  attitudeAtRandomPoses(state, model);
}
void BM_AttitudeRockerBogieWarm(benchmark::State& state) {
  const models::RockerBogieAttitudeModel model(surface());
  attitudeAlongPath(state, model);
}
void BM_AttitudePointBilinear(benchmark::State& state) {
  static const terrain::TerrainSurface bilinear(hills(), terrain::Interpolation::kBilinear);
  const models::PointAttitudeModel model(bilinear);
  attitudeAtRandomPoses(state, model);
}
// On the default surface of every command (C2 B-spline).
void BM_AttitudePointBSpline(benchmark::State& state) {
  static const terrain::TerrainSurface spline(hills(), terrain::Interpolation::kCubicBSpline);
  const models::PointAttitudeModel model(spline);
  attitudeAtRandomPoses(state, model);
}
BENCHMARK(BM_AttitudePoint);
BENCHMARK(BM_AttitudePointBilinear);
BENCHMARK(BM_AttitudePointBSpline);
BENCHMARK(BM_AttitudeFourWheel);
BENCHMARK(BM_AttitudeRockerBogieCold);
BENCHMARK(BM_AttitudeRockerBogieWarm);

// A 10 s trajectory (v = 0.8 + 0.02 t, omega = 0.15 - 0.02 t: cubic controls, 6 parameters).
void integrateTenSeconds(benchmark::State& state, models::IntegrationMethod method,
                         bool sensitivities, bool rocker_bogie, bool error_control = false) {
  const models::PointAttitudeModel point(surface());
  const models::RockerBogieAttitudeModel rb(surface());
  const models::RoverKinematics kinematics(
      rocker_bogie ? static_cast<const models::TerrainFollowingModel&>(rb)
                   : static_cast<const models::TerrainFollowingModel&>(point));
  models::IntegratorOptions options;
  options.method = method;
  options.step = 0.01;
  options.sensitivities = sensitivities;
  options.sensitivity_error_control = error_control;
  models::RoverIntegrator integrator(kinematics, options);
  const models::PolynomialControls controls({0.8, 0.02, 0.0}, {0.15, -0.02, 0.0});
  models::IntegrationResult result;
  for (auto _ : state) {
    integrator.integrate({10.0, 30.0, 0.2}, controls, 10.0, {}, result);
    if (result.status != models::IntegrationStatus::kOk)
      state.SkipWithError(result.message.c_str());
  }
  state.counters["rhs_evals"] = static_cast<double>(result.rhs_evaluations);
}

void BM_IntegrateCvodes(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kCvodes, false, false);
}
void BM_IntegrateCvodesSens(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kCvodes, true, false);
}
void BM_IntegrateCvodesSensErrCon(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kCvodes, true, false, true);
}
void BM_IntegrateRk4(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kRk4, false, false);
}
void BM_IntegrateRk4Sens(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kRk4, true, false);
}
void BM_IntegrateCvodesRockerBogie(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kCvodes, false, true);
}
void BM_IntegrateCvodesSensRockerBogie(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kCvodes, true, true);
}
void BM_IntegrateRk4RockerBogie(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kRk4, false, true);
}
void BM_IntegrateRk4SensRockerBogie(benchmark::State& s) {
  integrateTenSeconds(s, models::IntegrationMethod::kRk4, true, true);
}
BENCHMARK(BM_IntegrateCvodes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IntegrateCvodesSens)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IntegrateCvodesSensErrCon)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IntegrateRk4)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IntegrateRk4Sens)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IntegrateCvodesRockerBogie)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IntegrateCvodesSensRockerBogie)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IntegrateRk4RockerBogie)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IntegrateRk4SensRockerBogie)->Unit(benchmark::kMicrosecond);

void BM_TableLookupPitch(benchmark::State& state) {
  const models::PitchSpeedTable table = models::physicsPitchTable(models::defaultPitchEdges(), {});
  double p = -0.5;
  for (auto _ : state) {
    benchmark::DoNotOptimize(table.lookup(p));
    p = p > 0.5 ? -0.5 : p + 0.0013;
  }
}
void BM_TableLookupRollCurvature(benchmark::State& state) {
  const models::RollCurvatureSpeedTable table = models::physicsRollCurvatureTable(
      models::defaultRollEdges(), models::defaultCurvatureEdges(), {});
  double r = -0.5;
  for (auto _ : state) {
    benchmark::DoNotOptimize(table.lookup(r, 2.0 * r));
    r = r > 0.5 ? -0.5 : r + 0.0013;
  }
}
void BM_TableSmoothLookupRollCurvature(benchmark::State& state) {
  const models::RollCurvatureSpeedTable table = models::physicsRollCurvatureTable(
      models::defaultRollEdges(), models::defaultCurvatureEdges(), {});
  double r = -0.5, d_roll = 0.0, d_curvature = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(table.smoothLookup(r, 2.0 * r, &d_roll, &d_curvature));
    r = r > 0.5 ? -0.5 : r + 0.0013;
  }
}
BENCHMARK(BM_TableLookupPitch);
BENCHMARK(BM_TableLookupRollCurvature);
BENCHMARK(BM_TableSmoothLookupRollCurvature);

}  // namespace

BENCHMARK_MAIN();
