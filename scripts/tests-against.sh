#!/usr/bin/env bash
# Runs this build's user tests (those that start the granstack program: safety, reliability,
# trust) against the program of another commit, to show which of them that commit fails: a test
# written for a fault must fail on the commit before its fix. The other commit is built (its
# `granstack` alone, release preset) in a git worktree under build/against-COMMIT.
# Usage: scripts/tests-against.sh COMMIT [TEST_BINARY [GTEST_FILTER]]
#   e.g. scripts/tests-against.sh HEAD~3 granstack_trust_tests
# Prints each test's verdict on the other commit's program; exits 0 (the verdicts are the result).
set -euo pipefail
cd "$(dirname "$0")/.."
commit=$(git rev-parse --short "${1:?usage: scripts/tests-against.sh COMMIT [TEST_BINARY [GTEST_FILTER]]}")
binary=${2:-granstack_trust_tests}
filter=${3:-*}
tests=build/ci/tests/$binary
[ -x "$tests" ] || { echo "no $tests: build this tree first (bash scripts/build.sh ci)" >&2; exit 2; }
tree=build/against-$commit
if [ ! -d "$tree" ]; then
  git worktree add --detach "$tree" "$commit" >/dev/null
fi
(cd "$tree" && cmake --preset release >/dev/null && cmake --build --preset release --target granstack >/dev/null)
echo "$binary ($(git rev-parse --short HEAD)'s tests) against the program of $commit:"
GRANSTACK_TEST_EXE=$PWD/$tree/build/release/app/granstack "$tests" --gtest_filter="$filter" 2>&1 |
  grep -E '^\[ +(OK|FAILED|SKIPPED) +\] [A-Za-z_.]+ \(' || true
