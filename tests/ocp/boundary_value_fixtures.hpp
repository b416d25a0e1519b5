#pragma once
// The problem sets of 004_... (ocp/problem_sets.hpp) under the tests' short name.

#include "terratraj/ocp/problem_sets.hpp"

namespace terratraj::ocp {
namespace fixtures = problem_sets;
}  // namespace terratraj::ocp
