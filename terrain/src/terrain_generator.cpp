#include "terratraj/terrain/terrain_generator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <sstream>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::terrain {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kClearRadius = 3.0;  // [m] kept free around the standard start and goal

struct KindInfo {
  TerrainKind kind;
  const char* name;
  const char* description;
};

constexpr std::array<KindInfo, 8> kKinds{{
    {TerrainKind::kFlat, "flat", "level ground at height 0"},
    {TerrainKind::kRamp, "ramp", "a plane rising 10 degrees toward +x (east)"},
    {TerrainKind::kHill, "hill", "one Gaussian hill in the middle (the slope-dwell experiment)"},
    {TerrainKind::kHills, "hills", "hills and valleys: random Gaussian bumps and hollows"},
    {TerrainKind::kCorridor, "corridor",
     "gentle hills crossed by north-south walls, each passable only through a narrow corridor"},
    {TerrainKind::kObstacles, "obstacles",
     "hills with random lethal boulders (about 12 % of the area)"},
    {TerrainKind::kDeadEnd, "dead_end",
     "hills with U-shaped lethal traps opening toward the start (west)"},
    {TerrainKind::kForest, "forest", "gentle ground with many small lethal clusters (tree trunks)"},
}};

// Uniform reals from the raw 64-bit output of mt19937_64: the same on every platform.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  bool coin() { return (engine_() >> 63) != 0; }

 private:
  std::mt19937_64 engine_;
};

// Adds amplitude * exp(-r^2 / (2 sigma^2)) around (cx, cy), over a 4-sigma window.
void addGaussian(ElevationMap& map, double cx, double cy, double sigma, double amplitude) {
  const GridGeometry& g = map.geometry();
  const double reach = 4.0 * sigma;
  const int c0 = std::max(0, static_cast<int>(std::floor((cx - reach) / g.cell)));
  const int c1 = std::min(g.cols - 1, static_cast<int>(std::ceil((cx + reach) / g.cell)));
  const int r0 = std::max(0, static_cast<int>(std::floor((cy - reach) / g.cell)));
  const int r1 = std::min(g.rows - 1, static_cast<int>(std::ceil((cy + reach) / g.cell)));
  const double inv_two_var = 1.0 / (2.0 * sigma * sigma);
  GridLayer& z = map.elevation();
  for (int r = r0; r <= r1; ++r) {
    const double dy = (r + 0.5) * g.cell - cy;
    for (int c = c0; c <= c1; ++c) {
      const double dx = (c + 0.5) * g.cell - cx;
      z(r, c) += static_cast<float>(amplitude * std::exp(-(dx * dx + dy * dy) * inv_two_var));
    }
  }
}

// Random hills (positive) and valleys (negative); `relief` scales their height-to-width ratio.
void addHillsAndValleys(ElevationMap& map, Random& random, double relief) {
  const GridGeometry& g = map.geometry();
  const double area = g.width() * g.height();
  const int count = std::max(4, static_cast<int>(area / 100.0));
  const double max_sigma = std::max(0.5, std::min({6.0, g.width() / 4.0, g.height() / 4.0}));
  const double min_sigma = std::min(2.0, max_sigma / 2.0);
  for (int i = 0; i < count; ++i) {
    const double cx = random.uniform(0.0, g.width());
    const double cy = random.uniform(0.0, g.height());
    const double sigma = random.uniform(min_sigma, max_sigma);
    const double sign = random.coin() ? 1.0 : -1.0;
    addGaussian(map, cx, cy, sigma, sign * relief * sigma * random.uniform(0.15, 0.5));
  }
}

GridLayer& lethalLayer(ElevationMap& map) { return map.addLayer(layer_names::kLethal, 0.0f); }

// Marks cells whose centres fall in an axis-aligned rectangle [x0, x1] x [y0, y1] (local m).
void markRectangle(ElevationMap& map, double x0, double y0, double x1, double y1) {
  const GridGeometry& g = map.geometry();
  GridLayer& lethal = lethalLayer(map);
  const int c0 = std::max(0, static_cast<int>(std::ceil(x0 / g.cell - 0.5)));
  const int c1 = std::min(g.cols - 1, static_cast<int>(std::floor(x1 / g.cell - 0.5)));
  const int r0 = std::max(0, static_cast<int>(std::ceil(y0 / g.cell - 0.5)));
  const int r1 = std::min(g.rows - 1, static_cast<int>(std::floor(y1 / g.cell - 0.5)));
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) lethal(r, c) = 1.0f;
  }
}

// Sets cells whose centres lie within `radius` of (cx, cy) to `value` (at least the nearest).
void paintDisk(ElevationMap& map, double cx, double cy, double radius, float value) {
  const GridGeometry& g = map.geometry();
  GridLayer& lethal = lethalLayer(map);
  const double reach = radius + g.cell;
  const int c0 = std::max(0, static_cast<int>(std::floor((cx - reach) / g.cell)));
  const int c1 = std::min(g.cols - 1, static_cast<int>(std::ceil((cx + reach) / g.cell)));
  const int r0 = std::max(0, static_cast<int>(std::floor((cy - reach) / g.cell)));
  const int r1 = std::min(g.rows - 1, static_cast<int>(std::ceil((cy + reach) / g.cell)));
  const double r_eff = std::max(radius, 0.5 * g.cell);
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      const double dx = (c + 0.5) * g.cell - cx;
      const double dy = (r + 0.5) * g.cell - cy;
      if (dx * dx + dy * dy <= r_eff * r_eff) lethal(r, c) = value;
    }
  }
}

void clearStartAndGoal(ElevationMap& map) {
  const auto [start, goal] = standardStartGoal(map.geometry());
  paintDisk(map, start.x(), start.y(), kClearRadius, 0.0f);
  paintDisk(map, goal.x(), goal.y(), kClearRadius, 0.0f);
}

void generateRamp(ElevationMap& map) {
  const double rise = std::tan(10.0 * kPi / 180.0);
  const GridGeometry& g = map.geometry();
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c)
      map.elevation()(r, c) = static_cast<float>(rise * (c + 0.5) * g.cell);
  }
}

void generateHill(ElevationMap& map) {
  const GridGeometry& g = map.geometry();
  const double sigma = 0.1 * std::min(g.width(), g.height());
  addGaussian(map, 0.5 * g.width(), 0.5 * g.height(), sigma, 0.5 * sigma);
}

// North-south walls 2 m thick, evenly spaced between the start and goal zones, each with one
// 1.5 m gap: the only ways east are narrow 2 m long corridors.
void generateCorridors(ElevationMap& map, Random& random) {
  const GridGeometry& g = map.geometry();
  addHillsAndValleys(map, random, 0.3);
  const double thickness = 2.0, gap = 1.5;
  const double first = 0.1 * g.width() + kClearRadius + thickness;
  const double last = 0.9 * g.width() - kClearRadius - thickness;
  const int walls = std::max(1, static_cast<int>((last - first) / 10.0));
  for (int i = 0; i < walls; ++i) {
    const double x = walls == 1 ? 0.5 * g.width() : first + (last - first) * i / (walls - 1);
    const double gap_y = random.uniform(0.15 * g.height(), 0.85 * g.height() - gap);
    markRectangle(map, x - 0.5 * thickness, 0.0, x + 0.5 * thickness, gap_y);
    markRectangle(map, x - 0.5 * thickness, gap_y + gap, x + 0.5 * thickness, g.height());
  }
}

void generateObstacles(ElevationMap& map, Random& random) {
  const GridGeometry& g = map.geometry();
  addHillsAndValleys(map, random, 0.5);
  const double target = 0.12 * g.width() * g.height();
  double covered = 0.0;
  const int max_boulders = 1 + static_cast<int>(g.width() * g.height());  // ends the loop always
  for (int i = 0; i < max_boulders && covered < target; ++i) {
    const double radius = random.uniform(0.5, 2.5);
    paintDisk(map, random.uniform(0.0, g.width()), random.uniform(0.0, g.height()), radius, 1.0f);
    covered += kPi * radius * radius;
  }
}

// A U-shaped wall opening toward -x: back wall at x0 + depth, arms along y0 and y0 + width.
void markCup(ElevationMap& map, double x0, double y0, double width, double depth) {
  const double t = 0.75;
  markRectangle(map, x0, y0 - t, x0 + depth + t, y0);
  markRectangle(map, x0, y0 + width, x0 + depth + t, y0 + width + t);
  markRectangle(map, x0 + depth, y0 - t, x0 + depth + t, y0 + width + t);
}

void generateDeadEnds(ElevationMap& map, Random& random) {
  const GridGeometry& g = map.geometry();
  addHillsAndValleys(map, random, 0.4);
  // One trap straight across the line from start to goal, then random ones.
  const double main_width = std::min(8.0, 0.4 * g.height());
  const double main_depth = std::min(8.0, 0.3 * g.width());
  markCup(map, 0.5 * g.width() - 0.5 * main_depth, 0.5 * (g.height() - main_width), main_width,
          main_depth);
  const int extra = static_cast<int>(g.width() * g.height() / 400.0);
  for (int i = 0; i < extra; ++i) {
    const double width = random.uniform(4.0, 8.0);
    const double depth = random.uniform(4.0, 8.0);
    markCup(map, random.uniform(0.15 * g.width(), 0.85 * g.width() - depth),
            random.uniform(0.0, g.height() - width), width, depth);
  }
}

// Trunks of radius 0.15-0.5 m, about one per 20 m^2, at least 1 m apart (edge to edge).
void generateForest(ElevationMap& map, Random& random) {
  const GridGeometry& g = map.geometry();
  addHillsAndValleys(map, random, 0.2);
  struct Trunk {
    double x, y, r;
  };
  std::vector<Trunk> trunks;
  const int wanted = static_cast<int>(g.width() * g.height() / 20.0);
  const int attempts = 20 * wanted;
  for (int i = 0; i < attempts && static_cast<int>(trunks.size()) < wanted; ++i) {
    const Trunk t{random.uniform(0.0, g.width()), random.uniform(0.0, g.height()),
                  random.uniform(0.15, 0.5)};
    const bool spaced = std::none_of(trunks.begin(), trunks.end(), [&](const Trunk& o) {
      const double gap = t.r + o.r + 1.0;
      return (t.x - o.x) * (t.x - o.x) + (t.y - o.y) * (t.y - o.y) < gap * gap;
    });
    if (spaced) trunks.push_back(t);
  }
  for (const Trunk& t : trunks) paintDisk(map, t.x, t.y, t.r, 1.0f);
}

void validate(const GeneratorOptions& options) {
  std::ostringstream message;
  if (options.rows < 2 || options.cols < 2) {
    message << "a generated terrain needs at least 2 x 2 cells (got " << options.cols << " x "
            << options.rows << ")";
  } else if (static_cast<std::int64_t>(options.rows) * options.cols > kMaxGeneratedCells) {
    message << "a generated terrain may have at most " << kMaxGeneratedCells << " cells (got "
            << options.cols << " x " << options.rows << ")";
  } else if (!(options.cell > 0.0) || !std::isfinite(options.cell)) {
    message << "the cell size must be a positive finite number of metres (got " << options.cell
            << ")";
  } else {
    return;
  }
  throw InputError(message.str());
}

}  // namespace

std::optional<TerrainKind> parseTerrainKind(std::string_view name) {
  for (const KindInfo& info : kKinds) {
    if (name == info.name) return info.kind;
  }
  return std::nullopt;
}

const char* terrainKindName(TerrainKind kind) {
  for (const KindInfo& info : kKinds) {
    if (info.kind == kind) return info.name;
  }
  return "unknown";
}

const char* terrainKindDescription(TerrainKind kind) {
  for (const KindInfo& info : kKinds) {
    if (info.kind == kind) return info.description;
  }
  return "";
}

std::vector<std::string> terrainKindNames() {
  std::vector<std::string> names;
  for (const KindInfo& info : kKinds) names.emplace_back(info.name);
  return names;
}

std::pair<Eigen::Vector2d, Eigen::Vector2d> standardStartGoal(const GridGeometry& geometry) {
  const double y = 0.5 * geometry.height();
  return {Eigen::Vector2d(0.1 * geometry.width(), y), Eigen::Vector2d(0.9 * geometry.width(), y)};
}

ElevationMap generateTerrain(const GeneratorOptions& options) {
  validate(options);
  GridGeometry geometry;
  geometry.rows = options.rows;
  geometry.cols = options.cols;
  geometry.cell = options.cell;
  ElevationMap map(geometry, 0.0f);
  Random random(options.seed);
  switch (options.kind) {
    case TerrainKind::kFlat:
      break;
    case TerrainKind::kRamp:
      generateRamp(map);
      break;
    case TerrainKind::kHill:
      generateHill(map);
      break;
    case TerrainKind::kHills:
      addHillsAndValleys(map, random, 1.0);
      break;
    case TerrainKind::kCorridor:
      generateCorridors(map, random);
      break;
    case TerrainKind::kObstacles:
      generateObstacles(map, random);
      break;
    case TerrainKind::kDeadEnd:
      generateDeadEnds(map, random);
      break;
    case TerrainKind::kForest:
      generateForest(map, random);
      break;
  }
  if (map.hasLayer(layer_names::kLethal)) clearStartAndGoal(map);
  return map;
}

}  // namespace terratraj::terrain
