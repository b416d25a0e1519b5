// `terratraj bench robustness` (and the robustness part of `bench convergence`): the
// optimal-control core on ordinary problems a user expects to be solved (issue: the core solves
// every reachable problem by default), every method with its global seeds
// (refine::solveSeeded): constant-speed curvature-limited turns on flat ground (the Dubins
// length is the bound), rest-to-rest turn-backs, and rest-to-rest and moving problems on the
// three real DEMs with every vehicle model, obstacles (slopes over 25 deg) on the gully.
// Per method: success (the verdict), cost over the bound or the best verified cost of any
// method on the problem, time.

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "terratraj/bench/benchmark_suite.hpp"
#include "terratraj/bench/report_json.hpp"
#include "terratraj/bench/robustness_sets.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/models/vehicle_factory.hpp"
#include "terratraj/ocp/dubins_path.hpp"
#include "terratraj/refine/seeded_solver.hpp"
#include "terratraj/terrain/lethal_layer.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::bench {

using models::VehicleModelKind;
namespace {

namespace sets = bench::problem_sets;

// Multiple shooting is left out: 850+ iterations and the 60 s limit on most turns (see
// docs/benchmarks.md); `solve --method shooting` still takes the same seeds.
const char* const kMethods[] = {"auto", "newton", "ipopt", "ceres", "collocation"};

struct RobustDem {
  const char* name;
  const char* file;
  std::optional<double> cell;
  double z_scale;
  std::optional<double> lethal_slope_deg;  ///< obstacles: cells steeper than this
};

// The DEMs at rover scale (as the convergence suite's), obstacles on the gully.
const RobustDem kRobustDems[] = {
    {"dem_moon", "dem_moon.tif", std::nullopt, 1.0, std::nullopt},
    {"davosdorf", "davosdorf.tif", 0.25, 0.0125, std::nullopt},
    // At its own 3 m cells (at rover scale, 0.5 m, its data is too fragmented for 4-12 m
    // problems with clear ends): cells steeper than 25 deg lethal.
    {"west_bijou_gully", "west_bijou_gully.asc", std::nullopt, 1.0, 25.0},
};

const VehicleModelKind kVehicles[] = {VehicleModelKind::kPoint, VehicleModelKind::kFourWheel,
                                      VehicleModelKind::kRockerBogie, VehicleModelKind::kSegwayRmp};

// A set: its map, vehicle and problems, built on first use (one per process), never moved.
struct RobustSetData {
  terrain::ElevationMap map;
  std::unique_ptr<terrain::TerrainSurface> surface;
  std::unique_ptr<models::TerrainFollowingModel> vehicle;
  std::vector<ocp::BoundaryValueProblem> problems;
  bool dubins_bound = false;  ///< constant speed on flat ground: the Dubins length bounds
  bool segway = false;        ///< the Segway RMP: its look-ups apply (problems' tables.segway)
  models::SegwayLookups segway_lookups = models::defaultSegwayLookups();
};

struct RobustSetSpec {
  std::string name;
  std::string vehicle;
  int count = 0;
  std::function<std::unique_ptr<RobustSetData>()> build;
};

std::unique_ptr<RobustSetData> makeData(terrain::ElevationMap map, VehicleModelKind vehicle,
                                        terrain::Interpolation interpolation) {
  auto data = std::make_unique<RobustSetData>();
  data->map = std::move(map);
  data->surface = std::make_unique<terrain::TerrainSurface>(data->map, interpolation);
  data->vehicle = makeTerrainFollowingModel(vehicle, *data->surface);
  data->segway = vehicle == VehicleModelKind::kSegwayRmp;
  return data;
}

std::vector<RobustSetSpec> robustSets(const BenchmarkSettings& settings) {
  const bool quick = settings.quick;
  const terrain::Interpolation interpolation = settings.interpolation;
  // Seeds apart from the unit tests' (which draw with seeds 1..).
  const std::uint64_t seed = 1000 + settings.seed;
  std::vector<RobustSetSpec> specs;
  const int turns = quick ? 4 : 40, backs = quick ? 2 : 10;
  specs.push_back({"robust/turns", "point", turns, [turns, seed, interpolation] {
                     auto data =
                         makeData(sets::openFlatMap(), VehicleModelKind::kPoint, interpolation);
                     data->problems = sets::constantSpeedTurns(turns, seed);
                     data->dubins_bound = true;
                     return data;
                   }});
  specs.push_back({"robust/turn_backs", "point", backs, [backs, seed, interpolation] {
                     auto data =
                         makeData(sets::openFlatMap(), VehicleModelKind::kPoint, interpolation);
                     data->problems = sets::turnBacks(backs, seed + 1);
                     return data;
                   }});
  if (settings.data_dir.empty()) return specs;
  const int per = quick ? 2 : 4;
  for (const RobustDem& dem : kRobustDems) {
    for (const VehicleModelKind vehicle : kVehicles) {
      const std::filesystem::path path = settings.data_dir / dem.file;
      specs.push_back(
          {std::string("robust/") + dem.name + "_" + vehicleModelName(vehicle),
           vehicleModelName(vehicle), per, [path, dem, vehicle, per, seed, interpolation] {
             terrain::RasterLoadOptions load;
             load.cell = dem.cell;
             load.z_scale = dem.z_scale;
             terrain::ElevationMap map = terrain::loadElevationMap(path, load);
             if (dem.lethal_slope_deg) {
               terrain::markLethalBySlope(map, *dem.lethal_slope_deg * 3.14159265358979 / 180);
             }
             auto data = makeData(std::move(map), vehicle, interpolation);
             data->problems = sets::terrainProblems(data->map, *data->vehicle, sets::roverLimits(),
                                                    per, seed + 2);
             for (ocp::BoundaryValueProblem& problem : data->problems) {
               if (data->segway) problem.tables.segway = &data->segway_lookups;
             }
             return data;
           }});
    }
  }
  return specs;
}

refine::CoreMethod coreMethodNamed(const std::string& name) {
  for (refine::CoreMethod m :
       {refine::CoreMethod::kAuto, refine::CoreMethod::kNewton, refine::CoreMethod::kNewtonFd,
        refine::CoreMethod::kIpopt, refine::CoreMethod::kCeres, refine::CoreMethod::kShooting,
        refine::CoreMethod::kCollocation}) {
    if (name == refine::coreMethodName(m)) return m;
  }
  return refine::CoreMethod::kAuto;
}

nlohmann::json robustRow(const RobustSetData& data, int index, const std::string& method) {
  nlohmann::json row;
  if (index >= static_cast<int>(data.problems.size())) {
    row["status"] = "skipped";
    row["reason"] = "the map had no room for this problem";
    return row;
  }
  const ocp::BoundaryValueProblem& problem = data.problems[static_cast<std::size_t>(index)];
  refine::SeededSolveOptions options;
  options.method = coreMethodNamed(method);
  options.search_seed = 1;
  options.time_limit_s = 60.0;  // a case that needs more is a failure worth seeing
  const refine::SeededSolution s = refine::solveSeeded(*data.vehicle, problem, &data.map, options);
  // The problem, to reproduce the row with `terratraj solve` (headings in degrees).
  const auto state = [](const ocp::VehicleState& q) {
    return nlohmann::json{{"x", q.x},
                          {"y", q.y},
                          {"heading_deg", q.heading * 180.0 / 3.14159265358979323846},
                          {"v", q.v},
                          {"omega", q.omega}};
  };
  row["start"] = state(problem.start);
  row["goal"] = state(problem.goal);
  row["status"] = ocp::solveStatusName(s.status);
  row["reason"] = s.reason;
  row["method_used"] = s.method;
  row["initial_guess"] = s.initial_guess;
  row["attempts"] = attemptsJson(s.attempts);
  // Proved unreachable before any seed (models::checkGoalReachability): not a reachable
  // problem, so outside the success rates (counted apart).
  row["unreachable"] = s.reachability.has_value() && !s.reachability->reachable;
  if (s.reachability) row["reachability_ms"] = s.reachability->time_ms;
  row["iterations"] = s.iterations;
  row["time_ms"] = s.total_time_ms;
  row["cost"] = s.verified.ok ? jsonNumber(s.verified.cost) : nlohmann::json(nullptr);
  row["check_ok"] = s.verified.ok && s.verdict.passes();
  row["terminal_error_m"] =
      s.verified.ok ? jsonNumber(s.verified.terminal_error.head<2>().norm()) : nullptr;
  if (data.dubins_bound) {
    const std::vector<ocp::DubinsPath> paths = ocp::dubinsPaths(
        {problem.start.x, problem.start.y, problem.start.heading},
        {problem.goal.x, problem.goal.y, problem.goal.heading}, 1.0 / problem.limits.kappa_max);
    const double bound = paths.front().length() / problem.start.v;
    row["bound_s"] = bound;
    if (s.verified.ok) row["cost_over_bound"] = s.verified.cost / bound;
  }
  return row;
}

}  // namespace

class RobustnessCases {
 public:
  explicit RobustnessCases(const BenchmarkSettings& settings)
      : settings_(settings), specs_(robustSets(settings)), cache_(std::make_shared<Cache>()) {}

  std::vector<BenchmarkCase> cases() const {
    std::vector<BenchmarkCase> out;
    for (std::size_t s = 0; s < specs_.size(); ++s) {
      for (int i = 0; i < specs_[s].count; ++i) {
        for (const char* method : kMethods) {
          out.push_back({specs_[s].name + "/" + std::to_string(i) + "/" + method,
                         [this, s, i, method = std::string(method)] {
                           nlohmann::json row = robustRow(data(s), i, method);
                           row["set"] = specs_[s].name;
                           row["problem"] = i;
                           row["solver"] = method;
                           row["vehicle"] = specs_[s].vehicle;
                           row["family"] = "robustness";
                           return row;
                         }});
        }
      }
    }
    return out;
  }

  std::vector<std::filesystem::path> inputFiles() const {
    std::vector<std::filesystem::path> files;
    if (settings_.data_dir.empty()) return files;
    for (const RobustDem& dem : kRobustDems) files.push_back(settings_.data_dir / dem.file);
    return files;
  }

 private:
  struct Cache {
    std::map<std::size_t, std::unique_ptr<RobustSetData>> sets;
  };
  const RobustSetData& data(std::size_t s) const {
    std::unique_ptr<RobustSetData>& slot = cache_->sets[s];
    if (!slot) slot = specs_[s].build();
    return *slot;
  }
  BenchmarkSettings settings_;
  std::vector<RobustSetSpec> specs_;
  std::shared_ptr<Cache> cache_;
};

nlohmann::json summarizeRobustness(const nlohmann::json& rows) {
  // The best verified cost of any method per problem.
  std::map<std::string, double> best;
  const auto key = [](const nlohmann::json& row) {
    return row.value("set", "") + "/" + std::to_string(row.value("problem", -1));
  };
  for (const nlohmann::json& row : rows) {
    if (row.value("family", "") != "robustness" || row.value("status", "") != "converged") continue;
    const double cost = row["cost"].get<double>();
    auto [it, inserted] = best.emplace(key(row), cost);
    if (!inserted) it->second = std::min(it->second, cost);
  }
  struct Tally {
    int runs = 0, converged = 0, check_failures = 0, unreachable = 0;
    std::vector<double> over_bound, over_best, time_ms;
  };
  std::map<std::string, Tally> by_method;
  std::map<std::string, std::map<std::string, std::pair<int, int>>> by_set;
  for (const nlohmann::json& row : rows) {
    if (row.value("family", "") != "robustness" || row.value("status", "") == "skipped") continue;
    Tally& t = by_method[row.value("solver", "")];
    if (row.value("unreachable", false)) {  // proved before any seed: not a reachable problem
      ++t.unreachable;
      continue;
    }
    ++t.runs;
    std::pair<int, int>& set = by_set[row.value("set", "")][row.value("solver", "")];
    ++set.first;
    if (row["time_ms"].is_number()) t.time_ms.push_back(row["time_ms"].get<double>());
    if (row.value("status", "") != "converged") continue;
    ++t.converged;
    ++set.second;
    if (!row.value("check_ok", false)) ++t.check_failures;
    if (row.contains("cost_over_bound")) {
      t.over_bound.push_back(row["cost_over_bound"].get<double>());
    }
    t.over_best.push_back(row["cost"].get<double>() / best.at(key(row)));
  }
  nlohmann::json methods = nlohmann::json::object();
  for (auto& [method, t] : by_method) {
    methods[method] = {
        {"runs", t.runs},
        {"converged", t.converged},
        {"success_rate", t.runs > 0 ? nlohmann::json(static_cast<double>(t.converged) / t.runs)
                                    : nlohmann::json(nullptr)},
        {"converged_but_check_failed", t.check_failures},
        {"unreachable", t.unreachable},
        {"cost_over_dubins_bound", distributionJson(t.over_bound)},
        {"cost_over_best_of_any_method", distributionJson(t.over_best)},
        {"time_ms", distributionJson(t.time_ms)}};
  }
  nlohmann::json sets_json = nlohmann::json::object();
  for (const auto& [set, methods_in_set] : by_set) {
    for (const auto& [method, counts] : methods_in_set) {
      sets_json[set][method] = {{"runs", counts.first}, {"converged", counts.second}};
    }
  }
  return {{"methods", methods}, {"sets", sets_json}};
}

std::string robustnessText(const nlohmann::json& summary) {
  std::ostringstream text;
  text << "robustness   success   cost / Dubins (median, max, min)   cost / best (median, "
          "max)   time ms (median, p90)\n";
  for (const char* method : kMethods) {
    if (!summary["methods"].contains(method)) continue;
    const nlohmann::json& m = summary["methods"][method];
    text << method << std::string(13 - std::min<std::size_t>(std::string(method).size(), 12), ' ')
         << m["converged"] << "/" << m["runs"]
         << (m.value("unreachable", 0) > 0
                 ? " (+" + std::to_string(m.value("unreachable", 0)) + " unreachable)"
                 : std::string())
         << "   " << figureText(m["cost_over_dubins_bound"], "median") << ", "
         << figureText(m["cost_over_dubins_bound"], "max") << ", "
         << figureText(m["cost_over_dubins_bound"], "min") << "   "
         << figureText(m["cost_over_best_of_any_method"], "median") << ", "
         << figureText(m["cost_over_best_of_any_method"], "max") << "   "
         << figureText(m["time_ms"], "median") << ", " << figureText(m["time_ms"], "p90") << '\n';
  }
  return text.str();
}

namespace {

class RobustnessSuite final : public BenchmarkSuite {
 public:
  explicit RobustnessSuite(const BenchmarkSettings& settings) : cases_(settings) {}
  std::string name() const override { return "robustness"; }
  std::vector<BenchmarkCase> cases() const override { return cases_.cases(); }
  nlohmann::json summarize(const nlohmann::json& rows) const override {
    return summarizeRobustness(rows);
  }
  std::string summaryText(const nlohmann::json& summary) const override {
    return robustnessText(summary);
  }
  std::vector<std::filesystem::path> inputFiles() const override { return cases_.inputFiles(); }

 private:
  RobustnessCases cases_;
};

}  // namespace

std::unique_ptr<BenchmarkSuite> makeRobustnessSuite(const BenchmarkSettings& settings) {
  return std::make_unique<RobustnessSuite>(settings);
}

std::vector<BenchmarkCase> robustnessCases(const BenchmarkSettings& settings) {
  // The cases hold a shared cache: copying the object that owns it keeps it alive.
  auto owner = std::make_shared<RobustnessCases>(settings);
  std::vector<BenchmarkCase> cases = owner->cases();
  for (BenchmarkCase& c : cases) {
    c.run = [owner, run = std::move(c.run)] { return run(); };
  }
  return cases;
}

std::vector<std::filesystem::path> robustnessInputs(const BenchmarkSettings& settings) {
  return RobustnessCases(settings).inputFiles();
}

}  // namespace terratraj::bench
