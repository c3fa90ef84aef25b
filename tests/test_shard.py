"""A suite split across machines without a cluster (issue 21, item 4): `ocp bench --shard I/N` runs
the I-th of N disjoint slices of the pairs, and `ocp merge` joins the shards' stores into the store
of one run (the same pairs, each once, the same outcomes and T: the solves are deterministic);
merging stores of other suite settings, or two runs of one pair, is refused in one line; bad
--shard values are one line, exit 2."""

import json
import sqlite3

import pytest

from ocp import cli
from ocp.bench import runner, suite
from ocp.bench.store import Store

SUITE = """
name = "split"
repeats = 1
[[cases]]
kind = "swing-up"
kappa = [2.0, 3.0]
[[methods]]
transcription = "extremal-search"
[[methods]]
N = 10
"""


def run(argv, capsys):
    code = cli.main([*map(str, argv), "--json"])
    captured = capsys.readouterr()
    assert code == 0, captured.err[-2000:]
    return json.loads(captured.out)


def table(path):
    """{(case key, method key): (outcome, T, suite settings key)} of a store."""
    with sqlite3.connect(path) as db:
        rows = db.execute("select case_key, method_key, settings_key, record from results").fetchall()
    assert len(rows) == len({(c, m) for c, m, _, _ in rows})
    return {(c, m): (json.loads(r)["outcome"], json.loads(r)["T"], s) for c, m, s, r in rows}


def test_a_shard_is_stable_and_every_pair_is_in_one():
    """The slices partition the pairs, and a pair's slice does not depend on the suite's order or on
    the other pairs it holds (the quick suite's 110 pairs in 3 slices)."""
    pairs = suite.load("quick").pairs()

    def keys(chosen):
        return [(c.key, m.key) for c, m in chosen]

    slices = [keys(runner.shard(pairs, i, 3)) for i in (1, 2, 3)]
    assert sorted(p for s in slices for p in s) == sorted(keys(pairs)) and all(20 < len(s) < 50 for s in slices)
    assert keys(runner.shard(pairs[::-1], 2, 3)) == slices[1][::-1]
    assert keys(runner.shard(pairs[:40], 2, 3)) == [p for p in slices[1] if p in keys(pairs[:40])]


@pytest.fixture(scope="module")
def stores(tmp_path_factory):
    """One run of the suite, its two shards and their merge (the shards written as by two machines)."""
    folder = tmp_path_factory.mktemp("shards")
    path = folder / "split.toml"
    path.write_text(SUITE)
    out = {"suite": path, "one": folder / "one.sqlite", "merged": folder / "merged.sqlite",
           "shards": [folder / f"shard{i}.sqlite" for i in (1, 2)]}
    for argv in ([path, "--store", out["one"]], *([path, "--shard", f"{i}/2", "--store", s]
                                                  for i, s in enumerate(out["shards"], 1))):
        assert cli.main(["bench", *map(str, argv), "--json"]) == 0
    assert cli.main(["merge", str(out["merged"]), *map(str, out["shards"]), "--json"]) == 0
    return out


def test_the_merged_shards_are_the_store_of_one_run(stores, capsys):
    capsys.readouterr()
    one, shards = table(stores["one"]), [table(s) for s in stores["shards"]]
    assert all(shards) and not set(shards[0]) & set(shards[1])          # both slices run, disjoint
    assert table(stores["merged"]) == one and len(one) == 4
    assert {o for o, _, _ in one.values()} <= {"ok", "misses target"}
    merged = Store(stores["merged"], write=False)
    sessions, refs = merged.sessions(), merged.references()
    merged.close()
    assert [s["executor"] for s in sessions] == [f"serial (this process); shard {i}/2 of the pairs" for i in (1, 2)]
    assert len(refs) == 2
    again = run(["merge", stores["merged"], *stores["shards"]], capsys)        # merged twice: nothing added
    assert (again["rows"], again["sessions"], again["references"], again["total"]) == (0, 0, 0, 4)
    assert len(Store(stores["merged"], write=False).sessions()) == 2


def test_a_shard_resumes_into_its_own_store(stores, capsys):
    out = run(["bench", stores["suite"], "--shard", "2/2", "--store", stores["shards"][1]], capsys)
    assert out["shard"] == "2/2" and out["run_now"] == 0 and out["resumed"] == out["pairs"] == \
        len(table(stores["shards"][1]))


def test_conflicting_stores_are_refused_in_one_line(stores, tmp_path, capsys):
    """Two runs of one pair, rows of other suite settings, the output among the inputs: one line,
    exit 2, and nothing written."""
    other = tmp_path / "other.sqlite"
    other.write_bytes(stores["shards"][1].read_bytes())
    key = suite.Suite("s", "", 2, 60.0, 1e-6, (), ()).settings_key
    with sqlite3.connect(other) as db:
        db.execute("update results set settings_key = ?", (key,))
    target = tmp_path / "t.sqlite"
    for argv, words in [([stores["one"], stores["shards"][0]], "with different rows (two runs of it)"),
                        ([stores["shards"][0], other], "different suite settings (miss_tol = 1e-06, repeats = 1, "
                                                       "time_limit_s = none; miss_tol = 1e-06, repeats = 2, "
                                                       "time_limit_s = 60.0)")]:
        assert cli.main(["merge", str(target), *map(str, argv)]) == 2
        err = capsys.readouterr().err
        assert words in err and err.count("\n") == 1 and "Traceback" not in err
    assert not target.exists()                                  # refused before anything was written
    target.write_bytes(stores["one"].read_bytes())
    assert cli.main(["merge", str(target), str(stores["shards"][0]), str(target)]) == 2
    assert "both the merged store and a store to merge" in capsys.readouterr().err
    assert table(target) == table(stores["one"])


@pytest.mark.parametrize("shard", ["0/2", "3/2", "x", "1/0", "1/2/3", " 1/2", "-1/2"])
def test_a_bad_shard_is_one_line(shard, capsys):
    assert cli.main(["bench", "quick", f"--shard={shard}"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--shard" in err and "1 <= I <= N" in err
