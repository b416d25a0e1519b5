#pragma once
// A number in a message (internal to refine/src): the shortest default stream form (6
// significant digits), as the reasons of the refiner and its option checks print it.

#include <sstream>
#include <string>

namespace terratraj::refine::detail {

inline std::string formatNumber(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

}  // namespace terratraj::refine::detail
