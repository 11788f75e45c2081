# Sourced by the bench scripts: the repository's top folder ($here), the granstack to time ($gs:
# $GRANSTACK, else the release build) and a scratch folder ($work) removed on exit.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
gs=${GRANSTACK:-$here/build/release/app/granstack}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# A median of fewer than three alternating runs says nothing about a machine that drifts by 30 %:
# every script takes REPEATS >= 3 (its first argument), and refuses fewer.
if [ -n "${repeats:-}" ] && ! [ "$repeats" -ge 3 ] 2>/dev/null; then
  echo "$(basename "$0"): REPEATS is $repeats; give at least 3 (medians of fewer runs are not reported)" >&2
  exit 2
fi
