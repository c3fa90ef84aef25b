"""The published tables and figures (benchmarks/README.md, README.md, benchmarks/results/quick/,
docs/figures/) are those of the code as it stands: each part of `python benchmarks/publish.py`
records the commit it measured (benchmarks/results/published.json), and no later commit may change
the measured code (`git log <recorded>..HEAD -- ocp/ <the part's script>`, the data publish.py writes
into ocp/ excepted). When this fails, rerun
`python benchmarks/publish.py` on the committed code and commit what it writes.

Needs git and the history back to the recorded commits (a clone with full history; a shallow CI
checkout must fetch it). Outside a git work tree (an unpacked sdist) there is nothing to compare,
and the test says so by skipping."""

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = ROOT / "benchmarks" / "results" / "published.json"
#: part -> the generated blocks (file, name) that must carry its commit
BLOCKS = {
    "direct-error": [("benchmarks/README.md", "direct-error")],
    "bench": [("benchmarks/README.md", "bench-run"), ("benchmarks/README.md", "bench-environment")],
    "figures": [("README.md", "figures")],
    "failure-maps": [("benchmarks/README.md", "failure-maps")],
    "speed": [("README.md", "search-speed"), ("README.md", "synthesis-speed")],
    "bifurcation": [("README.md", "bifurcation")],
    "timings": [("README.md", "timings"), ("README.md", "verify-totals")],
}


def git(*args):
    return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True)


def in_git_work_tree():
    return shutil.which("git") is not None and git("rev-parse", "--is-inside-work-tree").stdout.strip() == "true"


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
    charts = re.findall(r"\]\((results/quick/[^)]+)\)", block("benchmarks/README.md", "bench-charts"))
    assert charts and all((ROOT / "benchmarks" / c).is_file() for c in charts)
    for name in ("summary.md", "results.csv"):
        assert (ROOT / "benchmarks/results/quick" / name).is_file()
    figures = re.findall(r"--only ([\w.-]+)", block("README.md", "figures"))
    assert len(figures) == 8 and all((ROOT / "docs/figures" / f"{f}.png").is_file() for f in figures)


@pytest.mark.skipif(not in_git_work_tree(), reason="not a git work tree: no history to compare the results with")
@pytest.mark.parametrize("part", list(BLOCKS))
def test_no_commit_since_the_published_one_changes_the_measured_code(manifest, part):
    record = manifest[part]
    commit = record["commit"]
    exists = git("cat-file", "-e", f"{commit}^{{commit}}")
    shallow = git("rev-parse", "--is-shallow-repository").stdout.strip() == "true"
    assert exists.returncode == 0, (f"{part}: the recorded commit {commit} is not in this history"
                                    + (" (a shallow clone: fetch the full history)" if shallow else
                                       ": publish from a commit of this branch"))
    later = git("log", "--format=%h %s", f"{commit}..HEAD", "--", *record["measured"]).stdout.strip()
    assert not later, (f"{part} was published at {commit[:12]}; since then these commits changed the measured code "
                       f"({', '.join(record['measured'])}); rerun `python benchmarks/publish.py` and commit "
                       f"its output:\n{later}")
