#!/usr/bin/env bash
# Configures and builds granstack with a CMake preset (default: "release"; "ci" turns warnings
# into errors). Usage: scripts/build.sh [PRESET]
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-release}
bash scripts/setup.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
