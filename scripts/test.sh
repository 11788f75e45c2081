#!/usr/bin/env bash
# The test suite: install, build with warnings as errors, then every test (unit tests, the
# real LIGGGHTS on small cases, the examples) with ctest on all cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --tests
bash scripts/build.sh ci
ctest --preset ci
