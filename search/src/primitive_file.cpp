#include "terratraj/search/primitive_file.hpp"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::search {
namespace {

constexpr const char* kFormat = "terratraj-primitives";
constexpr int kVersion = 1;

std::string where(const std::filesystem::path& path, const std::string& key) {
  return path.string() + ": " + key;
}

double number(const nlohmann::json& object, const char* key, const std::filesystem::path& path,
              const std::string& context) {
  if (!object.contains(key) || !object.at(key).is_number()) {
    throw InputError(where(path, context + key) + ": missing or not a number");
  }
  return object.at(key).get<double>();
}

int integer(const nlohmann::json& object, const char* key, const std::filesystem::path& path,
            const std::string& context) {
  if (!object.contains(key) || !object.at(key).is_number_integer()) {
    throw InputError(where(path, context + key) + ": missing or not an integer");
  }
  return object.at(key).get<int>();
}

std::vector<double> numbers(const nlohmann::json& object, const char* key,
                            const std::filesystem::path& path, const std::string& context) {
  if (!object.contains(key) || !object.at(key).is_array()) {
    throw InputError(where(path, context + key) + ": missing or not an array");
  }
  std::vector<double> out;
  for (const nlohmann::json& item : object.at(key)) {
    if (!item.is_number()) throw InputError(where(path, context + key) + ": not a number array");
    out.push_back(item.get<double>());
  }
  return out;
}

// FNV-1a over the bytes of a value.
class Hasher {
 public:
  template <typename T>
  void add(const T& value) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    for (unsigned char b : bytes) hash_ = (hash_ ^ b) * 1099511628211ull;
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 1469598103934665603ull;
};

}  // namespace

void writePrimitiveFile(const PrimitiveSet& set, const std::filesystem::path& path) {
  nlohmann::json primitives = nlohmann::json::array();
  for (const auto& list : set.by_heading) {
    for (const MotionPrimitive& p : list) {
      nlohmann::json t = nlohmann::json::array(), s = t, x = t, y = t, heading = t, curvature = t;
      for (const PrimitiveSample& q : p.samples) {
        t.push_back(q.t);
        s.push_back(q.s);
        x.push_back(q.x);
        y.push_back(q.y);
        heading.push_back(q.heading);
        curvature.push_back(q.curvature);
      }
      primitives.push_back({{"start_heading", p.start_heading},
                            {"end_heading", p.end_heading},
                            {"offset", {p.offset.x(), p.offset.y()}},
                            {"length_m", p.length},
                            {"duration_s", p.duration},
                            {"t", t},
                            {"s", s},
                            {"x", x},
                            {"y", y},
                            {"heading", heading},
                            {"curvature", curvature}});
    }
  }
  const PrimitiveGenerationInfo& g = set.generation;
  const nlohmann::json json{
      {"format", kFormat},
      {"version", kVersion},
      {"lattice",
       {{"resolution_m", set.lattice.resolution}, {"heading_count", set.lattice.heading_count}}},
      {"sample_spacing_m", set.sample_spacing},
      {"generation",
       {{"speed", g.speed},
        {"kappa_max", g.kappa_max},
        {"sigma_max", g.sigma_max},
        {"omega_max", g.omega_max},
        {"turns", g.turns},
        {"solves", g.solves},
        {"failures", g.failures},
        {"time_ms", g.generation_time_ms}}},
      {"primitives", primitives}};
  std::error_code error;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), error);
  const std::filesystem::path temporary = path.string() + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(temporary);
    if (!out) throw InputError(path.string() + ": cannot write the primitive file");
    out << json.dump();
    if (!out) throw InputError(path.string() + ": cannot write the primitive file");
  }
  std::filesystem::rename(temporary, path, error);  // atomic: readers never see half a file
  if (error)
    throw InputError(path.string() + ": cannot write the primitive file: " + error.message());
}

PrimitiveSet readPrimitiveFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open the primitive file");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": not valid JSON: " + e.what());
  }
  if (!json.is_object() || !json.contains("format") || json.at("format") != kFormat) {
    throw InputError(where(path, "format") + ": expected \"" + kFormat + "\"");
  }
  if (integer(json, "version", path, "") != kVersion) {
    throw InputError(where(path, "version") + ": unsupported (expected " +
                     std::to_string(kVersion) + ")");
  }
  PrimitiveSet set;
  if (!json.contains("lattice") || !json.at("lattice").is_object()) {
    throw InputError(where(path, "lattice") + ": missing or not an object");
  }
  const nlohmann::json& lattice = json.at("lattice");
  set.lattice.resolution = number(lattice, "resolution_m", path, "lattice.");
  set.lattice.heading_count = integer(lattice, "heading_count", path, "lattice.");
  if (const std::optional<std::string> error = set.lattice.validate()) {
    throw InputError(where(path, "lattice." + *error));
  }
  set.sample_spacing = number(json, "sample_spacing_m", path, "");
  if (json.contains("generation") && json.at("generation").is_object()) {
    const nlohmann::json& g = json.at("generation");
    set.generation.speed = number(g, "speed", path, "generation.");
    set.generation.kappa_max = number(g, "kappa_max", path, "generation.");
    set.generation.sigma_max = number(g, "sigma_max", path, "generation.");
    set.generation.omega_max = number(g, "omega_max", path, "generation.");
    if (g.contains("solves") && g.at("solves").is_number_integer()) {
      set.generation.solves = g.at("solves").get<int>();
    }
    if (g.contains("failures") && g.at("failures").is_number_integer()) {
      set.generation.failures = g.at("failures").get<int>();
    }
    if (g.contains("time_ms") && g.at("time_ms").is_number()) {
      set.generation.generation_time_ms = g.at("time_ms").get<double>();
    }
    if (g.contains("turns") && g.at("turns").is_array()) {
      for (const nlohmann::json& t : g.at("turns")) {
        if (t.is_number_integer()) set.generation.turns.push_back(t.get<int>());
      }
    }
  }
  if (!json.contains("primitives") || !json.at("primitives").is_array()) {
    throw InputError(where(path, "primitives") + ": missing or not an array");
  }
  set.by_heading.assign(set.lattice.heading_count, {});
  std::size_t index = 0;
  for (const nlohmann::json& item : json.at("primitives")) {
    const std::string context = "primitives[" + std::to_string(index++) + "].";
    if (!item.is_object()) throw InputError(where(path, context) + " not an object");
    MotionPrimitive p;
    p.start_heading = integer(item, "start_heading", path, context);
    p.end_heading = integer(item, "end_heading", path, context);
    if (p.start_heading < 0 || p.start_heading >= set.lattice.heading_count) {
      throw InputError(where(path, context + "start_heading") + ": out of range [0, " +
                       std::to_string(set.lattice.heading_count) + ")");
    }
    if (!item.contains("offset") || !item.at("offset").is_array() ||
        item.at("offset").size() != 2 || !item.at("offset")[0].is_number_integer() ||
        !item.at("offset")[1].is_number_integer()) {
      throw InputError(where(path, context + "offset") + ": expected two integers");
    }
    p.offset = {item.at("offset")[0].get<int>(), item.at("offset")[1].get<int>()};
    const std::vector<double> t = numbers(item, "t", path, context);
    const std::vector<double> s = numbers(item, "s", path, context);
    const std::vector<double> x = numbers(item, "x", path, context);
    const std::vector<double> y = numbers(item, "y", path, context);
    const std::vector<double> heading = numbers(item, "heading", path, context);
    const std::vector<double> curvature = numbers(item, "curvature", path, context);
    const std::size_t n = t.size();
    if (s.size() != n || x.size() != n || y.size() != n || heading.size() != n ||
        curvature.size() != n) {
      throw InputError(where(path, context) +
                       " sample arrays t, s, x, y, heading, curvature "
                       "differ in length");
    }
    for (std::size_t i = 0; i < n; ++i) {
      p.samples.push_back({s[i], t[i], x[i], y[i], heading[i], curvature[i]});
    }
    if (n >= 2) {
      p.length = s.back();
      p.duration = t.back();
      for (std::size_t i = 0; i < n; ++i) {
        p.max_abs_curvature = std::max(p.max_abs_curvature, std::abs(curvature[i]));
        if (i > 0 && s[i] > s[i - 1]) {
          p.max_abs_curvature_rate =
              std::max(p.max_abs_curvature_rate,
                       std::abs(curvature[i] - curvature[i - 1]) / (s[i] - s[i - 1]));
        }
      }
    }
    set.by_heading[p.start_heading].push_back(std::move(p));
  }
  return set;
}

std::string primitiveCacheName(const LatticeSpec& lattice, const models::VehicleLimits& limits,
                               const PrimitiveGenerationOptions& options) {
  Hasher h;
  h.add(kVersion);
  h.add(lattice.resolution);
  h.add(lattice.heading_count);
  h.add(options.speed > 0.0 ? options.speed : limits.v_max);
  h.add(limits.kappa_max);
  h.add(limits.sigma_max);
  h.add(limits.omega_max);
  for (int t : options.turns) h.add(t);
  h.add(-999);
  for (double l : options.straight_lengths) h.add(l);
  h.add(options.length_margin);
  h.add(options.attempts);
  h.add(options.sample_spacing);
  h.add(options.max_iterations);
  std::ostringstream name;
  name << "primitives-" << std::hex << std::setw(16) << std::setfill('0') << h.value() << ".json";
  return name.str();
}

const char* primitiveSourceName(PrimitiveSource source) {
  switch (source) {
    case PrimitiveSource::kFile:
      return "file";
    case PrimitiveSource::kCache:
      return "cache";
    case PrimitiveSource::kGenerated:
      return "generated";
  }
  return "unknown";
}

LoadedPrimitives loadOrGeneratePrimitives(const LatticeSpec& lattice,
                                          const models::VehicleLimits& limits,
                                          const PrimitiveGenerationOptions& options,
                                          const std::filesystem::path& file,
                                          const std::filesystem::path& cache_dir) {
  LoadedPrimitives loaded;
  if (!file.empty()) {
    if (!std::filesystem::exists(file)) {
      throw InputError(file.string() +
                       ": primitive file not found (generate one with `terratraj primitives "
                       "PROBLEM.yaml --out FILE`, or remove the key to use the cache)");
    }
    loaded.set = readPrimitiveFile(file);
    if (const std::optional<std::string> error = loaded.set.checkAgainst(lattice, &limits)) {
      throw InputError(file.string() + ": inconsistent with the lattice: " + *error);
    }
    loaded.source = PrimitiveSource::kFile;
    loaded.path = file;
    return loaded;
  }
  const std::filesystem::path cached =
      cache_dir.empty() ? std::filesystem::path()
                        : cache_dir / primitiveCacheName(lattice, limits, options);
  if (!cached.empty() && std::filesystem::exists(cached)) {
    try {
      PrimitiveSet set = readPrimitiveFile(cached);
      if (!set.checkAgainst(lattice, &limits)) {
        loaded.set = std::move(set);
        loaded.source = PrimitiveSource::kCache;
        loaded.path = cached;
        return loaded;
      }
      loaded.cache_note = cached.string() + ": stale, regenerated";
    } catch (const InputError& e) {
      loaded.cache_note = std::string(e.what()) + " (regenerated)";
    }
  }
  PrimitiveGenerationResult generated = generatePrimitives(lattice, limits, options);
  if (const std::optional<std::string> error = generated.set.checkAgainst(lattice, &limits)) {
    std::string message = "motion primitives: generation failed: " + *error;
    for (const std::string& f : generated.failures) message += "; " + f;
    throw InputError(message);
  }
  loaded.set = std::move(generated.set);
  loaded.source = PrimitiveSource::kGenerated;
  if (cached.empty()) {
    loaded.cache_note = "no cache directory";
    return loaded;
  }
  try {
    writePrimitiveFile(loaded.set, cached);
    loaded.path = cached;
  } catch (const InputError& e) {
    loaded.cache_note = e.what();
  }
  return loaded;
}

}  // namespace terratraj::search
