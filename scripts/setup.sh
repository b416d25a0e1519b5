#!/usr/bin/env bash
# Installs the Debian 12 packages terratraj needs, if any are missing. Idempotent, and silent
# when there is nothing to do. Run as root (or with sudo available).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libceres-dev coinor-libipopt-dev libsundials-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libgdal-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libspdlog-dev
  python3 python3-numpy python3-matplotlib
  libompl-dev
)

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "$package" 2>/dev/null || true)
  [ "$status" = "installed" ] || missing+=("$package")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: run as root, or install sudo" >&2; exit 1; }
  sudo="sudo"
fi
log=$(mktemp)
if ! { $sudo apt-get update -qq && \
       DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
         "${missing[@]}"; } >"$log" 2>&1; then
  cat "$log" >&2
  echo "setup: apt-get failed (log above)" >&2
  exit 1
fi
rm -f "$log"
