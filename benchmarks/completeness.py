"""The residual assumption of the search's completeness, as measured so far: every shard of
benchmarks/search_residual.py (the search against a brute force) and benchmarks/search_vs_maps.py
(against the synthesis maps) in benchmarks/, by the commit of the code that ran it, and whether
that commit's search is the tree's.

    python benchmarks/completeness.py

The search's code (`search_code`) is ocp/indirect/searching.py and every project file it imports,
directly or not (their packages' __init__ aside; a compiled extension by its C sources and headers,
as pyproject.toml declares them); a commit's search is the tree's where each of those files has,
at that commit, the `measured.code_hash` it has now (docstrings and comments aside). A line of the
table: the commit, its date, that verdict, the states against the brute force (of them the fast
starts of --fast), the brute force's arrivals and those the search missed, then the map cells by
verdict (`search_vs_maps`: the same extremal; unsettled and agreeing; the map's extremal slower,
settled or not; the search missed or slower, settled or not). States and cells whose search was
not proven optimal are not compared, and counted apart.
"""

import ast
import json
import subprocess
import sys
from pathlib import Path

from measured import code_hash, extension_sources, source_hash

ROOT = Path(__file__).resolve().parents[1]
SHARDS = {"brute force": "benchmarks/search_residual-*.jsonl", "maps": "benchmarks/search_vs_maps-*.jsonl"}
SEARCH = "ocp/indirect/searching.py"
#: a map cell's verdict -> its column
MAP_COLUMNS = {"same extremal": "same", "unsettled, agree": "agree", "map slower": "map slower",
               "unsettled, map slower": "map slower", "search missed": "missed",
               "unsettled, search slower": "missed"}


def git(*args):
    return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, check=False)


def _module_file(name):
    """The project files of the module `name` (dotted): its .py, or an extension's C sources, or none."""
    extensions = extension_sources()
    if name in extensions:
        return extensions[name]
    path = ROOT / (name.replace(".", "/") + ".py")
    return [str(path.relative_to(ROOT))] if path.is_file() else []


def search_code(start=SEARCH):
    """The project files `start` imports, directly or through the project's other modules (relative
    or `ocp.` imports, at any depth of the file), itself included."""
    seen, todo = set(), [start]
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        if not path.endswith(".py"):
            continue
        package = path[:-3].replace("/", ".").rsplit(".", 1)[0]
        for node in ast.walk(ast.parse((ROOT / path).read_bytes())):
            names = []
            if isinstance(node, ast.ImportFrom):
                base = package.rsplit(".", node.level - 1)[0] if node.level else ""
                module = ".".join(p for p in (base, node.module) if p)
                names = [module] + [f"{module}.{alias.name}" for alias in node.names]
            elif isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            todo += [f for name in names if name.startswith("ocp.") for f in _module_file(name)]
    return sorted(seen)


def same_search(commit, files, now):
    """Whether every file of `files` has at `commit` the code hash `now` gives it."""
    for path in files:
        shown = git("show", f"{commit}:{path}")
        if shown.returncode != 0 or source_hash(shown.stdout, Path(path).suffix) != now[path]:
            return False
    return True


def inputs():
    """{path: code hash} of what the table reads: the shards and the search's code (a change to
    either makes a published table stale: tests/test_published.py)."""
    shards = [path for pattern in SHARDS.values() for path in sorted(ROOT.glob(pattern))]
    return {str(path.relative_to(ROOT)): code_hash(path) for path in shards} | \
        {path: code_hash(ROOT / path) for path in search_code()}


def tally(rows):
    """{commit: counts} of the shards' rows."""
    counts = {}
    for kind, row in rows:
        c = counts.setdefault(row.get("commit", "unknown"), {
            "states": 0, "fast": 0, "arrivals": 0, "missed": 0, "cells": 0, "same": 0, "agree": 0,
            "map slower": 0, "cell missed": 0, "not compared": 0})
        if kind == "brute force":
            if "missing" not in row:
                c["not compared"] += 1
                continue
            c["states"] += 1
            c["fast"] += row.get("states") == "fast"
            c["arrivals"] += row["n_brute"]
            c["missed"] += len(row["missing"])
        else:
            column = MAP_COLUMNS.get(row["verdict"])
            if column is None:
                c["not compared"] += 1
                continue
            c["cells"] += 1
            c["cell missed" if column == "missed" else column] += 1
    return counts


def main():
    rows = [(kind, json.loads(line)) for kind, pattern in SHARDS.items() for path in sorted(ROOT.glob(pattern))
            for line in path.read_text().splitlines()]
    counts = tally(rows)
    files = search_code()
    now = {path: code_hash(ROOT / path) for path in files}
    dated = []
    for commit, c in counts.items():
        shown = git("show", "-s", "--format=%cI", commit)
        stamp = shown.stdout.decode().strip() if shown.returncode == 0 and "dirty" not in commit else "?"
        dated.append((stamp, commit, stamp != "?" and same_search(commit, files, now), c))
    dated.sort()
    print(f"The search's code: {', '.join(files)}.\n")
    print("| code of | committed | its search | brute force: states (fast starts) | arrivals | missed | maps: cells "
          "| same extremal | unsettled, agreeing | the map's slower | missed | not compared |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for stamp, commit, current, c in dated:
        print(f"| {commit} | {stamp[:10]} | {'the tree' if current else 'older'} | {c['states']} ({c['fast']}) | "
              f"{c['arrivals']} | {c['missed']} | {c['cells']} | {c['same']} | {c['agree']} | {c['map slower']} | "
              f"{c['cell missed']} | {c['not compared']} |")
    for label, chosen in (("The search as it stands", [d for d in dated if d[2]]), ("Every commit", dated)):
        total = {k: sum(d[3][k] for d in chosen) for k in ("states", "fast", "arrivals", "missed", "cells",
                                                           "cell missed", "not compared")}
        print(f"\n{label} ({len(chosen)} commits): {total['states']} states against the brute force "
              f"({total['fast']} fast starts; {total['arrivals']} arrivals, {total['missed']} missed), "
              f"{total['cells']} cells against the maps ({total['cell missed']} missed); {total['not compared']} "
              f"not compared (the search not proven optimal).")


if __name__ == "__main__":
    sys.exit(main())
