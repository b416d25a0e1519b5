#include "terratraj/apps/plot_writer.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "terratraj/apps/plot_script.hpp"
#include "terratraj/bench/report_json.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {

using bench::jsonNumber;
namespace {

namespace fs = std::filesystem;

void writeBytes(const fs::path& file, const char* data, std::size_t size) {
  std::ofstream out(file, std::ios::binary);
  out.write(data, static_cast<std::streamsize>(size));
  if (!out) throw InputError("--plot: cannot write '" + file.string() + "'");
}

void writeText(const fs::path& file, const std::string& text) {
  writeBytes(file, text.data(), text.size());
}

// The raster (float32, little-endian on this platform, row 0 south) and its mask (0 free,
// 1 lethal, 2 no data).
void writeRaster(const terrain::ElevationMap& map, const fs::path& elevation,
                 const fs::path& mask) {
  const terrain::GridGeometry& g = map.geometry();
  std::vector<float> heights(g.cellCount());
  std::vector<unsigned char> flags(g.cellCount(), 0);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const terrain::CellIndex cell{r, c};
      const std::size_t i = g.linearIndex(cell);
      heights[i] = map.elevation()(cell);
      if (map.isNoData(cell)) {
        flags[i] = 2;
      } else if (map.isLethal(cell)) {
        flags[i] = 1;
      }
    }
  }
  writeBytes(elevation, reinterpret_cast<const char*>(heights.data()),
             heights.size() * sizeof(float));
  writeBytes(mask, reinterpret_cast<const char*>(flags.data()), flags.size());
}

nlohmann::json requestJson(const PlotRequest& request, const terrain::GridGeometry& g,
                           const fs::path& elevation, const fs::path& mask,
                           const PlotFiles& files) {
  nlohmann::json trajectories = nlohmann::json::array();
  for (const PlotTrajectory& t : request.trajectories) {
    trajectories.push_back({{"label", t.label},
                            {"csv", fs::absolute(t.csv).string()},
                            {"role", t.candidate ? "candidate" : "refined"},
                            {"group", t.group}});
  }
  nlohmann::json histories = nlohmann::json::array();
  for (const PlotHistory& h : request.histories) {
    nlohmann::json rows = nlohmann::json::array();
    for (const ocp::IterationRecord& r : h.iterations) {
      rows.push_back({{"iteration", r.iteration},
                      {"terminal_error", jsonNumber(r.terminal_error)},
                      {"cost", jsonNumber(r.cost)}});
    }
    histories.push_back({{"label", h.label}, {"iterations", rows}, {"group", h.group}});
  }
  nlohmann::json frames = nlohmann::json::array();
  for (const PlotFrame& f : request.frames) {
    frames.push_back(
        {{"name", f.name}, {"start", {f.start.x(), f.start.y()}}, {"end", {f.end.x(), f.end.y()}}});
  }
  const auto pose = [](const std::optional<PlotPose>& p) {
    return p ? nlohmann::json{{"x", p->x}, {"y", p->y}, {"heading", p->heading}}
             : nlohmann::json(nullptr);
  };
  const models::VehicleLimits& l = request.limits;
  return {{"title", request.title},
          {"map",
           {{"rows", g.rows},
            {"cols", g.cols},
            {"cell", g.cell},
            {"elevation", fs::absolute(elevation).string()},
            {"mask", fs::absolute(mask).string()}}},
          {"trajectories", trajectories},
          {"histories", histories},
          {"frames", frames},
          {"start", pose(request.start)},
          {"goal", pose(request.goal)},
          {"limits",
           {{"v_max", l.v_max},
            {"omega_max", l.omega_max},
            {"pitch_max", l.pitch_max},
            {"roll_max", l.roll_max}}},
          {"tolerance_position_m", request.tolerance_position_m},
          {"outputs",
           {{"map", fs::absolute(files.map).string()},
            {"profiles", fs::absolute(files.profiles).string()},
            {"convergence", fs::absolute(files.convergence).string()}}}};
}

// Runs `python script request` with stdout and stderr to `log`; its exit status, or -1 when it
// could not be started.
int runPython(const std::string& python, const fs::path& script, const fs::path& request,
              const fs::path& log) {
  // Everything the child needs is prepared before fork(): it only redirects and execs.
  const std::string script_path = script.string(), request_path = request.string();
  char* const argv[] = {const_cast<char*>(python.c_str()), const_cast<char*>(script_path.c_str()),
                        const_cast<char*>(request_path.c_str()), nullptr};
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return -1;
  const pid_t pid = fork();
  if (pid < 0) {
    ::close(fd);
    return -1;
  }
  if (pid == 0) {
    if (dup2(fd, STDOUT_FILENO) < 0 || dup2(fd, STDERR_FILENO) < 0) _exit(126);
    execv(python.c_str(), argv);
    _exit(127);
  }
  ::close(fd);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string readLog(const fs::path& log) {
  std::ifstream in(log);
  std::ostringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  constexpr std::size_t kMaxChars = 2000;
  if (s.size() > kMaxChars) s = "..." + s.substr(s.size() - kMaxChars);
  return s;
}

// Writes `script` into `work` and runs it on `request_file` with Debian's python3 (or
// $TERRATRAJ_PYTHON); "" on success, else why it failed (the package to install, or the
// script's output).
std::string runPlotScript(const char* script_text, const fs::path& work,
                          const fs::path& request_file, CommandContext& context) {
  const fs::path script = work / "plot.py", log = work / "plot.log";
  writeText(script, script_text);
  const char* configured = std::getenv("TERRATRAJ_PYTHON");
  const std::string python =
      configured != nullptr && *configured != '\0' ? configured : "/usr/bin/python3";
  context.log->info("plotting with {} ({})", python, request_file.string());
  const int status = runPython(python, script, request_file, log);
  if (status == 0) return "";
  const std::string output = readLog(log);
  std::string why;
  if (status == 127 || status < 0) {
    why = "cannot run " + python + " (install Debian's python3, or set TERRATRAJ_PYTHON)";
  } else if (output.find("No module named") != std::string::npos) {
    why = python + " lacks numpy or matplotlib (apt-get install python3-matplotlib): " + output;
  } else {
    why = "the plotting script failed (exit " + std::to_string(status) + "; request in " +
          request_file.string() + "): " + output;
  }
  context.log->warn("--plot: {}", why);
  return why;
}

}  // namespace

std::vector<PlotFrame> plotFrames(const search::ReferenceFrames& frames) {
  std::vector<PlotFrame> out;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    out.push_back({search::HomotopySignature::frameName(static_cast<int>(k)),
                   frames.frames()[k].start, frames.frames()[k].end});
  }
  return out;
}

PlotFiles plotFiles(const fs::path& png) {
  const fs::path dir = png.parent_path();
  const std::string stem = png.stem().string();
  return {png, dir / (stem + "-profiles.png"), dir / (stem + "-convergence.png")};
}

nlohmann::json PlotOutcome::toJson() const {
  if (!files) return {{"status", "error"}, {"error", error}};
  return {{"status", "ok"},
          {"map", files->map.string()},
          {"profiles", files->profiles.string()},
          {"convergence", files->convergence.string()}};
}

PlotOutcome writePlots(const PlotRequest& request, const terrain::ElevationMap& map,
                       const fs::path& png, CommandContext& context) {
  const PlotFiles files = plotFiles(png);
  const fs::path work = png.parent_path() / (png.stem().string() + "-plot");
  std::error_code error;
  fs::create_directories(work, error);
  if (error) {
    throw InputError("--plot: cannot create '" + work.string() + "': " + error.message());
  }
  const fs::path elevation = work / "elevation.f32", mask = work / "mask.u8";
  const fs::path request_file = work / "request.json";
  writeRaster(map, elevation, mask);
  writeText(request_file, requestJson(request, map.geometry(), elevation, mask, files).dump(1));

  PlotOutcome outcome;
  outcome.error = runPlotScript(detail::kPlotScript, work, request_file, context);
  if (outcome.error.empty()) outcome.files = files;
  return outcome;
}

BenchPlotOutcome writeBenchPlots(const fs::path& result_file, const fs::path& png,
                                 CommandContext& context) {
  const fs::path work = png.parent_path() / (png.stem().string() + "-plot");
  std::error_code error;
  fs::create_directories(work, error);
  if (error) {
    throw InputError("--plot: cannot create '" + work.string() + "': " + error.message());
  }
  const fs::path request_file = work / "request.json", listing = work / "files.json";
  fs::remove(listing, error);
  writeText(request_file, nlohmann::json{{"result", fs::absolute(result_file).string()},
                                         {"png", fs::absolute(png).string()},
                                         {"files", fs::absolute(listing).string()}}
                              .dump(1));
  BenchPlotOutcome outcome;
  outcome.error = runPlotScript(detail::kBenchPlotScript, work, request_file, context);
  if (!outcome.error.empty()) return outcome;
  try {
    std::ifstream in(listing);
    for (const nlohmann::json& file : nlohmann::json::parse(in)) {
      outcome.files.emplace_back(file.get<std::string>());
    }
  } catch (const std::exception&) {
    outcome.error = "the plotting script wrote no list of figures (" + listing.string() + ")";
  }
  return outcome;
}

}  // namespace terratraj::apps
