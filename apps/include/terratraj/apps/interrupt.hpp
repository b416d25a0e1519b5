#pragma once
// SIGINT as a request to stop: the first Ctrl-C sets a flag that long commands poll (plan,
// refine, bench, primitives), which then stop their work and write what they have; a second
// Ctrl-C ends the process at once.

#include <atomic>

namespace terratraj::apps {

/// Installs the SIGINT handler (once per process; main() calls it) and returns the flag it sets.
const std::atomic<bool>& installInterruptHandler();

}  // namespace terratraj::apps
