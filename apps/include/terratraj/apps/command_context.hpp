#pragma once
// CommandContext: what every command receives: where results and messages go, and a logger.

#include <iosfwd>
#include <memory>

#include <spdlog/logger.h>

namespace terratraj::apps {

/// The streams and options shared by all commands.
struct CommandContext {
  std::ostream& out;                    ///< results (one JSON object with --json)
  std::ostream& err;                    ///< messages and progress
  bool json = false;                    ///< --json was given
  std::shared_ptr<spdlog::logger> log;  ///< progress lines, written to `err`
};

}  // namespace terratraj::apps
