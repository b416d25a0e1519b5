#!/usr/bin/env bash
# Installs what is missing, builds, and runs `terratraj demo` (output in ./terratraj-demo/).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
"$here/setup.sh"
"$here/build.sh"
exec "$here/../build/apps/terratraj" demo "$@"
