#pragma once
// formatNumber: a number as the CLI's messages write it (not installed; apps/src only).

#include <locale>
#include <sstream>
#include <string>

namespace terratraj::apps {

/// `value` with up to 6 significant digits in the classic locale ("0", "1.5708", "1e-06"): the
/// one number format of the loader's, the translation layer's and the commands' messages.
inline std::string formatNumber(double value) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(6);
  out << value;
  return out.str();
}

}  // namespace terratraj::apps
