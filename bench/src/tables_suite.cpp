// `terratraj bench tables`: 003_... IV: plans with physics-derived against data-driven speed
// tables. The data-driven tables come from a simulated driving log (what drivers did); each
// plan's trajectory is measured against both: traversal time and the fraction of its states
// faster than a table allows. Plans without tables are the reference.

#include <sstream>

#include "terratraj/bench/benchmark_suite.hpp"
#include "terratraj/bench/benchmark_world.hpp"
#include "terratraj/bench/report_json.hpp"
#include "terratraj/models/driving_log_simulator.hpp"
#include "terratraj/models/kinodynamic_tables.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/search/trajectory_checker.hpp"

namespace terratraj::bench {
namespace {

const char* const kTableKinds[] = {"none", "physics", "data"};

// The two pairs of tables (pitch; roll x curvature), built once per process.
struct Tables {
  models::PitchSpeedTable physics_pitch, data_pitch;
  models::RollCurvatureSpeedTable physics_roll, data_roll;
  std::size_t log_states = 0;
};

const Tables& tables(std::uint64_t seed) {
  static std::map<std::uint64_t, std::unique_ptr<Tables>> cache;
  std::unique_ptr<Tables>& t = cache[seed];
  if (t) return *t;
  t = std::make_unique<Tables>();
  const models::PhysicsTableParameters physics;
  t->physics_pitch = models::physicsPitchTable(models::defaultPitchEdges(), physics);
  t->physics_roll = models::physicsRollCurvatureTable(models::defaultRollEdges(),
                                                      models::defaultCurvatureEdges(), physics);
  models::DrivingLogOptions log_options;
  log_options.seed = seed;
  const models::DrivingStates states =
      models::drivingStates(models::simulateDrivingLog(log_options), "simulated log");
  models::DataTableOptions data;
  data.fill_empty = true;
  t->data_pitch = models::dataPitchTable(states, models::defaultPitchEdges(), data);
  t->data_roll = models::dataRollCurvatureTable(states, models::defaultRollEdges(),
                                                models::defaultCurvatureEdges(), data);
  t->log_states = states.speed.size();
  return *t;
}

// The 003 vehicle's envelope: fast enough that the tables, not v_max, decide the speed.
models::VehicleLimits fastLimits() {
  models::VehicleLimits limits = bench::benchmarkLimits(25.0);
  limits.v_max = 8.0;
  limits.a_max = 1.5;
  limits.omega_max = 2.0;
  limits.kappa_max = 0.8;
  limits.sigma_max = 0.4;
  return limits;
}

nlohmann::json measure(const models::Trajectory& trajectory, const Tables& t) {
  const models::DrivingStates states = models::drivingStates(trajectory, "plan");
  const models::ViolationReport data =
      models::analyseViolations(states, &t.data_pitch, &t.data_roll, 1e-6);
  const models::ViolationReport physics =
      models::analyseViolations(states, &t.physics_pitch, &t.physics_roll, 1e-6);
  return {{"states", states.speed.size()},
          {"violating_data_tables", data.combined_fraction},
          {"violating_data_pitch_table", data.pitch_fraction.value_or(0.0)},
          {"violating_data_roll_curvature_table", data.roll_curvature_fraction.value_or(0.0)},
          {"violating_physics_tables", physics.combined_fraction},
          {"max_excess_over_data_mps", data.max_excess}};
}

class TablesSuite final : public BenchmarkSuite {
 public:
  explicit TablesSuite(const BenchmarkSettings& settings) : settings_(settings) {}

  std::string name() const override { return "tables"; }

  std::vector<BenchmarkCase> cases() const override {
    std::vector<BenchmarkCase> out;
    const int problems = settings_.quick ? 2 : 5;
    for (int p = 0; p < problems; ++p) {
      for (int k = 0; k < settings_.seeds; ++k) {
        for (const char* kind : kTableKinds) {
          const std::uint64_t map_seed = settings_.seed + static_cast<std::uint64_t>(p);
          const std::uint64_t planner_seed = settings_.seed + static_cast<std::uint64_t>(k);
          std::ostringstream id;
          id << "hills" << map_seed << "/seed" << planner_seed << "/" << kind;
          out.push_back({id.str(), [this, map_seed, planner_seed, kind = std::string(kind)] {
                           return run(map_seed, planner_seed, kind);
                         }});
        }
      }
    }
    return out;
  }

  nlohmann::json summarize(const nlohmann::json& rows) const override {
    std::map<std::string, std::map<std::string, std::vector<double>>> values;
    std::map<std::string, int> runs, solved, any_violation;
    // Paired problems (same map and planner seed): traversal times with each kind of table.
    std::map<std::string, std::map<std::string, double>> paired;
    for (const nlohmann::json& row : rows) {
      const std::string kind = row.value("tables", "");
      ++runs[kind];
      if (row.value("status", "") != "solved") continue;
      ++solved[kind];
      for (const char* key :
           {"traversal_time_s", "violating_data_tables", "violating_data_pitch_table",
            "violating_data_roll_curvature_table", "violating_physics_tables"}) {
        values[kind][key].push_back(row[key].get<double>());
      }
      any_violation[kind] += row["violating_data_tables"].get<double>() > 0.0;
      const std::string problem = std::to_string(row["map_seed"].get<std::uint64_t>()) + "/" +
                                  std::to_string(row["seed"].get<std::uint64_t>());
      paired[problem][kind] = row["traversal_time_s"].get<double>();
    }
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [kind, n] : runs) {
      out[kind] = {{"runs", n},
                   {"solved", solved[kind]},
                   {"trajectories_violating_data_tables", any_violation[kind]}};
      for (auto& [key, v] : values[kind]) out[kind][key] = distributionJson(v);
    }
    int pairs = 0, data_faster = 0;
    for (const auto& [problem, times] : paired) {
      if (times.count("data") == 0 || times.count("physics") == 0) continue;
      ++pairs;
      data_faster += times.at("data") < times.at("physics");
    }
    return {{"by_tables", out},
            {"physics_data_pairs", pairs},
            {"data_faster_than_physics",
             pairs > 0 ? nlohmann::json(static_cast<double>(data_faster) / pairs)
                       : nlohmann::json(nullptr)}};
  }

  std::string summaryText(const nlohmann::json& summary) const override {
    std::ostringstream text;
    text << "tables    solved   traversal s (mean)   states over data tables (mean)   over "
            "physics tables (mean)\n";
    const auto mean = [](const nlohmann::json& s, const char* key) {
      return figureText(s.value(key, nlohmann::json::object()), "mean");
    };
    for (const auto& [kind, s] : summary["by_tables"].items()) {
      text << kind << std::string(10 - std::min<std::size_t>(kind.size(), 9), ' ') << s["solved"]
           << "/" << s["runs"] << "      " << mean(s, "traversal_time_s") << "      "
           << mean(s, "violating_data_tables") << "      " << mean(s, "violating_physics_tables")
           << '\n';
    }
    text << "data-table plans faster than physics-table plans: fraction "
         << summary["data_faster_than_physics"] << " of " << summary["physics_data_pairs"]
         << " paired problems\n";
    return text.str();
  }

 private:
  nlohmann::json run(std::uint64_t map_seed, std::uint64_t planner_seed,
                     const std::string& kind) const {
    const int size = settings_.quick ? 128 : 256;
    const double budget = settings_.quick ? 0.3 : 1.0;
    nlohmann::json row = {{"tables", kind},        {"map_seed", map_seed},
                          {"seed", planner_seed},  {"map_cells", size},
                          {"budget_s", budget},    {"log_seed", settings_.seed},
                          {"time_dependent", true}};
    const Tables& t = tables(settings_.seed);
    row["log_states"] = t.log_states;
    bench::BenchmarkWorld w(
        bench::generateBenchmarkMap(terrain::TerrainKind::kHills, size, map_seed),
        bench::BenchmarkVehicle::kPoint, fastLimits());
    if (kind == "physics") {
      w.problem.pitch_table = &t.physics_pitch;
      w.problem.roll_curvature_table = &t.physics_roll;
    } else if (kind == "data") {
      w.problem.pitch_table = &t.data_pitch;
      w.problem.roll_curvature_table = &t.data_roll;
    }
    const auto [start, goal] = terrain::standardStartGoal(w.map.geometry());
    if (!w.place(start, goal)) {
      row["status"] = "no start / goal on moderate ground";
      return row;
    }
    search::PrmOptions options;
    options.seed = planner_seed;
    search::KinodynamicPrm planner(w.problem, options);
    const search::PlanResult r = planner.solve(search::TerminationCondition::timeLimit(budget));
    row["status"] = search::planStatusName(r.status);
    if (r.status != search::PlanStatus::kSolved) return row;
    row["traversal_time_s"] = r.best_cost_s;
    row["length_m"] = r.length_m;
    row.update(measure(r.trajectory, t));
    search::CheckTolerances tolerances;
    tolerances.relative = 1e-3;
    row["check_ok"] = search::TrajectoryChecker(w.problem, tolerances).check(r.trajectory).ok();
    return row;
  }

  BenchmarkSettings settings_;
};

}  // namespace

std::unique_ptr<BenchmarkSuite> makeTablesSuite(const BenchmarkSettings& settings) {
  return std::make_unique<TablesSuite>(settings);
}

}  // namespace terratraj::bench
