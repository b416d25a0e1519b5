// `terratraj bench convergence`: every boundary-value solver on the problem sets of 004_...
// (flat 45-goal fan, rough 94-edge lattice, slope-dwell hill with alpha 0, 1, 2) and on seeded
// random problems on the real DEMs. One case per (problem, solver); each result is the
// independent re-simulation's, not the solver's claim.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "terratraj/bench/benchmark_suite.hpp"
#include "terratraj/bench/problem_sets.hpp"
#include "terratraj/bench/report_json.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/ocp/transcription_model.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::bench {
namespace {

namespace sets = bench::problem_sets;

// collocation_refined: Hermite-Simpson with up to 3 rounds of mesh refinement (intervals whose
// local error exceeds 1e-4 split): the same formulation at a setting that trades time for the
// discretisation error the re-simulation sees.
const char* const kSolvers[] = {
    "newton_fd", "newton", "ipopt", "ceres", "shooting", "collocation", "collocation_refined"};

// A problem set: its map, vehicle and problems, built on first use (one per process).
struct ProblemSetData {
  ProblemSetData() = default;
  ProblemSetData(const ProblemSetData&) = delete;
  ProblemSetData& operator=(const ProblemSetData&) = delete;
  terrain::ElevationMap map;
  std::unique_ptr<terrain::TerrainSurface> surface;
  std::unique_ptr<models::TerrainFollowingModel> vehicle;
  std::vector<ocp::BoundaryValueProblem> problems;
};

struct ProblemSetSpec {
  std::string name;
  std::string vehicle;  // "point" or "rocker_bogie"
  int count = 0;        // problems in the set (after the quick cut)
  std::function<std::unique_ptr<ProblemSetData>()> build;
};

std::unique_ptr<models::TerrainFollowingModel> makeVehicle(const std::string& name,
                                                           const terrain::TerrainSurface& s) {
  if (name == "rocker_bogie") return std::make_unique<models::RockerBogieAttitudeModel>(s);
  return std::make_unique<models::PointAttitudeModel>(s);
}

// The surface and vehicle point into the map: the data is built in place and never moved.
std::unique_ptr<ProblemSetData> finish(terrain::ElevationMap map, const std::string& vehicle,
                                       std::vector<ocp::BoundaryValueProblem> problems,
                                       terrain::Interpolation interpolation) {
  auto data = std::make_unique<ProblemSetData>();
  data->map = std::move(map);
  data->problems = std::move(problems);
  data->surface = std::make_unique<terrain::TerrainSurface>(data->map, interpolation);
  data->vehicle = makeVehicle(vehicle, *data->surface);
  return data;
}

// Every `stride`-th problem of `all` (the quick suite's cut), at most `count`.
std::vector<ocp::BoundaryValueProblem> cut(std::vector<ocp::BoundaryValueProblem> all, int count) {
  if (count >= static_cast<int>(all.size())) return all;
  std::vector<ocp::BoundaryValueProblem> out;
  const double stride = static_cast<double>(all.size()) / count;
  for (int i = 0; i < count; ++i) out.push_back(all[static_cast<std::size_t>(i * stride)]);
  return out;
}

// A real DEM rescaled to rover scale: `cell` [m] and z_scale keep or soften its slopes.
struct DemSpec {
  const char* name;
  const char* file;
  std::optional<double> cell;
  double z_scale;
};

const DemSpec kDems[] = {
    {"dem_moon", "dem_moon.tif", std::nullopt, 1.0},             // 2.43 m cells, lunar slopes
    {"davosdorf", "davosdorf.tif", 0.25, 0.0125},                // 10 m -> 0.25 m, slopes halved
    {"west_bijou_gully", "west_bijou_gully.asc", 0.5, 1.0 / 6},  // 3 m -> 0.5 m, slopes kept
};

std::vector<ProblemSetSpec> problemSets(const BenchmarkSettings& settings) {
  const bool quick = settings.quick;
  const terrain::Interpolation surface = settings.interpolation;
  std::vector<ProblemSetSpec> specs;
  specs.push_back({"flat_fan", "point", quick ? 5 : 45, [quick, surface] {
                     return finish(sets::flatMap(), "point", cut(sets::flatFan(), quick ? 5 : 45),
                                   surface);
                   }});
  specs.push_back({"rough_lattice", "rocker_bogie", quick ? 6 : 94, [quick, surface] {
                     return finish(sets::roughMap(), "rocker_bogie",
                                   cut(sets::roughLattice(), quick ? 6 : 94), surface);
                   }});
  specs.push_back({"slope_dwell", "point", 3, [surface] {
                     std::vector<ocp::BoundaryValueProblem> problems;
                     for (const double alpha : {0.0, 1.0, 2.0}) {
                       problems.push_back(sets::singleHillProblem(alpha));
                     }
                     return finish(sets::singleHillMap(), "point", problems, surface);
                   }});
  if (settings.data_dir.empty()) return specs;
  const int per_dem = quick ? 2 : 10;
  for (const DemSpec& dem : kDems) {
    const std::filesystem::path path = settings.data_dir / dem.file;
    const std::uint64_t seed = settings.seed;
    specs.push_back({dem.name, "point", per_dem, [path, dem, per_dem, seed, surface] {
                       terrain::RasterLoadOptions load;
                       load.cell = dem.cell;
                       load.z_scale = dem.z_scale;
                       terrain::ElevationMap map = terrain::loadElevationMap(path, load);
                       sets::RandomProblemOptions random;
                       random.count = per_dem;
                       random.seed = seed;
                       std::vector<ocp::BoundaryValueProblem> problems =
                           sets::randomProblems(map, random);
                       return finish(std::move(map), "point", std::move(problems), surface);
                     }});
  }
  return specs;
}

nlohmann::json parametricRow(const ProblemSetData& data, const ocp::BoundaryValueProblem& problem,
                             ocp::BoundaryValueMethod method) {
  ocp::BoundaryValueOptions options;
  options.method = method;
  const ocp::BoundaryValueSolution s =
      ocp::solveBoundaryValue(*data.vehicle, problem, options, &data.map);
  nlohmann::json row;
  row["status"] = ocp::solveStatusName(s.status);
  row["reason"] = s.reason;
  row["iterations"] = s.solver.iterations;
  row["integrations"] = s.solver.integrations;
  row["time_ms"] = s.total_time_ms;  // the initial guess and the solver
  row["cost"] = s.verified.ok ? jsonNumber(s.verified.cost) : nlohmann::json(nullptr);
  row["terminal_error_m"] =
      s.verified.ok ? jsonNumber(s.verified.terminal_error.head<2>().norm()) : nullptr;
  row["terminal_heading_error_rad"] =
      s.verified.ok ? jsonNumber(std::abs(s.verified.terminal_error.z())) : nullptr;
  return row;
}

nlohmann::json transcriptionRow(const ProblemSetData& data,
                                const ocp::BoundaryValueProblem& problem,
                                const ocp::DirectTranscriptionOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  nlohmann::json row;
  // The same information as the parametric solvers: start and goal, a straight-line guess.
  const Expected<ocp::TranscriptionGuess> guess = ocp::guessFromPath(
      {{problem.start.x, problem.start.y}, {problem.goal.x, problem.goal.y}}, problem);
  if (!guess) {
    row["status"] = "error";
    row["reason"] = "no straight-line guess: " + guess.reason();
    return row;
  }
  ocp::TranscriptionSolution solution =
      ocp::solveDirectTranscription(*data.vehicle, problem, *guess, options);
  const auto verification_started = std::chrono::steady_clock::now();
  const ocp::TranscriptionModel model(*data.vehicle, problem, options.model);
  const ocp::VerifiedTrajectory verified =
      solution.points.empty() ? ocp::VerifiedTrajectory{}
                              : ocp::verifyTranscriptionSolution(model, solution, &data.map);
  const double verification_ms = millisecondsSince(verification_started);
  ocp::SolveStatus status = solution.result.status;
  std::string reason = solution.result.reason;
  const ocp::ConvergenceCriteria criteria;
  if (status == ocp::SolveStatus::kConverged) {
    if (!verified.ok) {
      status = ocp::SolveStatus::kDiverged;
      reason = "the re-simulation failed: " + verified.message;
    } else if (verified.terminal_error.head<2>().norm() > criteria.position_m ||
               std::abs(verified.terminal_error.z()) > criteria.heading_rad) {
      status = ocp::SolveStatus::kDiverged;
      reason = "the re-simulated trajectory misses the goal";
    }
  }
  row["status"] = ocp::solveStatusName(status);
  row["reason"] = reason;
  row["iterations"] = solution.result.iterations;
  row["integrations"] = solution.result.integrations;
  // The guess and the solver, not the re-simulation (as the parametric solvers' total_time_ms).
  row["time_ms"] = millisecondsSince(started) - verification_ms;
  row["cost"] = verified.ok ? jsonNumber(verified.cost) : nlohmann::json(nullptr);
  row["terminal_error_m"] =
      verified.ok ? jsonNumber(verified.terminal_error.head<2>().norm()) : nullptr;
  row["terminal_heading_error_rad"] =
      verified.ok ? jsonNumber(std::abs(verified.terminal_error.z())) : nullptr;
  return row;
}

nlohmann::json runCase(const ProblemSetData& data, int index, const std::string& solver) {
  const ocp::BoundaryValueProblem& problem = data.problems[static_cast<std::size_t>(index)];
  ocp::DirectTranscriptionOptions options;
  if (solver == "shooting") {
    options.scheme = ocp::TranscriptionScheme::kMultipleShooting;
    return transcriptionRow(data, problem, options);
  }
  if (solver == "collocation") return transcriptionRow(data, problem, options);
  if (solver == "collocation_refined") {
    options.refinement.max_rounds = 3;
    options.refinement.tolerance = 1e-4;
    return transcriptionRow(data, problem, options);
  }
  for (const ocp::BoundaryValueMethod method :
       {ocp::BoundaryValueMethod::kNewton, ocp::BoundaryValueMethod::kNewtonFd,
        ocp::BoundaryValueMethod::kIpopt, ocp::BoundaryValueMethod::kCeres}) {
    if (solver == ocp::boundaryValueMethodName(method)) return parametricRow(data, problem, method);
  }
  return {{"status", "error"}, {"reason", "unknown solver " + solver}};
}

class ConvergenceSuite final : public BenchmarkSuite {
 public:
  explicit ConvergenceSuite(const BenchmarkSettings& settings)
      : settings_(settings), specs_(problemSets(settings)), cache_(std::make_shared<Cache>()) {}

  std::string name() const override { return "convergence"; }
  std::vector<std::filesystem::path> inputFiles() const override {
    std::vector<std::filesystem::path> files;
    if (settings_.data_dir.empty()) return files;
    for (const DemSpec& dem : kDems) files.push_back(settings_.data_dir / dem.file);
    for (const std::filesystem::path& file : robustnessInputs(settings_)) {
      if (std::find(files.begin(), files.end(), file) == files.end()) files.push_back(file);
    }
    return files;
  }

  std::vector<BenchmarkCase> cases() const override {
    std::vector<BenchmarkCase> out;
    for (std::size_t s = 0; s < specs_.size(); ++s) {
      for (int i = 0; i < specs_[s].count; ++i) {
        for (const char* solver : kSolvers) {
          const std::string set = specs_[s].name;
          out.push_back({set + "/" + std::to_string(i) + "/" + solver,
                         [this, s, i, solver = std::string(solver)] {
                           nlohmann::json row = runCase(data(s), i, solver);
                           row["set"] = specs_[s].name;
                           row["problem"] = i;
                           row["solver"] = solver;
                           row["vehicle"] = specs_[s].vehicle;
                           row["formulation"] = formulation(solver);
                           return row;
                         }});
        }
      }
    }
    // The robustness set (its rows carry "family": "robustness"; summarised apart).
    for (BenchmarkCase& c : robustnessCases(settings_)) out.push_back(std::move(c));
    return out;
  }

  nlohmann::json summarize(const nlohmann::json& all_rows) const override {
    nlohmann::json rows = nlohmann::json::array();
    for (const nlohmann::json& row : all_rows) {
      if (row.value("family", "") != "robustness") rows.push_back(row);
    }
    // The best re-simulated cost per problem among the solvers that converged on it.
    std::map<std::string, double> best;
    for (const nlohmann::json& row : rows) {
      if (row.value("status", "") != "converged" || !row["cost"].is_number()) continue;
      const std::string key = problemKey(row);
      const double cost = row["cost"].get<double>();
      auto [it, inserted] = best.emplace(key, cost);
      if (!inserted) it->second = std::min(it->second, cost);
    }
    // The paper's solver, newton_fd, is the baseline: each solver's time over its time on the
    // same problem, where both converged.
    std::map<std::string, double> baseline_ms;
    for (const nlohmann::json& row : rows) {
      if (row.value("solver", "") == "newton_fd" && row.value("status", "") == "converged") {
        baseline_ms[row.value("set", "") + "/" + std::to_string(row.value("problem", -1))] =
            row["time_ms"].get<double>();
      }
    }
    struct Tally {
      int runs = 0, converged = 0, best = 0;
      std::vector<double> iterations, time_ms, cost_ratio, over_baseline;
    };
    std::map<std::string, Tally> by_solver;
    std::map<std::string, std::map<std::string, std::pair<int, int>>> by_set;
    for (const nlohmann::json& row : rows) {
      const std::string solver = row.value("solver", "");
      Tally& t = by_solver[solver];
      ++t.runs;
      std::pair<int, int>& set = by_set[row.value("set", "")][solver];
      ++set.first;
      if (row["time_ms"].is_number()) t.time_ms.push_back(row["time_ms"].get<double>());
      if (row.value("status", "") != "converged") continue;
      ++t.converged;
      ++set.second;
      t.iterations.push_back(row["iterations"].get<double>());
      const double ratio = row["cost"].get<double>() / best.at(problemKey(row));
      t.cost_ratio.push_back(ratio);
      if (ratio <= 1.0 + 1e-3) ++t.best;
      const auto base =
          baseline_ms.find(row.value("set", "") + "/" + std::to_string(row.value("problem", -1)));
      if (base != baseline_ms.end() && base->second > 0.0) {
        t.over_baseline.push_back(row["time_ms"].get<double>() / base->second);
      }
    }
    nlohmann::json solvers = nlohmann::json::object();
    for (auto& [solver, t] : by_solver) {
      solvers[solver] = {
          {"runs", t.runs},
          {"converged", t.converged},
          {"success_rate", t.runs > 0 ? static_cast<double>(t.converged) / t.runs : 0.0},
          {"best_within_0.1_percent", t.best},
          {"iterations", distributionJson(t.iterations)},
          {"time_ms", distributionJson(t.time_ms)},
          {"cost_relative_to_best", distributionJson(t.cost_ratio)},
          {"time_over_newton_fd", distributionJson(t.over_baseline)}};
    }
    nlohmann::json sets_json = nlohmann::json::object();
    for (const auto& [set, solvers_in_set] : by_set) {
      for (const auto& [solver, counts] : solvers_in_set) {
        sets_json[set][solver] = {{"runs", counts.first}, {"converged", counts.second}};
      }
    }
    return {{"problem_formulations", best.size()},
            {"cost_compared_within",
             "formulation (parametric: newton_fd, newton, ipopt, ceres; "
             "transcription: shooting, collocation)"},
            {"solvers", solvers},
            {"sets", sets_json},
            {"robustness", summarizeRobustness(all_rows)}};
  }

  std::string summaryText(const nlohmann::json& summary) const override {
    std::ostringstream text;
    text << "solver              success   iterations (median)   time ms (median, p90)   cost / "
            "best of "
            "its formulation (mean, max)   time / newton_fd (median)\n";
    for (const char* solver : kSolvers) {
      if (!summary["solvers"].contains(solver)) continue;
      const nlohmann::json& s = summary["solvers"][solver];
      const std::size_t width = std::string(solver).size();
      text << solver << std::string(width < 20 ? 20 - width : 1, ' ') << s["converged"] << "/"
           << s["runs"] << "    " << figureText(s["iterations"], "median") << "    "
           << figureText(s["time_ms"], "median") << ", " << figureText(s["time_ms"], "p90")
           << "    " << figureText(s["cost_relative_to_best"], "mean") << ", "
           << figureText(s["cost_relative_to_best"], "max") << "    "
           << figureText(s["time_over_newton_fd"], "median") << '\n';
    }
    if (summary.contains("robustness")) text << robustnessText(summary["robustness"]);
    return text.str();
  }

 private:
  BenchmarkSettings settings_;
  struct Cache {
    std::map<std::size_t, std::unique_ptr<ProblemSetData>> sets;
  };

  // Costs are compared within a formulation: the parametric solvers hold the speed profile
  // of the polynomial controls (constant speed on these sets), the transcriptions leave the
  // speed free between the boundary speeds: different problems, different optima.
  static std::string formulation(const std::string& solver) {
    return solver == "shooting" || solver.rfind("collocation", 0) == 0 ? "transcription"
                                                                       : "parametric";
  }
  static std::string problemKey(const nlohmann::json& row) {
    return row.value("set", "") + "/" + std::to_string(row.value("problem", -1)) + "/" +
           formulation(row.value("solver", ""));
  }

  const ProblemSetData& data(std::size_t s) const {
    std::unique_ptr<ProblemSetData>& d = cache_->sets[s];
    if (!d) d = specs_[s].build();
    return *d;
  }

  std::vector<ProblemSetSpec> specs_;
  std::shared_ptr<Cache> cache_;
};

}  // namespace

std::unique_ptr<BenchmarkSuite> makeConvergenceSuite(const BenchmarkSettings& settings) {
  return std::make_unique<ConvergenceSuite>(settings);
}

}  // namespace terratraj::bench
