#pragma once
// Runs one `terratraj` command line in-process (runCli), as the apps tests do.

#include <sstream>
#include <string>
#include <vector>

#include "terratraj/apps/cli.hpp"

namespace terratraj::apps::testing {

/// What a command line did: its exit status and what it wrote to stdout and stderr.
struct CliRun {
  int status;
  std::string out;
  std::string err;
};

/// Runs `terratraj args...`.
inline CliRun run(std::vector<std::string> args) {
  args.insert(args.begin(), "terratraj");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int status = runCli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {status, out.str(), err.str()};
}

}  // namespace terratraj::apps::testing
