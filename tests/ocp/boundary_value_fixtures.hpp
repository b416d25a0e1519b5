#pragma once
// The problem sets of 004_... (bench/problem_sets.hpp, the benchmark fixtures) under the tests'
// short name.

#include "terratraj/bench/problem_sets.hpp"

namespace terratraj::ocp {
namespace fixtures = bench::problem_sets;
}  // namespace terratraj::ocp
