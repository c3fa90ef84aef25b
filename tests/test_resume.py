"""Resume always resumes (issue 18, items 4 and 6): a store left with a hot journal by a SIGKILL
mid-transaction opens for `ocp report` (read from a private copy: the user's files unchanged) and
for `ocp bench` (SQLite rolls the journal back); a WAL-mode store is reported without -wal or -shm
files appearing; a full disk says so; `ocp bench` killed at random moments resumes every time and
ends with every row once; a --scheduler that is not Dask is refused within its timeout before the
store is created.

References: SQLite's documentation of hot journals ("atomic commit", section 4.2: a reader rolls a
hot journal back, which needs write access) and of WAL mode (readers need the -shm file), the
header field of WAL mode (bytes 18-19 = 2, "database file format"), and the contract of
ocp/bench/store.py. The runs use stand-ins for the reference and the solve (no solve here).
"""

import hashlib
import random
import socket
import sqlite3
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from ocp import cli
from ocp.bench import report, suite
from ocp.bench.store import Store
from ocp.core import parallel
from ocp.core.errors import Fault

SUITE = """
name = "tiny"
[[cases]]
kind = "swing-up"
kappa = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
[[methods]]
N = [20, 30]
"""

#: `ocp bench` with stand-ins: a reference at once, a measurement in 50 ms, an environment of one key
BENCH = """
import sys, time
from ocp import cli
from ocp.bench import environment, runner
from ocp.bench.row import Measurement, Reference
def reference(case):
    return Reference(problem=case.problem_key, T=4.0, T_error=1e-12, source="a stand-in", arc_signs=(1, -1),
                     switch_times=(1.0,))
def measure(case, method, repeats=1, miss_tol=1e-6, time_limit_s=None):
    time.sleep(0.05)
    return Measurement(success=True, status="optimal", T=4.0, T_error=1e-12, arc_signs=(1, -1), switch_times=(1.0,),
                       total_time_s=0.02)
runner.reference, runner.measure = reference, measure
environment.environment = lambda: {"stand-in": True}
sys.exit(cli.main(["bench", sys.argv[1], "--store", sys.argv[2]]))
"""

#: a writer that dies by SIGKILL in the middle of a transaction, its pages spilled: a hot journal
KILLED_WRITER = """
import os, signal, sqlite3, sys
db = sqlite3.connect(sys.argv[1], isolation_level=None)
db.execute("pragma cache_size = 1")
db.execute("begin immediate")
for i in range(3000):
    db.execute("insert into claims values (?, ?, ?)", ("c%d" % i * 20, "m", 1))
os.kill(os.getpid(), signal.SIGKILL)
"""


@pytest.fixture
def tiny(tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(SUITE)
    return path


def digest(*paths):
    return [hashlib.sha256(Path(p).read_bytes()).hexdigest() if Path(p).exists() else None for p in paths]


def bench(tiny, store, timeout=120):
    return subprocess.run([sys.executable, "-c", BENCH, str(tiny), str(store)], capture_output=True, text=True,
                          timeout=timeout)


def sessions(store):
    """The sessions in the store, read-only (0 while it cannot be read: absent, locked, or a hot journal)."""
    try:
        with sqlite3.connect(store.as_uri() + "?mode=ro", uri=True, timeout=0.01) as db:
            return db.execute("select count(*) from sessions").fetchone()[0]
    except sqlite3.Error:
        return 0


def rows(store):
    with sqlite3.connect(store) as db:
        return db.execute("select case_key, method_key from results").fetchall()


def test_a_hot_journal_is_reported_untouched_and_resumed(tiny, tmp_path):
    """Issue 18: 3 of 12 kills left a hot journal, and then report and resume both failed "attempt to
    write a readonly database". Now the report reads a recovered private copy (the store and its
    journal keep their bytes), and the next `ocp bench` rolls the journal back and resumes."""
    store = tmp_path / "s.sqlite"
    assert bench(tiny, store).returncode == 0 and len(rows(store)) == 12
    with sqlite3.connect(store) as db:
        db.execute("delete from results where rowid in (select rowid from results order by rowid desc limit 3)")
    assert subprocess.run([sys.executable, "-c", KILLED_WRITER, str(store)], timeout=60).returncode == -9
    journal = store.with_name(store.name + "-journal")
    assert journal.stat().st_size > 0
    with pytest.raises(sqlite3.OperationalError, match="readonly"):          # what a read-only reader meets
        sqlite3.connect(store.as_uri() + "?mode=ro", uri=True).execute("select count(*) from claims").fetchone()
    before = digest(store, journal)
    assert report.report(store)["runs"] == 9
    assert digest(store, journal) == before
    result = bench(tiny, store)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "12 runs (3 now, 9 already stored)" in result.stdout and not journal.exists()
    assert result.stderr.startswith("ocp bench: suite tiny, 12 pairs")     # said at once (issue 24)
    assert sorted(rows(store)) == sorted(set(rows(store))) and len(rows(store)) == 12


def test_a_wal_store_is_reported_without_files_beside_it(tiny, tmp_path):
    """Issue 18: a WAL-mode store got -wal and -shm files when reported. Now nothing appears beside
    it, its bytes stay, and rows still in the write-ahead log are read."""
    store = tmp_path / "wal.sqlite"
    assert bench(tiny, store).returncode == 0
    with sqlite3.connect(store) as db:
        assert db.execute("pragma journal_mode = wal").fetchone() == ("wal",)
    assert not store.with_name(store.name + "-wal").exists()
    before, listing = digest(store), sorted(p.name for p in tmp_path.iterdir())
    assert report.report(store)["runs"] == 12
    assert digest(store) == before and sorted(p.name for p in tmp_path.iterdir()) == listing


def test_a_full_disk_says_so(tmp_path):
    """Issue 18: on a full disk the message was "cannot rollback - no transaction is active" (SQLite
    had rolled back already), masking the cause. Here the disk is full at the store's page limit."""
    db = Store(tmp_path / "full.sqlite")
    session = db.open_session("full", "test", {})
    pages = db.db.execute("pragma page_count").fetchone()[0]
    db.db.execute(f"pragma max_page_count = {pages}")
    with pytest.raises(Fault) as caught:
        db.add_result("c", "m", session, {"text": "x" * 100_000})
    db.close()
    assert "full" in str(caught.value) and "cannot rollback" not in str(caught.value)


def test_killed_at_random_moments_it_resumes_every_time(tiny, tmp_path):
    """Issue 18 (done when): `ocp bench` of a fast suite SIGKILLed at random moments (seeded), six
    times (each after its run has opened its session, whatever the machine's load): after every
    kill the report opens the store and the next run resumes; the last run ends with every pair's
    row once."""
    tiny.write_text(SUITE.replace("kappa = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0]", "kappa = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0, "
                                  "1.1, 1.2, 1.3, 1.4, 1.5, 1.6]"))
    store, rng, pairs = tmp_path / "killed.sqlite", random.Random(18), len(suite.load(tiny).pairs())
    kills, seen, journals = 0, [], 0
    while kills < 6:
        proc = subprocess.Popen([sys.executable, "-c", BENCH, str(tiny), str(store)], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        begun, before = time.monotonic(), sessions(store)
        while sessions(store) <= before and proc.poll() is None and time.monotonic() - begun < 120:
            time.sleep(0.01)                        # until this run has opened its session
        time.sleep(rng.uniform(0.0, 0.5))           # it writes all its rows in about 1.5 s on a quiet machine
        if proc.poll() is not None:
            break                                   # it finished: nothing left to kill
        proc.kill()
        proc.wait()
        kills += 1
        if store.exists():
            journals += store.with_name(store.name + "-journal").exists()
            seen.append(report.report(store)["runs"])
    result = bench(tiny, store)
    assert result.returncode == 0, result.stderr[-2000:]
    print(f"{kills} kills, {journals} left a journal, rows after each: {seen}")
    assert kills >= 3 and seen == sorted(seen) and any(0 < n < pairs for n in seen)   # killed mid-run; rows stay
    assert len(rows(store)) == len(set(rows(store))) == pairs == 24


def test_a_server_that_is_not_dask_is_refused_within_the_timeout(tiny, tmp_path, monkeypatch, capsys):
    """Issue 18: --scheduler at a TCP server that accepts and says nothing hung silently (150 s), the
    store already created. Now: one line, exit 2, within the connect timeout, no store."""
    server = socket.create_server(("127.0.0.1", 0))
    held = []
    threading.Thread(target=lambda: held.append(server.accept()), daemon=True).start()
    monkeypatch.setattr(parallel, "CONNECT_S", 2.0)
    store = tmp_path / "s.sqlite"
    begun = time.monotonic()
    code = cli.main(["bench", str(tiny), "--store", str(store), "--scheduler",
                     f"tcp://127.0.0.1:{server.getsockname()[1]}"])
    elapsed = time.monotonic() - begun
    server.close()
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "not a Dask scheduler" in err and "within 2 s" in err
    assert elapsed < 8 and not store.exists()
