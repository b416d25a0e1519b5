#pragma once
// The `terratraj` command-line front end, callable in-process (tests) as well as from main().

#include <atomic>
#include <iosfwd>

namespace terratraj::apps {

/// Exit statuses of every command (../shared/spec/interface.md, "Exit status"), plus one for
/// bugs, which the contract does not foresee.
enum ExitStatus : int {
  kExitSuccess = 0,    ///< done
  kExitNotSolved = 1,  ///< the problem was read but not solved; the report is still printed
  kExitBadInput = 2,   ///< bad input or usage; a message names the file, key or value at fault
  kExitInternal = 3,   ///< an internal error (a bug): the message says what failed
};

/// Runs one command line. Results go to `out` (with --json, exactly one JSON object), messages
/// and progress to `err`. `stop` (optional) is polled by long commands: when it becomes true
/// they stop and write what they have. Never throws; returns an ExitStatus.
int runCli(int argc, const char* const* argv, std::ostream& out, std::ostream& err,
           const std::atomic<bool>* stop = nullptr);

}  // namespace terratraj::apps
