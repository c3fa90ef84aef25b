"""The residual assumption of the search's completeness, as measured so far: every committed shard
of benchmarks/search_residual.py (the search against a brute force), benchmarks/search_vs_maps.py
(against the synthesis maps) and benchmarks/search_saddle_audit.py (the halves settled by omega's
bound by a saddle, sampled inside) in benchmarks/ (files tracked by git only: a shard still being
written is not counted), by the commit of the code that ran it, and whether that commit's search is
the tree's.

    python benchmarks/completeness.py

The search's code (`search_code`) is ocp/indirect/searching.py and every project file it imports,
directly or not, by module (a name a package's __init__ re-exports is not followed; a compiled
extension by its C sources and headers as pyproject.toml declares them, not its compile flags); a
commit's search (`verdict`) is "the tree" where each of those files has, at that commit, the
`measured.code_hash` it has now (docstrings and comments aside), "older" where one differs, and
"unknown" where the shard recorded no commit git knows (none, or one with uncommitted changes). A
line of the table: the commit, its date, that verdict; the states against the brute force (of them
the fast starts of --fast, the small kappa of --small and the large of --large), the brute force's own reach (its arrivals, the states where its best is
the search's and where it found none: "0 missed" checks nothing there) and the arrivals the search
did not report; then the map cells by verdict (`search_vs_maps`: the same extremal; unsettled and
agreeing; the map's extremal slower, settled or not; the map's value below the search's answer
where the map's extremals near the cell pass it by: not attained, no extremal's; the map's faster
than the search's answer, settled or not: a miss), a cell's verdict judged again by
benchmarks/map_settlements.jsonl where that holds one for it (`search_vs_maps.py --settle`: the cells
an earlier version of that script left unsettled). States and cells whose search was not proven
optimal are not compared, and counted apart. Below it, the audit by saddles, for the search as it stands and for every shard:
its states, the halves audited, those hiding a turning point, and the hidden arrivals before the
search's best (an arrival the search may have missed).
"""

import ast
import json
import subprocess
import sys
from pathlib import Path

from measured import code_hash, extension_sources, source_hash

ROOT = Path(__file__).resolve().parents[1]
SHARDS = {"brute force": "benchmarks/search_residual*.jsonl", "maps": "benchmarks/search_vs_maps*.jsonl",
          "saddle audit": "benchmarks/search_saddle_audit*.jsonl"}
SETTLEMENTS = "benchmarks/map_settlements.jsonl"
SEARCH = "ocp/indirect/searching.py"
COUNTS = ("states", "fast", "small", "large", "arrivals", "its best", "none found", "missed", "cells", "same", "agree", "map slower",
          "not attained", "cell missed", "not compared", "audited", "halves", "hiding", "hidden arrivals")
#: a map cell's verdict -> its column
MAP_COLUMNS = {"same extremal": "same", "unsettled, agree": "agree", "map slower": "map slower",
               "unsettled, map slower": "map slower", "unsettled, not attained": "not attained",
               "search missed": "missed", "unsettled, search slower": "missed"}


def same_arrival(T, F):
    """Whether the times T and F (each solved to CHECK accuracy at least) are one arrival's: within
    1e-8 relative (search_residual.py's test of a miss too)."""
    return abs(T - F) <= 1e-8 * T


def git(*args):
    return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, check=False)


def shard_commit():
    """The commit a shard records as the code that ran: `git describe --always` of this checkout. A run
    with uncommitted changes to tracked files (a shard being written is untracked), or whose `ocp` is
    imported from elsewhere (an editable install of another checkout), would record a commit that is
    not the code that runs: refused, with the reason, exit status 2."""
    import ocp
    described = git("describe", "--always", "--dirty").stdout.decode().strip()
    reason = (f"`ocp` is imported from {Path(ocp.__file__).parent}, not this checkout's {ROOT / 'ocp'}"
              if Path(ocp.__file__).resolve().parent != ROOT / "ocp" else
              "this checkout has uncommitted changes: commit them first" if described.endswith("-dirty") else
              "no commit to record: not a git checkout" if not described else None)
    if reason:
        print(f"a shard records the commit of the code that runs; {reason}", file=sys.stderr)
        sys.exit(2)
    return described


def shard_range(args, usage, key):
    """(OUT path, the seeds FIRST to END - 1 still to run) of a shard runner's arguments OUT FIRST END
    (strings): those whose `key` no line of OUT holds yet (a shard resumes after them); anything else:
    `usage` (its module's docstring) on stderr, exit status 2."""
    try:
        out, first, end = args
        out, seeds = Path(out), range(int(first), int(end))
    except ValueError:
        print(f"expected OUT.jsonl FIRST END (integers), got {' '.join(args) or 'nothing'}; usage:\n{usage}",
              file=sys.stderr)
        sys.exit(2)
    done = {json.loads(line)[key] for line in out.read_text().splitlines()} if out.exists() else set()
    return out, [seed for seed in seeds if seed not in done]


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


def shards():
    """(kind, path) of every shard git tracks, by name."""
    return [(kind, path) for kind, pattern in SHARDS.items()
            for path in sorted(git("ls-files", pattern).stdout.decode().split())]


def settled(rows, settlements):
    """The shards' (kind, row) with each map cell that a settlement judges again (the same map, x0
    and commit of its search) given the settlement's verdict."""
    judged = {(s["map"], tuple(s["x0"]), s["of"]): s["verdict"] for s in settlements}
    return [(kind, {**row, "verdict": judged.get((row["map"], tuple(row["x0"]), row.get("commit")), row["verdict"])}
             if kind == "maps" else row) for kind, row in rows]


def read_settlements():
    """The settlements' rows, if git tracks the file."""
    tracked = git("ls-files", SETTLEMENTS).stdout.decode().split()
    return [json.loads(line) for path in tracked for line in (ROOT / path).read_text().splitlines()]


def same_search(commit, files, now):
    """Whether every file of `files` has at `commit` the code hash `now` gives it."""
    for path in files:
        shown = git("show", f"{commit}:{path}")
        if shown.returncode != 0 or source_hash(shown.stdout, Path(path).suffix) != now[path]:
            return False
    return True


def verdict(commit, files, now):
    """(commit date, "the tree" | "older" | "unknown") of the search that ran at `commit`."""
    shown = git("show", "-s", "--format=%cI", commit) if commit and "dirty" not in commit else None
    if shown is None or shown.returncode != 0:
        return "?", "unknown"
    return shown.stdout.decode().strip(), "the tree" if same_search(commit, files, now) else "older"


def inputs():
    """{path: code hash} of what the table reads: the shards and the search's code (a change to
    either makes a published table stale: tests/test_published.py)."""
    tracked = [path for _, path in shards()] + git("ls-files", SETTLEMENTS).stdout.decode().split()
    return {path: code_hash(ROOT / path) for path in tracked} | _hashes(search_code())


def _hashes(files):
    """{path: code hash now} of the project files `files`."""
    return {path: code_hash(ROOT / path) for path in files}


def tally(rows):
    """{commit: counts} of the shards' rows."""
    counts = {}
    for kind, row in rows:
        c = counts.setdefault(row.get("commit"), dict.fromkeys(COUNTS, 0))
        if kind == "brute force":
            if "missing" not in row:
                c["not compared"] += 1
                continue
            c["states"] += 1
            c["fast"] += row.get("states") == "fast"
            c["small"] += row.get("states") == "small"
            c["large"] += row.get("states") == "large"
            c["arrivals"] += row["n_brute"]
            c["its best"] += row["brute_best"] is not None and same_arrival(row["brute_best"], row["best"])
            c["none found"] += row["n_brute"] == 0
            c["missed"] += len(row["missing"])
        elif kind == "saddle audit":
            c["audited"] += 1
            c["halves"] += row["halves"]
            c["hiding"] += row["hiding"]
            c["hidden arrivals"] += len(row["hidden_arrivals"])
        else:
            column = MAP_COLUMNS.get(row["verdict"])
            if column is None:
                c["not compared"] += 1
                continue
            c["cells"] += 1
            c["cell missed" if column == "missed" else column] += 1
    return counts


def main():
    rows = settled([(kind, json.loads(line)) for kind, path in shards() for line in (ROOT / path).read_text().splitlines()],
                   read_settlements())
    files = search_code()
    now = _hashes(files)
    lines = sorted((*verdict(commit, files, now), commit or "none", c) for commit, c in tally(rows).items())
    print(f"The search's code: {', '.join(files)}.\n")
    print("| code of | committed | its search | brute force: states (fast starts, small kappa, large kappa) | its arrivals | its best the "
          "search's | it found none | missed | maps: cells | same extremal | unsettled, agreeing | the map's slower "
          "| not attained | missed | not compared |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for stamp, judged, commit, c in lines:
        print(f"| {commit} | {stamp[:10]} | {judged} | {c['states']} ({c['fast']}, {c['small']}, {c['large']}) | {c['arrivals']} | {c['its best']} | "
              f"{c['none found']} | {c['missed']} | {c['cells']} | {c['same']} | {c['agree']} | {c['map slower']} | "
              f"{c['not attained']} | {c['cell missed']} | {c['not compared']} |")
    for label, chosen in (("The search as it stands", [line for line in lines if line[1] == "the tree"]),
                          ("Every shard", lines)):
        total = {k: sum(line[3][k] for line in chosen) for k in COUNTS}
        print(f"\n{label} ({len(chosen)} lines): {total['states']} states against the brute "
              f"force ({total['fast']} fast starts, {total['small']} at small kappa, {total['large']} at large kappa; {total['arrivals']} arrivals, its best the search's in "
              f"{total['its best']} states, none found in {total['none found']}; {total['missed']} missed), "
              f"{total['cells']} cells against the maps ({total['cell missed']} missed, {total['not attained']} where "
              f"the map's value is not attained); {total['not compared']} not "
              f"compared (the search not proven optimal). The audit by saddles: {total['audited']} states, "
              f"{total['halves']} halves settled by omega's bound where an arc may pass by a saddle, "
              f"{total['hiding']} hiding a turning point, {total['hidden arrivals']} hidden arrivals before the "
              f"search's best.")


if __name__ == "__main__":
    sys.exit(main())
