#!/usr/bin/env bash
# Configures (once) and builds terratraj. Quiet unless something fails.
#   scripts/build.sh            -> build/        (RelWithDebInfo)
#   scripts/build.sh --sanitize -> build-asan/   (AddressSanitizer + UndefinedBehaviorSanitizer)
# CI=true turns compiler warnings into errors.
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
options=(-DCMAKE_BUILD_TYPE=RelWithDebInfo)
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-asan
  options=(-DCMAKE_BUILD_TYPE=Debug -DTERRATRAJ_SANITIZE=ON -DTERRATRAJ_BUILD_BENCHMARKS=OFF
           -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g")
fi
[ "${CI:-}" = "true" ] && options+=(-DTERRATRAJ_WERROR=ON)

log="$build_dir.log"
mkdir -p "$build_dir"
if [ ! -f "$build_dir/build.ninja" ] || [ "${CI:-}" = "true" ]; then
  if ! cmake -S . -B "$build_dir" -G Ninja "${options[@]}" >"$build_dir/$log" 2>&1; then
    cat "$build_dir/$log" >&2
    echo "build: cmake configure failed" >&2
    exit 1
  fi
fi
if ! cmake --build "$build_dir" -- --quiet >"$build_dir/$log" 2>&1; then
  cat "$build_dir/$log" >&2
  echo "build: compilation failed" >&2
  exit 1
fi
