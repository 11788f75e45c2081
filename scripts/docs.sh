#!/usr/bin/env bash
# Builds the documentation site into OUT (default build/site) with mkdocs --strict, from a copy of
# docs/ to which it adds the command-line reference generated from granstack's own --help (so
# the reference cannot drift from the program), then checks that every local link and image of
# the built site resolves.
#   scripts/docs.sh [GRANSTACK] [OUT]    GRANSTACK: the program (default build/release/app/granstack)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
gs=${1:-$here/build/release/app/granstack}
out=$(realpath -m "${2:-$here/build/site}")
command -v mkdocs >/dev/null || { echo "docs: mkdocs is missing: bash scripts/setup.sh --tests installs it" >&2; exit 1; }
[ -x "$gs" ] || { echo "docs: no granstack at $gs: build it first (bash scripts/build.sh release)" >&2; exit 1; }
src=$(mktemp -d)
trap 'rm -rf "$src"' EXIT
cp -r "$here/docs" "$src/docs"
sed -e "s|^site_dir:.*|site_dir: $out|" "$here/mkdocs.yml" > "$src/mkdocs.yml"

# The command-line reference, generated (run through PATH, so its usage lines say "granstack").
help() { PATH="$(dirname "$gs"):$PATH" granstack "$@" --help; }
{
  echo "# Command-line help"
  echo
  echo "Generated from \`granstack --help\` and each command's \`--help\` when the site is built"
  echo "(\`scripts/docs.sh\`); [Commands](commands.md) explains each command at length."
  echo
  echo "## granstack"
  echo
  echo '```'
  help
  echo '```'
  for cmd in $(help | awk '/^Subcommands:/ {on = 1; next} on && NF {print $1}'); do
    echo
    echo "## granstack $cmd"
    echo
    echo '```'
    help "$cmd"
    echo '```'
  done
} > "$src/docs/reference/cli.md"

(cd "$src" && mkdocs build --strict > "$src/mkdocs.log" 2>&1) || { grep -v '^INFO' "$src/mkdocs.log" >&2; exit 1; }

# Every local href and src of the built pages points at a file of the site (and an anchor of it).
python3 - "$out" <<'PY'
import html.parser, os, sys, urllib.parse
site = sys.argv[1]
class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.ids = [], set()
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a: self.ids.add(a["id"])
        for k in ("href", "src"):
            if k in a and a[k]: self.links.append(a[k])
pages = {}
for root, _, files in os.walk(site):
    for f in files:
        if f.endswith(".html"):
            p = Page()
            p.feed(open(os.path.join(root, f), encoding="utf-8").read())
            pages[os.path.normpath(os.path.join(root, f))] = p
bad = []
for path, p in pages.items():
    for link in p.links:
        u = urllib.parse.urlparse(link)
        if u.scheme or link.startswith("//") or link.startswith("mailto:"):
            continue
        where = site if u.path.startswith("/") else os.path.dirname(path)
        target = os.path.normpath(os.path.join(where, urllib.parse.unquote(u.path).lstrip("/"))) if u.path else path
        if os.path.isdir(target): target = os.path.join(target, "index.html")
        if not os.path.exists(target):
            bad.append(f"{os.path.relpath(path, site)}: {link} (no such file)")
        elif u.fragment and target in pages and u.fragment not in pages[target].ids:
            bad.append(f"{os.path.relpath(path, site)}: {link} (no such anchor)")
if bad:
    print("docs: broken links:\n  " + "\n  ".join(bad), file=sys.stderr)
    sys.exit(1)
print(f"docs: {len(pages)} pages in {site}, every local link resolves")
PY
