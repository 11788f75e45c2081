# Sourced by the bench scripts: the repository's top folder ($here), the granstack to time ($gs:
# $GRANSTACK, else the release build) and a scratch folder ($work) removed on exit.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
gs=${GRANSTACK:-$here/build/release/app/granstack}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
