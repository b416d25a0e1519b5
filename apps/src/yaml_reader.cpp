#include "yaml_reader.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <locale>
#include <sstream>
#include <system_error>

namespace terratraj::apps::yaml_reader {
namespace {

constexpr const char* kYamlStringTag = "tag:yaml.org,2002:str";

}  // namespace

// ------------------------------------------------------------------------------------------
// Messages.

// A coordinate [m] for a message: as formatNumber(), with ".0" on whole numbers ("512.0").
std::string formatCoordinate(double value) {
  std::string text = formatNumber(value);
  if (std::isfinite(value) && text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

std::string inQuotes(std::string_view text) { return "\"" + std::string(text) + "\""; }

std::string joinNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) {
    if (!joined.empty()) joined += ", ";
    joined += name;
  }
  return joined;
}

std::string joinPath(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

// What a node holds, for "expected X, got Y" messages.
std::string describeNode(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Null:
      return "an empty value";
    case YAML::NodeType::Scalar:
      return inQuotes(node.Scalar());
    case YAML::NodeType::Undefined:
      break;
  }
  return "nothing";
}

[[noreturn]] void failAt(const Context& ctx, const Field& field, const std::string& what) {
  ctx.fail(field.mark(), field.path, what);
}

std::string Range::describe() const {
  const bool has_lower = lower_bound != Bound::kNone;
  const bool has_upper = upper_bound != Bound::kNone;
  std::string text;
  if (has_lower && has_upper) {
    text = "in ";
    text += lower_bound == Bound::kOpen ? "(" : "[";
    text += formatNumber(lower) + ", " + formatNumber(upper);
    text += upper_bound == Bound::kOpen ? ")" : "]";
    if (!unit.empty()) text += " " + unit;
  } else if (has_lower) {
    text = (lower_bound == Bound::kOpen ? "> " : ">= ") + formatNumber(lower);
  } else if (has_upper) {
    text = (upper_bound == Bound::kOpen ? "< " : "<= ") + formatNumber(upper);
  }
  return text;
}

// ------------------------------------------------------------------------------------------
// Scalars.

namespace {

std::size_t countDigits(std::string_view text, std::size_t from) {
  std::size_t count = 0;
  while (from + count < text.size() && text[from + count] >= '0' && text[from + count] <= '9') {
    ++count;
  }
  return count;
}

// Whether `text` is a YAML 1.2 core-schema decimal number:
// [-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?
bool isDecimalNumber(std::string_view text) {
  std::size_t i = 0;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
  const std::size_t integer_digits = countDigits(text, i);
  i += integer_digits;
  std::size_t fraction_digits = 0;
  if (i < text.size() && text[i] == '.') {
    ++i;
    fraction_digits = countDigits(text, i);
    i += fraction_digits;
  }
  if (integer_digits == 0 && fraction_digits == 0) return false;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    const std::size_t exponent_digits = countDigits(text, i);
    if (exponent_digits == 0) return false;
    i += exponent_digits;
  }
  return i == text.size();
}

// Whether `text` spells an infinity or NaN (YAML's .inf / .nan in any case, and inf / nan).
bool isNonFiniteSpelling(std::string_view text) {
  if (!text.empty() && (text.front() == '+' || text.front() == '-')) text.remove_prefix(1);
  if (!text.empty() && text.front() == '.') text.remove_prefix(1);
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower == "inf" || lower == "infinity" || lower == "nan";
}

// The scalar text of a field that must be a plain (unquoted) scalar holding a number.
std::string numberText(const Context& ctx, const Field& field, const char* expected) {
  if (!field.value.IsScalar()) {
    failAt(ctx, field, std::string("expected ") + expected + ", got " + describeNode(field.value));
  }
  const std::string& text = field.value.Scalar();
  const std::string& tag = field.value.Tag();
  if (tag == "!" || tag == kYamlStringTag) {
    failAt(ctx, field,
           std::string("expected ") + expected + ", got the quoted string " + inQuotes(text) +
               " (write numbers without quotes)");
  }
  return text;
}

// An integer written as one, split into sign and magnitude (saturated on overflow).
struct ParsedInteger {
  bool negative = false;
  unsigned long long magnitude = 0;
  bool overflow = false;
};

ParsedInteger parseIntegerText(const Context& ctx, const Field& field) {
  const std::string text = numberText(ctx, field, "an integer");
  std::string_view digits = text;
  ParsedInteger parsed;
  if (!digits.empty() && (digits.front() == '+' || digits.front() == '-')) {
    parsed.negative = digits.front() == '-';
    digits.remove_prefix(1);
  }
  if (digits.empty() || countDigits(digits, 0) != digits.size()) {
    failAt(ctx, field,
           "expected an integer, got " + (isDecimalNumber(text) ? text : inQuotes(text)));
  }
  const auto result =
      std::from_chars(digits.data(), digits.data() + digits.size(), parsed.magnitude);
  if (result.ec == std::errc::result_out_of_range) {
    parsed.overflow = true;
    parsed.magnitude = std::numeric_limits<unsigned long long>::max();
  }
  return parsed;
}

}  // namespace

// A finite real number in `range`.
double readNumber(const Context& ctx, const Field& field, const Range& range) {
  const std::string text = numberText(ctx, field, "a number");
  if (isNonFiniteSpelling(text)) failAt(ctx, field, "must be a finite number (got " + text + ")");
  if (!isDecimalNumber(text)) failAt(ctx, field, "expected a number, got " + inQuotes(text));
  std::string_view digits = text;
  if (digits.front() == '+') digits.remove_prefix(1);
  double value = 0.0;
  const auto result = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (result.ec != std::errc() || result.ptr != digits.data() + digits.size() ||
      !std::isfinite(value)) {
    failAt(ctx, field, "is out of the range of a double (got " + text + ")");
  }
  if (!range.contains(value)) {
    failAt(ctx, field, "must be " + range.describe() + " (got " + text + ")");
  }
  return value;
}

// An integer in [min_value, max_value].
int readInt(const Context& ctx, const Field& field, int min_value, int max_value) {
  const ParsedInteger parsed = parseIntegerText(ctx, field);
  const std::string got = " (got " + field.value.Scalar() + ")";
  if (parsed.negative && parsed.magnitude != 0) {
    // Negative: below min_value unless its magnitude is at most -min_value.
    if (min_value >= 0 ||
        parsed.magnitude > static_cast<unsigned long long>(-static_cast<long long>(min_value))) {
      failAt(ctx, field, "must be >= " + std::to_string(min_value) + got);
    }
    return static_cast<int>(-static_cast<long long>(parsed.magnitude));
  }
  if (parsed.magnitude < static_cast<unsigned long long>(std::max(min_value, 0))) {
    failAt(ctx, field, "must be >= " + std::to_string(min_value) + got);
  }
  if (max_value < 0 || parsed.magnitude > static_cast<unsigned long long>(max_value)) {
    failAt(ctx, field, "must be <= " + std::to_string(max_value) + got);
  }
  return static_cast<int>(parsed.magnitude);
}

// An integer in [0, 2^64 - 1] (random seeds).
std::uint64_t readUint64(const Context& ctx, const Field& field) {
  const ParsedInteger parsed = parseIntegerText(ctx, field);
  const std::string got = " (got " + field.value.Scalar() + ")";
  if (parsed.negative && parsed.magnitude != 0) failAt(ctx, field, "must be >= 0" + got);
  if (parsed.overflow) {
    failAt(ctx, field,
           "must be <= " + std::to_string(std::numeric_limits<std::uint64_t>::max()) + got);
  }
  return static_cast<std::uint64_t>(parsed.magnitude);
}

// A scalar as text (quoted or not).
std::string readString(const Context& ctx, const Field& field) {
  if (!field.value.IsScalar()) {
    failAt(ctx, field, "expected a string, got " + describeNode(field.value));
  }
  return field.value.Scalar();
}

// A non-empty file path, resolved against the problem file's folder.
std::filesystem::path readPath(const Context& ctx, const Field& field) {
  const std::string text = readString(ctx, field);
  if (text.empty()) failAt(ctx, field, "expected a file path, got an empty string");
  return ctx.resolve(std::filesystem::path(text));
}

// ------------------------------------------------------------------------------------------
// Maps.

// Checks that `map` holds only the keys in `allowed`, each once, each a plain name; throws
// InputError at the first offending key (in file order).
void requireKeys(const Context& ctx, const YAML::Node& map, const std::string& path,
                 const std::vector<std::string_view>& allowed) {
  std::vector<std::pair<std::string, YAML::Mark>> seen;
  for (auto it = map.begin(); it != map.end(); ++it) {
    const YAML::Node key = it->first;  // a copy: `it->` yields a temporary proxy
    if (!key.IsScalar()) {
      ctx.fail(key.Mark(), path, "keys must be plain names, got " + describeNode(key));
    }
    const std::string& name = key.Scalar();
    if (name.empty()) ctx.fail(key.Mark(), path, "keys must be plain names, got an empty key");
    bool known = false;
    for (std::string_view candidate : allowed) known = known || candidate == name;
    if (!known) {
      std::vector<std::string> names(allowed.begin(), allowed.end());
      ctx.fail(key.Mark(), joinPath(path, name),
               "unknown key (expected one of: " + joinNames(names) + ")");
    }
    for (const auto& [previous, previous_mark] : seen) {
      if (previous == name) {
        ctx.fail(
            key.Mark(), joinPath(path, name),
            "duplicate key (first given on line " + std::to_string(previous_mark.line + 1) + ")");
      }
    }
    seen.emplace_back(name, key.Mark());
  }
}

}  // namespace terratraj::apps::yaml_reader
