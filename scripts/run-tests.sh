#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite under ctest.
#   scripts/run-tests.sh             the normal build (build/)
#   scripts/run-tests.sh --sanitize  the ASan + UBSan build (build-asan/)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
"$here/setup.sh"
"$here/build.sh" "$@"
build_dir="$here/../build"
[ "${1:-}" = "--sanitize" ] && build_dir="$here/../build-asan"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# Third-party leaks only (OMPL's SST): tests/sanitizers/lsan.supp says which and why.
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$here/../tests/sanitizers/lsan.supp:print_suppressions=0}"
cd "$build_dir"
exec ctest --output-on-failure -j 2 --timeout 900
