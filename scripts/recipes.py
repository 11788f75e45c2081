#!/usr/bin/env python3
"""extending.md's recipes held to the code (the docs.recipes test).

Four recipes (a contact model, an engine, a design measure, a batch system) each say, between
`<!-- recipe: KIND -->` and `<!-- /recipe -->`, what a new one needs: a bullet per file, its path
first (`<name>` where each one has a file of its own, e.g. `runner/src/<name>_engine.cpp`), then the
names it holds that a new one joins (a table, an enum, a factory). Checked here: each file exists
(for every existing one of the kind, where the path is per instance) and holds each name.

What keeps the list true is the second block, `<!-- special: KIND -->`: every place the code names
one existing model, engine, measure or batch system by itself outside its kind's tables (an
`if (m == NormalModel::hooke)`, a `"srs_peak"` read by name) is a place a new one may need too.
Each such (instance, file) is listed there with why, and the code's set must equal the list: a
new special case fails the test until the recipe says it, and a removed one until the recipe
stops saying it.

Usage: scripts/recipes.py [--check]   (prints what differs; exit 1 when anything does)
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
DOC = ROOT / "docs/developer/extending.md"
LIBRARIES = ["app", "model", "os", "formats", "generator", "refsim", "postproc", "runner", "cluster", "design", "study"]


def sources(folders):
    for folder in folders:
        for p in sorted((ROOT / folder).rglob("*")):
            if p.suffix in (".cpp", ".hpp") and p.is_file():
                yield p


def enumerators(header, enum):
    text = (ROOT / header).read_text()
    body = re.search(r"enum class " + enum + r"\s*\{([^}]*)\}", text).group(1)
    body = re.sub(r"//[^\n]*", "", body)
    return [e.strip() for e in body.split(",") if e.strip()]


def contact_instances():
    header = "model/include/granstack/model/contact.hpp"
    for enum in ("NormalModel", "TangentialModel", "RollingModel"):
        for e in enumerators(header, enum):
            yield f"{enum}::{e}", re.compile(r"\b" + enum + "::" + e + r"\b")


def engine_instances():
    for e in enumerators("runner/include/granstack/runner/runner.hpp", "Engine"):
        # its enumerator, or its name as flags, run.json and folders spell it
        yield f"Engine::{e}", re.compile(r"(?<![A-Za-z_])Engine::" + e + r'\b|"' + e + '"')


def measure_instances():
    text = (ROOT / "design/src/objectives.cpp").read_text()
    table = text[text.index("kTable{"):]
    for name in re.findall(r'^    \{"(\w+)", "', table, re.M):
        yield f'"{name}"', re.compile('"' + name + '"')


def scheduler_instances():
    for p in sources(["cluster"]):
        for name in re.findall(r"class (\w+) final : public Scheduler", p.read_text()):
            yield name, re.compile(r"\b" + name + r"\b")


# Each kind: its instances (name, pattern), where they are looked for, and the files that are the
# kind's tables or an instance's own definition (naming every instance there is the recipe).
KINDS = {
    "contact model": (contact_instances, LIBRARIES, {"model/include/granstack/model/contact.hpp"}),
    "engine": (engine_instances, LIBRARIES, {"runner/src/engines.cpp"}),
    "design measure": (measure_instances, ["design", "app"], {"design/src/objectives.cpp"}),
    "batch system": (scheduler_instances, ["cluster", "app"], set()),
}


def blocks(text, tag):
    return {m.group(1): m.group(2) for m in re.finditer(r"<!-- " + tag + r": ([a-z ]+) -->\n(.*?)<!-- /" + tag + " -->",
                                                           text, re.S)}


def bullets(block):
    items, current = [], None
    for line in block.splitlines():
        if line.startswith("- "):
            current = line[2:]
            items.append(current)
        elif current is not None and line.startswith("  "):
            items[-1] += " " + line.strip()
    return items


def code_special_cases(kind):
    instances, folders, tables = KINDS[kind]
    found = set()
    instances = list(instances())
    for p in sources(folders):
        rel = str(p.relative_to(ROOT))
        if rel in tables:
            continue
        text = re.sub(r"//[^\n]*", "", p.read_text())  # what the code names, not its comments
        for name, pattern in instances:
            if pattern.search(text) and not own_file(kind, name, rel, text):
                found.add((name, rel))
    return found, [n for n, _ in instances]


def own_file(kind, name, rel, text):
    """An engine's own file, or the file defining a batch system's class, is the recipe, not a
    special case."""
    if kind == "engine":
        return rel == f"runner/src/{name.split('::')[1]}_engine.cpp"
    return kind == "batch system" and re.search(r"class " + name + r" final : public Scheduler", text) is not None


def check_needs(kind, block, instances):
    problems = []
    items = bullets(block)
    if not items:
        problems.append(f"{kind}: the recipe lists no file")
    for item in items:
        names = re.findall(r"`([^`]+)`", item)
        if not names:
            problems.append(f"{kind}: '{item[:60]}...' names no file")
            continue
        path, held = names[0], [n for n in names[1:] if "/" not in n and "." not in n]
        files = [path]
        if "<name>" in path:
            words = [i.split("::")[-1].strip('"').lower() for i in instances]
            files = [path.replace("<name>", w) for w in words if (ROOT / path.replace("<name>", w)).exists()]
            if not files:
                problems.append(f"{kind}: no existing one has a file {path}")
        for f in files:
            p = ROOT / f
            if f.endswith("/") and p.is_dir():
                continue
            if not p.is_file():
                problems.append(f"{kind}: {f}, which the recipe names, does not exist")
                continue
            text = p.read_text()
            for n in held:
                if n not in text:
                    problems.append(f"{kind}: {f} does not hold `{n}`, which the recipe says a new one joins there")
    return problems


def check_special(kind, block, code):
    listed = set()
    for item in bullets(block):
        names = re.findall(r"`([^`]+)`", item)
        if not names:
            continue
        for f in names[1:]:
            if "/" in f:
                listed.add((names[0], f))
    problems = []
    for name, f in sorted(code - listed):
        problems.append(f"{kind}: {f} names {name} by itself, which the recipe's special cases do not list: "
                        f"list it there with why (a new one may need the same), or read it from the kind's table")
    for name, f in sorted(listed - code):
        problems.append(f"{kind}: the recipe lists {f} as naming {name}, which it no longer does: take it out")
    return problems


def main():
    text = DOC.read_text()
    needs, special = blocks(text, "recipe"), blocks(text, "special")
    problems = []
    for kind in KINDS:
        code, instances = code_special_cases(kind)
        if kind not in needs:
            problems.append(f"{kind}: extending.md has no '<!-- recipe: {kind} -->' block")
        else:
            problems += check_needs(kind, needs[kind], instances)
        if kind not in special:
            problems.append(f"{kind}: extending.md has no '<!-- special: {kind} -->' block")
        else:
            problems += check_special(kind, special[kind], code)
        print(f"{kind}: {len(instances)} existing, {len(code)} special cases in the code", flush=True)
    for p in problems:
        print("recipes:", p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
