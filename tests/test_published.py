"""The published tables and figures (benchmarks/README.md, README.md, benchmarks/results/quick/,
docs/figures/) are those of the code as it stands: each part of `python benchmarks/publish.py`
records the code it ran (benchmarks/results/published.json: every project file its commands
imported, keyed by the hash of its code without docstrings and help texts, `benchmarks/measured.py`;
and the package data), and that code must be what the tree holds now. When this fails, rerun
`python benchmarks/publish.py --only PART` on the committed code and commit what it writes."""

import importlib.util
import json
import re
import subprocess
import sys
import types
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = ROOT / "benchmarks" / "results" / "published.json"
#: part -> the generated blocks (file, name) that must carry its commit
BLOCKS = {
    "direct-error": [("benchmarks/README.md", "direct-error")],
    "bench": [("benchmarks/README.md", "bench-run"), ("benchmarks/README.md", "bench-environment")],
    "standard": [("benchmarks/README.md", "standard-run"), ("benchmarks/README.md", "standard-outcomes"),
                 ("benchmarks/README.md", "standard-environment")],
    "figures": [("README.md", "figures")],
    "failure-maps": [("benchmarks/README.md", "failure-maps")],
    "speed": [("README.md", "search-speed"), ("README.md", "search-cost"), ("README.md", "search-range"),
              ("README.md", "synthesis-speed")],
    "bifurcation": [("README.md", "bifurcation")],
    "completeness": [("benchmarks/README.md", "completeness")],
    "timings": [("README.md", "timings"), ("README.md", "verify-totals")],
}


def block(path, name):
    text = (ROOT / path).read_text(encoding="utf-8")
    match = re.search(rf"<!-- BEGIN generated: {re.escape(name)} .*?-->\n(.*?)<!-- END generated: {re.escape(name)} -->",
                      text, re.S)
    assert match, f"{path} has no generated block {name!r}"
    return match.group(1)


@pytest.fixture(scope="module")
def manifest():
    assert MANIFEST.is_file(), "no benchmarks/results/published.json: run python benchmarks/publish.py"
    return json.loads(MANIFEST.read_text())


def test_every_part_is_published(manifest):
    assert set(manifest) == set(BLOCKS)
    for part, record in manifest.items():
        assert re.fullmatch(r"[0-9a-f]{40}", record["commit"]), \
            f"{part}: published from uncommitted code ({record['commit']}); commit, then rerun publish.py"
        for path, name in BLOCKS[part]:
            assert record["commit"][:12] in block(path, name), f"{path} block {name} is not from {part}'s run"


def test_the_published_files_exist(manifest):
    for suite, prefix in (("quick", "bench"), ("standard", "standard")):
        charts = re.findall(rf"\]\((results/{suite}/[^)]+)\)", block("benchmarks/README.md", f"{prefix}-charts"))
        assert charts and all((ROOT / "benchmarks" / c).is_file() for c in charts)
        for name in ("summary.md", "results.csv"):
            assert (ROOT / "benchmarks/results" / suite / name).is_file()
    figures = re.findall(r"--only ([\w.-]+)", block("README.md", "figures"))
    assert len(figures) == 8 and all((ROOT / "docs/figures" / f"{f}.png").is_file() for f in figures)


def _benchmark(name):
    """The module benchmarks/NAME.py (their folder on the path: they import each other)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))
    return module


def _measured():
    return _benchmark("measured")


@pytest.mark.parametrize("part", list(BLOCKS))
def test_the_code_and_data_each_part_ran_are_unchanged(manifest, part):
    measured = _measured()
    record = manifest[part]
    assert record.get("code"), f"{part}: no record of the code it ran; rerun `python benchmarks/publish.py --only {part}`"
    changed = [f for f, h in record["code"].items() if not (ROOT / f).is_file() or measured.code_hash(ROOT / f) != h]
    data = measured.data_hashes()
    changed += [f"{f} (data)" for f in sorted(set(data) | set(record["data"])) if data.get(f) != record["data"].get(f)]
    assert not changed, (f"{part} was published at {record['commit'][:12]}; since then the code or data it ran "
                         f"changed: {', '.join(changed)}; rerun `python benchmarks/publish.py --only {part}` and "
                         f"commit its output")


def test_the_completeness_table_counts_the_shards_and_the_search_as_they_stand(manifest):
    """The table of the residual assumption's measurements reads the shards of search_residual.py and
    search_vs_maps.py and judges each commit's search against the tree's: a shard added or changed,
    or the search's code changed, makes it stale."""
    now, then = _benchmark("completeness").inputs(), manifest["completeness"]["inputs"]
    changed = sorted(f for f in set(now) | set(then) if now.get(f) != then.get(f))
    assert not changed, (f"the completeness table was published at {manifest['completeness']['commit'][:12]}; since "
                         f"then these changed: {', '.join(changed)}; rerun `python benchmarks/publish.py --only "
                         f"completeness` and commit its output")


@pytest.mark.parametrize("part", list(BLOCKS))
def test_each_part_records_the_project_code_only(manifest, part):
    """A part's record names files of the project's source folders only: a publication from a
    checkout with its virtual environment inside (the README's .venv) once recorded every package
    imported from there, files a clean clone does not have."""
    sources = _measured().SOURCES
    outside = [f for f in manifest[part]["code"] if f.split("/")[0] not in sources]
    assert not outside, f"{part} records files outside {sources}: {outside[:3]}"


def test_a_module_of_a_virtual_environment_in_the_checkout_is_not_the_projects(tmp_path, monkeypatch):
    """A module imported from ROOT/.venv (as from the README's install) is not recorded; one of ocp/ is."""
    measured = _measured()
    module = ROOT / ".venv" / "lib" / "site-packages" / "somepackage.py"
    monkeypatch.setitem(sys.modules, "somepackage", types.SimpleNamespace(__file__=str(module)))
    from ocp.core import problem  # noqa: F401
    recorded = measured.imported_sources()
    assert "ocp/core/problem.py" in recorded and not [f for f in recorded if f.startswith(".venv")]


def test_a_docstring_or_a_help_text_is_not_code(tmp_path):
    measured = _measured()
    before = tmp_path / "a.py"
    before.write_text('"""A module."""\ndef f(p):\n    """Doc."""\n    p.add_argument("--n", help="old")\n'
                      '    return 1  # a comment\n')
    after = tmp_path / "b.py"
    after.write_text('"""Another text."""\ndef f(p):\n    p.add_argument("--n", help="new " + "text")\n    return 1\n')
    changed = tmp_path / "c.py"
    changed.write_text('def f(p):\n    p.add_argument("--n", default=2, help="new")\n    return 1\n')
    assert measured.code_hash(before) == measured.code_hash(after) != measured.code_hash(changed)


def test_a_compiled_extension_is_keyed_by_its_c_sources(tmp_path):
    """An imported extension (a .so) records its C source and headers (pyproject.toml's ext-modules),
    hashed by their bytes: a change to the C code makes the parts that ran it stale."""
    from ocp.indirect import taylor  # noqa: F401 (imports the compiled ocp.indirect._taylor)
    measured = _measured()
    assert {"ocp/indirect/_taylor.c", "ocp/_arrays.h"} <= set(measured.imported_sources())
    source = tmp_path / "k.c"
    source.write_bytes(b"double f(double x) { return x; }\n")
    before = measured.code_hash(source)
    source.write_bytes(b"double f(double x) { return x; } \n")
    assert measured.code_hash(source) != before


# ---- benchmarks/completeness.py: the search's code it follows, and how it counts the shards ----

def test_the_search_code_is_what_searching_imports_at_any_depth():
    """searching.py imports problem.py (which imports model.py), roots.py, near.py and taylor.py, which
    imports the compiled _taylor (its C source and the header pyproject.toml declares); no package
    __init__, nothing of the direct methods."""
    files = _benchmark("completeness").search_code()
    assert {"ocp/indirect/searching.py", "ocp/core/problem.py", "ocp/core/model.py", "ocp/core/roots.py",
            "ocp/indirect/near.py", "ocp/indirect/taylor.py", "ocp/indirect/_taylor.c", "ocp/_arrays.h"} <= set(files)
    assert not [f for f in files if f.endswith("__init__.py") or f.startswith("ocp/direct/")]


def test_a_commit_is_judged_by_the_code_of_the_search_at_it():
    """The search of the commit checked out is the tree's (in a checkout without changes to the search's
    files, as CI's clean clone); ae28c5c's is older (searching.py changed after it: the turns that
    follow their samples, 51fab86); a commit with uncommitted changes, or none recorded, is unknown;
    one file's code changed makes a commit older."""
    module = _benchmark("completeness")
    files = module.search_code()
    head = module.git("rev-parse", "--short", "HEAD").stdout.decode().strip()
    at_head = {path: module.code_hash(ROOT / path) for path in files}
    assert module.verdict(head, files, at_head)[1] == "the tree"
    assert module.verdict("ae28c5c", files, at_head)[1] == "older"
    assert module.verdict(f"{head}-dirty", files, at_head) == module.verdict(None, files, at_head) == ("?", "unknown")
    assert module.verdict(head, files, {**at_head, "ocp/core/roots.py": "0" * 16})[1] == "older"


def test_the_shards_are_counted_by_commit_and_verdict():
    """Brute-force states compared (their arrivals and misses, whether the brute force's best is the
    search's, to 1e-8 relative, and where it found none), one not proven optimal (apart), a fast
    start, one at small kappa, one at large; map cells: the same extremal, unsettled and agreeing, the map slower, the search slower
    unsettled (a miss), a search stopped (apart); audited states, their halves, those hiding a turning
    point and the hidden arrivals."""
    rows = [("brute force", {"commit": "a", "n_brute": 3, "missing": [1.0], "best": 2.0, "brute_best": 1.0}),
            ("brute force", {"commit": "a", "n_brute": 0, "missing": [], "best": 2.0, "brute_best": None}),
            ("brute force", {"commit": "a", "status": "stopped"}),
            ("brute force", {"commit": "b", "n_brute": 1, "missing": [], "states": "fast", "best": 2.0,
                             "brute_best": 2.0 + 1e-9}),
            ("brute force", {"commit": "b", "n_brute": 0, "missing": [], "states": "small", "best": 2.0,
                             "brute_best": None}),
            ("brute force", {"commit": "b", "n_brute": 1, "missing": [], "states": "large", "best": 0.5,
                             "brute_best": 0.5}),
            ("maps", {"commit": "a", "verdict": "same extremal"}),
            ("maps", {"commit": "a", "verdict": "unsettled, agree"}),
            ("maps", {"commit": "a", "verdict": "map slower"}),
            ("maps", {"commit": "a", "verdict": "unsettled, search slower"}),
            ("maps", {"commit": "a", "verdict": "unsettled, not attained"}),
            ("maps", {"commit": "b", "verdict": "stopped"}),
            ("saddle audit", {"commit": "a", "halves": 5, "hiding": 2, "hidden_arrivals": [[0.1, 0.2, [3, 0], 0, 4.0]]}),
            ("saddle audit", {"commit": "a", "halves": 0, "hiding": 0, "hidden_arrivals": []})]
    counts = _benchmark("completeness").tally(rows)
    assert counts["a"] == {"states": 2, "fast": 0, "small": 0, "large": 0, "arrivals": 3, "its best": 0, "none found": 1, "missed": 1,
                           "cells": 5, "same": 1, "agree": 1, "map slower": 1, "not attained": 1, "cell missed": 1,
                           "not compared": 1,
                           "audited": 2, "halves": 5, "hiding": 2, "hidden arrivals": 1}
    b = counts["b"]
    assert (b["states"], b["fast"], b["small"], b["large"], b["its best"], b["none found"], b["cells"],
            b["not compared"]) == (3, 1, 1, 1, 2, 1, 0, 1)


def test_a_settlement_judges_again_only_its_own_cell():
    """A settlement replaces the verdict of the map cell of its map, x0 and search commit (`of`), and
    of no other: the same cell of another commit's search, another cell, a brute-force row."""
    module = _benchmark("completeness")
    cell = {"map": 655, "x0": [2.8, -2.3], "verdict": "unsettled, search slower"}
    rows = [("maps", {**cell, "commit": "a"}), ("maps", {**cell, "commit": "b"}),
            ("maps", {**cell, "x0": [2.8, -2.4], "commit": "a"}), ("brute force", {"commit": "a", "missing": []})]
    out = module.settled(rows, [{"map": 655, "x0": [2.8, -2.3], "of": "a", "verdict": "unsettled, not attained"}])
    assert [row.get("verdict") for _, row in out] == ["unsettled, not attained", "unsettled, search slower",
                                                        "unsettled, search slower", None]


# the cells of map 655 and 581 (benchmarks/search_vs_maps-z.jsonl at 5db98e9): the map's value V below the
# search's T beyond the maps' error estimate, and Newton from the map's (psi, V) diverging; psi is the node's
# interval of final costate angles, V and V_coarse the fine and coarse maps' values there (drawn again)
MAP_655 = dict(kind="swing-up", kappa=0.21660060306489817, x0=(2.827433388230814, -2.325), branch=-2,
               psi=(2.331459, 2.331483), V=7.702554860119428, V_coarse=7.702574636063258, T=7.755984476535616,
               T_error=6.553013045812907e-11)
MAP_581 = dict(kind="swing-up", kappa=0.22971745257716833, x0=(-0.15707963267948966, -1.125), branch=0,
               psi=(5.66959299, 5.68186484), V=9.116213421557052, V_coarse=9.11285697273387, T=9.699121003743494,
               T_error=7.942610396038971e-12)


def test_a_cell_by_a_fold_of_the_map_is_not_attained_and_one_beside_a_jump_is_the_same_extremal():
    """Map 655's node lies beside the fold of its field: its extremals there end at the target on
    an arc u = +1 that turns there, the same curve for every psi (rank 1), which passes x0 at
    1.4e-5 at best: the map's 7.7026 is no extremal's (the search's answer is 7.7560, one switch,
    u = -1 last). Map 581's node lies
    where V jumps between neighbours (9.6, 9.1, 13.3): from the closest approach, Newton finds the
    map's extremal through x0, the search's."""
    module = _benchmark("search_vs_maps")
    fold = module.judge(**MAP_655)
    assert fold["verdict"] == "unsettled, not attained"
    assert 1e-5 < fold["closest_miss"] < 2e-5 and abs(fold["closest_s"] - MAP_655["V"]) < 1e-4
    jump = module.judge(**MAP_581)
    assert jump["verdict"] == "same extremal" and jump["settled_by"] == "closest"
    assert abs(jump["exact_s"] - MAP_581["T"]) < 1e-8


def test_a_shard_records_only_a_commit_that_is_the_code_that_runs(monkeypatch, capsys):
    """`completeness.shard_commit`: this checkout's commit, refused (exit 2, the reason on stderr) where
    the tracked files have uncommitted changes or `ocp` is imported from another checkout."""
    import subprocess

    import ocp
    module = _benchmark("completeness")
    described = {"text": b"abc1234"}
    monkeypatch.setattr(module, "git", lambda *args: subprocess.CompletedProcess(args, 0, described["text"], b""))
    monkeypatch.setattr(ocp, "__file__", str(module.ROOT / "ocp" / "__init__.py"))
    assert module.shard_commit() == "abc1234"
    described["text"] = b"abc1234-dirty"
    with pytest.raises(SystemExit) as stop:
        module.shard_commit()
    assert stop.value.code == 2 and "uncommitted changes" in capsys.readouterr().err
    described["text"] = b"abc1234"
    monkeypatch.setattr(ocp, "__file__", "/elsewhere/checkout/ocp/__init__.py")
    with pytest.raises(SystemExit) as stop:
        module.shard_commit()
    assert stop.value.code == 2 and "imported from /elsewhere/checkout/ocp" in capsys.readouterr().err


def test_a_shard_runner_reads_its_range_and_resumes_after_the_lines_it_holds(tmp_path, capsys):
    """`completeness.shard_range`: OUT FIRST END, else the usage and exit 2 (no traceback); the seeds
    to run, every one before the shard's file exists, then those none of its lines holds."""
    module = _benchmark("completeness")
    out = tmp_path / "shard.jsonl"
    assert module.shard_range([str(out), "3", "7"], "USAGE", "seed") == (out, [3, 4, 5, 6])
    for args in ([], ["out.jsonl", "3"], ["out.jsonl", "3", "seven"], ["--fast", "out.jsonl", "3"]):
        with pytest.raises(SystemExit) as stop:
            module.shard_range(args, "USAGE", "seed")
        assert stop.value.code == 2 and "USAGE" in capsys.readouterr().err
    out.write_text('{"seed": 4, "x": 1}\n{"seed": 9}\n')
    assert module.shard_range([str(out), "3", "7"], "USAGE", "seed") == (out, [3, 5, 6])
