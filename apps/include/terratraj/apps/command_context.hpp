#pragma once
// CommandContext: what every command receives: where results and messages go, and a logger.

#include <atomic>
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
  /// Set when the user asked to stop (SIGINT, interrupt.hpp); null: never. A long command
  /// stops its work early and writes what it has.
  const std::atomic<bool>* stop = nullptr;
  /// Whether a stop was requested.
  bool stopRequested() const { return stop != nullptr && stop->load(); }
};

/// The version string of reports ("terratraj 0.1.0").
inline constexpr const char* kTerratrajVersion = "terratraj 0.1.0";

}  // namespace terratraj::apps
