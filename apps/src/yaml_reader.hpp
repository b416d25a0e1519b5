#pragma once
// The problem file's YAML reader (internal to apps): the file being read (Context), a value
// with its key (Field), ranges of allowed numbers (Range), scalar readers that check type and
// range, and MapReader, a map whose keys are validated. Every failure is an InputError
// "<file>:<line>:<column>: <key.path>: <what>". The section parsers (problem_loader.cpp) are
// built on these.

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "message_number.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps::yaml_reader {

// A number for a message: up to 6 significant digits ("0", "1.5708"; message_number.hpp).
using apps::formatNumber;
// A coordinate [m] for a message: as formatNumber(), with ".0" on whole numbers ("512.0").
std::string formatCoordinate(double value);
std::string inQuotes(std::string_view text);
std::string joinNames(const std::vector<std::string>& names);
std::string joinPath(const std::string& parent, std::string_view key);
// What a node holds, for "expected X, got Y" messages.
std::string describeNode(const YAML::Node& node);

// The file being parsed: its name for messages and the folder relative paths start from.
class Context {
 public:
  Context(std::string display_name, std::filesystem::path base_dir)
      : display_name_(std::move(display_name)), base_dir_(std::move(base_dir)) {}

  const std::string& displayName() const { return display_name_; }

  // Throws InputError "<file>:<line>:<column>: <path>: <what>" (position and path omitted when
  // unknown / empty).
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& path,
                         const std::string& what) const {
    std::ostringstream message;
    message << display_name_;
    if (!mark.is_null()) message << ":" << mark.line + 1 << ":" << mark.column + 1;
    message << ": ";
    if (!path.empty()) message << path << ": ";
    message << what;
    throw InputError(message.str());
  }

  // A path from the file: relative ones are taken from the file's folder.
  std::filesystem::path resolve(const std::filesystem::path& path) const {
    return path.is_absolute() ? path : base_dir_ / path;
  }

 private:
  std::string display_name_;
  std::filesystem::path base_dir_;
};

// A value in the file with the key it was found under.
struct Field {
  YAML::Node value;
  YAML::Mark key_mark;
  std::string path;  // e.g. "vehicle.limits.v_max"

  // Where errors about the value point: the value itself, or its key when the value is empty
  // (yaml-cpp places an empty value at the start of the next line).
  YAML::Mark mark() const {
    if (value.IsNull() || value.Mark().is_null()) return key_mark;
    return value.Mark();
  }
};

[[noreturn]] void failAt(const Context& ctx, const Field& field, const std::string& what);

// Ranges of allowed real values, for checks and "must be ..." messages.
struct Range {
  enum class Bound { kNone, kOpen, kClosed };
  Bound lower_bound = Bound::kNone;
  double lower = 0.0;
  Bound upper_bound = Bound::kNone;
  double upper = 0.0;
  std::string unit;  // shown after two-sided bounds, e.g. "deg"

  static Range any() { return {}; }
  static Range positive() { return {Bound::kOpen, 0.0, Bound::kNone, 0.0, ""}; }
  static Range nonNegative() { return {Bound::kClosed, 0.0, Bound::kNone, 0.0, ""}; }
  static Range atLeast(double low) { return {Bound::kClosed, low, Bound::kNone, 0.0, ""}; }
  static Range closed(double low, double high, std::string unit_name) {
    return {Bound::kClosed, low, Bound::kClosed, high, std::move(unit_name)};
  }
  static Range openInterval(double low, double high, std::string unit_name) {
    return {Bound::kOpen, low, Bound::kOpen, high, std::move(unit_name)};
  }
  // The same range with both bounds multiplied by `factor` (> 0), in another unit.
  Range scaled(double factor, std::string unit_name) const {
    return {lower_bound, lower * factor, upper_bound, upper * factor, std::move(unit_name)};
  }

  bool contains(double value) const {
    const bool above = lower_bound == Bound::kNone ||
                       (lower_bound == Bound::kOpen ? value > lower : value >= lower);
    const bool below = upper_bound == Bound::kNone ||
                       (upper_bound == Bound::kOpen ? value < upper : value <= upper);
    return above && below;
  }

  // "> 0", ">= 0", "in (0, 90) deg", ...
  std::string describe() const;
};

// A finite real number in `range`.
double readNumber(const Context& ctx, const Field& field, const Range& range);
// An integer in [min_value, max_value].
int readInt(const Context& ctx, const Field& field, int min_value, int max_value);
// An integer in [0, 2^64 - 1] (random seeds).
std::uint64_t readUint64(const Context& ctx, const Field& field);
// A scalar as text (quoted or not).
std::string readString(const Context& ctx, const Field& field);
// A non-empty file path, resolved against the problem file's folder.
std::filesystem::path readPath(const Context& ctx, const Field& field);

// One of an enumeration's names.
template <typename Enum, typename Parser>
Enum readEnum(const Context& ctx, const Field& field, Parser parse,
              const std::vector<std::string>& names) {
  const std::string expected = "must be one of: " + joinNames(names);
  if (!field.value.IsScalar()) {
    failAt(ctx, field, expected + " (got " + describeNode(field.value) + ")");
  }
  const std::optional<Enum> value = parse(field.value.Scalar());
  if (!value) failAt(ctx, field, expected + " (got " + inQuotes(field.value.Scalar()) + ")");
  return *value;
}

// Checks that `map` holds only the keys in `allowed`, each once, each a plain name; throws
// InputError at the first offending key (in file order).
void requireKeys(const Context& ctx, const YAML::Node& map, const std::string& path,
                 const std::vector<std::string_view>& allowed);

// A validated map: its keys are known, and each value can be looked up with its key's mark.
class MapReader {
 public:
  // Throws InputError unless `field` holds a map whose keys are all in `allowed`.
  MapReader(const Context& ctx, const Field& field, std::vector<std::string_view> allowed)
      : ctx_(ctx), field_(field) {
    if (!field.value.IsMap()) {
      failAt(ctx, field, "expected a map, got " + describeNode(field.value));
    }
    requireKeys(ctx, field.value, field.path, allowed);
  }

  const std::string& path() const { return field_.path; }
  // Where errors about the map as a whole (e.g. a missing key) point.
  YAML::Mark mark() const { return field_.mark(); }
  std::string childPath(std::string_view key) const { return joinPath(field_.path, key); }

  // The value under `key`, if present.
  std::optional<Field> find(std::string_view key) const {
    for (auto it = field_.value.begin(); it != field_.value.end(); ++it) {
      if (it->first.Scalar() == key) return Field{it->second, it->first.Mark(), childPath(key)};
    }
    return std::nullopt;
  }

  // The value under `key`; throws InputError at the map when it is absent.
  Field require(std::string_view key) const {
    std::optional<Field> field = find(key);
    if (!field) ctx_.fail(mark(), childPath(key), "missing required key");
    return *std::move(field);
  }

  // Throws InputError at this map, about the key `key` (or the map itself when empty).
  [[noreturn]] void fail(std::string_view key, const std::string& what) const {
    ctx_.fail(mark(), key.empty() ? path() : childPath(key), what);
  }

  std::optional<double> optionalNumber(std::string_view key, const Range& range) const {
    const std::optional<Field> field = find(key);
    if (!field) return std::nullopt;
    return readNumber(ctx_, *field, range);
  }
  double requiredNumber(std::string_view key, const Range& range) const {
    return readNumber(ctx_, require(key), range);
  }
  // Sets `target` from `key` when the key is present.
  void readNumberInto(std::string_view key, const Range& range, double& target) const {
    if (const std::optional<double> value = optionalNumber(key, range)) target = *value;
  }
  void readIntInto(std::string_view key, int min_value, int max_value, int& target) const {
    if (const std::optional<Field> field = find(key)) {
      target = readInt(ctx_, *field, min_value, max_value);
    }
  }
  void readSeedInto(std::string_view key, std::uint64_t& target) const {
    if (const std::optional<Field> field = find(key)) target = readUint64(ctx_, *field);
  }

  // An angle given as `rad_key` [rad] or `rad_key`_deg [deg], not both; returned in radians.
  // `degree_range` bounds it (in degrees).
  std::optional<double> optionalAngle(std::string_view rad_key, const Range& degree_range) const {
    const std::string deg_key = std::string(rad_key) + "_deg";
    const std::optional<Field> radians = find(rad_key);
    const std::optional<Field> degrees = find(deg_key);
    if (radians && degrees) {
      ctx_.fail(degrees->key_mark, childPath(rad_key),
                "give either " + std::string(rad_key) + " or " + deg_key + ", not both");
    }
    if (radians)
      return readNumber(ctx_, *radians, degree_range.scaled(models::kRadiansPerDegree, "rad"));
    if (degrees) return readNumber(ctx_, *degrees, degree_range) * models::kRadiansPerDegree;
    return std::nullopt;
  }
  void readAngleInto(std::string_view rad_key, const Range& degree_range, double& target) const {
    if (const std::optional<double> value = optionalAngle(rad_key, degree_range)) target = *value;
  }

 private:
  const Context& ctx_;
  Field field_;
};

}  // namespace terratraj::apps::yaml_reader
