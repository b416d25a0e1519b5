#include "terratraj/apps/lut_commands.hpp"

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <ostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "terratraj/apps/cli.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/models/velocity_table.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
namespace {

double parseNumber(const std::string& text, const std::string& option) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value)) {
    throw InputError(option + ": '" + text + "' is not a finite number");
  }
  return value;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, separator)) parts.push_back(part);
  return parts;
}

void requireKind(const std::string& kind) {
  if (kind != "pitch" && kind != "roll_curvature") {
    throw InputError("--kind: '" + kind + "' is not a table kind (pitch, roll_curvature)");
  }
}

std::string pitchTableText(const models::PitchSpeedTable& table) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(3);
  const std::vector<double>& edges = table.pitchEdges().edges();
  text << "  pitch bin [rad]        v_max [m/s]\n";
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    text << "  [" << std::setw(7) << edges[i] << ", " << std::setw(7) << edges[i + 1] << ")   "
         << std::setw(8) << table.vMax()[i] << '\n';
  }
  return text.str();
}

std::string rollCurvatureTableText(const models::RollCurvatureSpeedTable& table) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(2);
  text << "  v_max [m/s]; rows: roll bin centre [rad]; columns: curvature bin centre [1/m]\n";
  text << "  " << std::setw(7) << "";
  for (int j = 0; j < table.curvatureEdges().binCount(); ++j) {
    text << std::setw(7) << table.curvatureEdges().centre(j);
  }
  text << '\n';
  for (int i = 0; i < table.rollEdges().binCount(); ++i) {
    text << "  " << std::setw(7) << table.rollEdges().centre(i);
    for (int j = 0; j < table.curvatureEdges().binCount(); ++j)
      text << std::setw(7) << table.vMax()(i, j);
    text << '\n';
  }
  return text.str();
}

// Writes the table of the requested kind and reports it; `build` makes it from the edges.
template <typename MakePitch, typename MakeRollCurvature>
int writeAndReport(const TableBinning& binning, const std::filesystem::path& out,
                   nlohmann::json report, CommandContext& context, MakePitch make_pitch,
                   MakeRollCurvature make_roll_curvature) {
  requireKind(binning.kind);
  std::string text;
  if (binning.kind == "pitch") {
    const models::PitchSpeedTable table = make_pitch(
        parseBinEdges(binning.pitch_edges, models::defaultPitchEdges(), "--pitch-edges"));
    models::writeTable(table, out);
    report["table"] = nlohmann::json::parse(models::tableJson(table));
    text = pitchTableText(table);
  } else {
    const models::RollCurvatureSpeedTable table = make_roll_curvature(
        parseBinEdges(binning.roll_edges, models::defaultRollEdges(), "--roll-edges"),
        parseBinEdges(binning.curvature_edges, models::defaultCurvatureEdges(),
                      "--curvature-edges"));
    models::writeTable(table, out);
    report["table"] = nlohmann::json::parse(models::tableJson(table));
    text = rollCurvatureTableText(table);
  }
  report["status"] = "ok";
  report["kind"] = binning.kind;
  report["file"] = out.string();
  if (context.json) {
    context.out << report.dump(2) << '\n';
  } else {
    context.out << "wrote " << out.string() << " (" << binning.kind << ")\n" << text;
  }
  return kExitSuccess;
}

}  // namespace

models::BinEdges parseBinEdges(const std::string& text, const models::BinEdges& fallback,
                               const std::string& option) {
  if (text.empty()) return fallback;
  const std::vector<std::string> range = split(text, ':');
  if (range.size() == 3) {
    const double bins = parseNumber(range[2], option);
    if (bins != std::floor(bins) || bins < 1 || bins > 100000) {
      throw InputError(option + ": the bin count '" + range[2] + "' must be a whole number >= 1");
    }
    return models::uniformEdges(parseNumber(range[0], option), parseNumber(range[1], option),
                                static_cast<int>(bins), option);
  }
  std::vector<double> edges;
  for (const std::string& part : split(text, ',')) edges.push_back(parseNumber(part, option));
  return models::BinEdges(std::move(edges), option);
}

int runLutBuild(const LutBuildOptions& options, CommandContext& context) {
  const models::Trajectory log = models::readTrajectoryCsv(options.log);
  const models::DrivingStates states = models::drivingStates(log, options.log.string());
  context.log->info("{}: {} states", options.log.string(), states.speed.size());
  nlohmann::json report{{"log", options.log.string()},
                        {"samples", states.speed.size()},
                        {"top_fraction", options.data.top_fraction},
                        {"fill_empty", options.data.fill_empty}};
  return writeAndReport(
      options.binning, options.out, report, context,
      [&](const models::BinEdges& pitch) {
        return models::dataPitchTable(states, pitch, options.data);
      },
      [&](const models::BinEdges& roll, const models::BinEdges& curvature) {
        return models::dataRollCurvatureTable(states, roll, curvature, options.data);
      });
}

int runLutPhysics(const LutPhysicsOptions& options, CommandContext& context) {
  const models::PhysicsTableParameters& p = options.parameters;
  if (!(p.gravity > 0 && p.half_track > 0 && p.cog_height > 0 && p.friction > 0 &&
        p.vehicle_length > 0 && p.speed_cap > 0)) {
    throw InputError("lut physics: every vehicle parameter must be > 0");
  }
  nlohmann::json report{{"parameters",
                         {{"gravity", p.gravity},
                          {"half_track_m", p.half_track},
                          {"cog_height_m", p.cog_height},
                          {"friction", p.friction},
                          {"vehicle_length_m", p.vehicle_length},
                          {"speed_cap_mps", p.speed_cap}}}};
  return writeAndReport(
      options.binning, options.out, report, context,
      [&](const models::BinEdges& pitch) { return models::physicsPitchTable(pitch, p); },
      [&](const models::BinEdges& roll, const models::BinEdges& curvature) {
        return models::physicsRollCurvatureTable(roll, curvature, p);
      });
}

int runLutCheck(const LutCheckOptions& options, CommandContext& context) {
  if (options.tables.empty() || options.tables.size() > 2) {
    throw InputError("--table: give one or two tables (a pitch and / or a roll_curvature table)");
  }
  std::optional<models::PitchSpeedTable> pitch;
  std::optional<models::RollCurvatureSpeedTable> roll_curvature;
  for (const std::filesystem::path& file : options.tables) {
    const std::string kind = models::readTableKind(file);
    if ((kind == "pitch" && pitch) || (kind == "roll_curvature" && roll_curvature)) {
      throw InputError(file.string() + ": a second " + kind +
                       " table (give at most one of each kind)");
    }
    if (kind == "pitch") {
      pitch = models::readPitchTable(file);
    } else {
      roll_curvature = models::readRollCurvatureTable(file);
    }
  }
  const models::Trajectory trajectory = models::readTrajectoryCsv(options.trajectory);
  const models::DrivingStates states =
      models::drivingStates(trajectory, options.trajectory.string());
  const models::ViolationReport report =
      models::analyseViolations(states, pitch ? &*pitch : nullptr,
                                roll_curvature ? &*roll_curvature : nullptr, options.tolerance);
  const auto fraction = [](const std::optional<double>& f) {
    return f ? nlohmann::json(*f) : nlohmann::json(nullptr);
  };
  nlohmann::json json{
      {"status", "ok"},
      {"trajectory", options.trajectory.string()},
      {"states", report.states},
      {"pitch_violation_fraction", fraction(report.pitch_fraction)},
      {"roll_curvature_violation_fraction", fraction(report.roll_curvature_fraction)},
      {"combined_violation_fraction", report.combined_fraction},
      {"max_excess_mps", report.max_excess},
      {"tolerance_mps", options.tolerance}};
  if (context.json) {
    context.out << json.dump(2) << '\n';
    return kExitSuccess;
  }
  context.out << options.trajectory.string() << ": " << report.states << " states\n"
              << std::fixed << std::setprecision(2);
  if (report.pitch_fraction) {
    context.out << "  pitch table           " << 100.0 * *report.pitch_fraction
                << " % of states too fast\n";
  }
  if (report.roll_curvature_fraction) {
    context.out << "  roll x curvature      " << 100.0 * *report.roll_curvature_fraction
                << " % of states too fast\n";
  }
  context.out << "  combined              " << 100.0 * report.combined_fraction << " %\n"
              << "  largest excess        " << report.max_excess << " m/s\n";
  return kExitSuccess;
}

int runLutSimulateLog(const LutSimulateOptions& options, CommandContext& context) {
  context.log->info("simulating {} s of driving (seed {})", options.driver.duration,
                    options.driver.seed);
  const models::Trajectory log = models::simulateDrivingLog(options.driver);
  models::writeTrajectoryCsv(log, options.out);
  if (context.json) {
    context.out << nlohmann::json{{"status", "ok"},
                                  {"file", options.out.string()},
                                  {"samples", log.samples.size()},
                                  {"seed", options.driver.seed},
                                  {"duration_s", options.driver.duration}}
                       .dump(2)
                << '\n';
  } else {
    context.out << "wrote " << options.out.string() << " (" << log.samples.size() << " samples)\n";
  }
  return kExitSuccess;
}

}  // namespace terratraj::apps
