"""The results store and `ocp report` as issue 11 asks: reports open a store read-only and refuse a
file that is not an ocp store of this schema version, leaving its bytes unchanged; a corrupted store
or an unwritable --out is one line and writes nothing half; a full disk keeps every finished row and
says how many; concurrent `ocp bench` runs claim pairs instead of running each twice, recover the
claims of a dead process, and say when a timing was shared; workers die with their parent.

References: the conventions of ocp/core/errors.py (InputError: one line "error: ...", exit 2;
Fault: one line "failed: ...", exit 1; nothing finished lost), SQLite's read-only URI mode and
header fields (application_id, user_version), and the contract of ocp/bench/store.py. The runner
is exercised with stand-ins for the reference and the solve (`fake`), so no test here solves.
"""

import errno
import hashlib
import json
import os
import signal
import sqlite3
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from ocp import cli
from ocp.bench import runner, store as store_module, suite
from ocp.bench.row import Measurement, Reference
from ocp.bench.store import Store
from ocp.core import files
from ocp.core.parallel import SerialExecutor
from ocp.core.errors import Fault

SUITE = """
name = "tiny"
[[cases]]
kind = "swing-up"
kappa = [1.0, 0.5]
[[methods]]
N = [20, 30]
"""


def fake_reference(case):
    return Reference(problem=case.problem_key, T=4.0, T_error=1e-12, source="a stand-in", arc_signs=(1, -1),
                     switch_times=(1.0,))


def fake_measure(case, method, repeats=1, miss_tol=1e-6, time_limit_s=None):
    """N = 20: a Measurement as the search gives it, on the reference; otherwise a build error."""
    if method.N != 20:
        return Measurement(success=False, status="build_error", message="build error: a stand-in")
    return Measurement(success=True, status="optimal", T=4.0 + 1e-13, T_error=1e-12, arc_signs=(1, -1),
                       switch_times=(1.0,), total_time_s=0.01)


@pytest.fixture
def fake(monkeypatch):
    """The runner with stand-ins for the reference and the solve: every row is a real row of
    `ocp bench` (outcome "ok" at N = 20, "build error" otherwise)."""
    monkeypatch.setattr(runner, "reference", fake_reference)
    monkeypatch.setattr(runner, "measure", fake_measure)


@pytest.fixture
def tiny(tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(SUITE)
    return path


def run(the_suite, path):
    """One `ocp bench` session, serial, in this process: its result."""
    db = Store(path)
    try:
        return runner.run(the_suite, db, SerialExecutor(), 1, "serial", {"test": True})
    finally:
        db.close()


def digest(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def one_line(err, start):
    return err.count("\n") == 1 and err.startswith(start) and "Traceback" not in err


@pytest.fixture
def stored(tmp_path, tiny, fake):
    """A store with the four rows of the tiny suite."""
    path = tmp_path / "tiny.sqlite"
    assert len(run(suite.load(tiny), path)["records"]) == 4
    return path


def foreign_sqlite(path):
    with sqlite3.connect(path) as db:
        db.execute("create table notes (text)")
        db.execute("insert into notes values ('mine')")
    return path


@pytest.mark.parametrize("kind", ["foreign sqlite", "empty file", "random bytes", "store of another version",
                                  "valid store"])
def test_report_never_changes_its_input(kind, tmp_path, stored, capsys):
    """Issue 11: `ocp report` opened its input read-write (a foreign SQLite file gained three tables, an
    empty file became a database). Now the input's bytes are the same after the report, and a file
    that is not an ocp store is refused in one line, nothing written: bad input, exit 2 (issue 24;
    exit 1 before)."""
    path = tmp_path / "input.sqlite"
    if kind == "valid store":
        path = stored
    elif kind == "foreign sqlite":
        foreign_sqlite(path)
    elif kind == "store of another version":
        path.write_bytes(stored.read_bytes())
        with sqlite3.connect(path) as db:
            db.execute("pragma user_version = 99")
    else:
        path.write_bytes(b"" if kind == "empty file" else os.urandom(3000))
    before, out = digest(path), tmp_path / "out"
    code = cli.main(["report", str(path), "--out", str(out)])
    err = capsys.readouterr().err
    assert digest(path) == before
    if kind == "valid store":
        assert code == 0 and (out / "summary.md").is_file()
    else:
        assert code == 2 and one_line(err, "error:") and not out.exists()
        assert "not an ocp results store" in err or "schema version 99" in err or "not a database" in err


def test_bench_refuses_a_foreign_store_untouched(tmp_path, tiny, capsys):
    """Issue 11: `ocp bench --store` on a file of another program leaves it as it was (bad input,
    exit 2 as for `ocp report`, issue 24; exit 1 before)."""
    path = foreign_sqlite(tmp_path / "other.db")
    before = digest(path)
    assert cli.main(["bench", str(tiny), "--store", str(path)]) == 2
    assert one_line(capsys.readouterr().err, "error:") and digest(path) == before


def corrupt(path, how):
    with sqlite3.connect(path) as db:
        first = "(select min(rowid) from results)"
        record = json.loads(db.execute(f"select record from results where rowid = {first}").fetchone()[0])
        if how == "undecodable record":
            db.execute(f"update results set record = cast(x'7b22ff' as text) where rowid = {first}")
        elif how == "missing column":
            db.execute("alter table results rename column record to something_else")
        elif how == "bad JSON":
            db.execute(f"update results set record = '{{\"case\": ' where rowid = {first}")
        elif how == "missing key":
            del record["outcome"]
            db.execute(f"update results set record = ? where rowid = {first}", (json.dumps(record),))
        elif how == "NaN in a record":
            db.execute(f"update results set record = ? where rowid = {first}",
                       (json.dumps(dict(record, total_time_s=float("nan"))),))
        elif how == "a list, not a record":
            db.execute(f"update results set record = '[1, 2]' where rowid = {first}")
        elif how == "a string for a number":
            db.execute(f"update results set record = ? where rowid = {first}",
                       (json.dumps(dict(record, total_time_s="fast")),))
        elif how == "missing table":
            db.execute("drop table sessions")


@pytest.mark.parametrize("how", ["undecodable record", "missing column", "bad JSON", "missing key", "NaN in a record",
                                 "a list, not a record", "a string for a number", "missing table"])
def test_corrupted_store_is_one_line_and_nothing_is_written(how, stored, tmp_path, capsys):
    """Issue 11: a corrupted or wrong-schema store gave tracebacks (and NaN a half-written report).
    Every record is checked before a file is written: one line, exit 1, no output folder."""
    corrupt(stored, how)
    before = digest(stored)
    out = tmp_path / "out"
    assert cli.main(["report", str(stored), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert one_line(err, "failed:") and str(stored) in err and not out.exists() and digest(stored) == before


@pytest.mark.parametrize("command", [["report", "STORE"], ["figures", "--only", "profiles", "--store", "STORE"]])
def test_unwritable_out_is_one_line(command, stored, tmp_path, capsys):
    """Issue 11: an --out that cannot be created (here: under a regular file) is a fault of the
    environment, one line and exit 1, for `ocp report` and `ocp figures`."""
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    argv = [str(stored) if a == "STORE" else a for a in command] + ["--out", str(blocker / "out")]
    assert cli.main(argv) == 1
    err = capsys.readouterr().err
    assert one_line(err, "failed:") and "a-file" in err


def test_a_file_is_written_whole_or_not_at_all(tmp_path, monkeypatch):
    """Issue 11 (nothing written half): a write that fails midway (a full disk) leaves the previous
    file as it was and no temporary file; the failure is a Fault."""
    target = tmp_path / "summary.md"
    target.write_text("the previous report\n")

    def full_disk(f):
        f.write("half of a new rep")
        raise OSError(errno.ENOSPC, "No space left on device")

    with pytest.raises(Fault, match="No space left on device"):
        with files.replacing(target) as f:
            full_disk(f)
    assert target.read_text() == "the previous report\n" and os.listdir(tmp_path) == ["summary.md"]
    files.write_text(target, "new\n")
    assert target.read_text() == "new\n" and os.listdir(tmp_path) == ["summary.md"]


def test_full_disk_during_bench_keeps_every_finished_row(tiny, tmp_path, fake, monkeypatch, capsys):
    """Issue 11: a full disk while `ocp bench` stores rows: one line (exit 1) saying how many rows are
    kept; they are, and the same command resumes with the rest."""
    path = tmp_path / "full.sqlite"
    add = Store.add_result
    calls = []

    def fills_up(self, *args, **kwargs):
        calls.append(1)
        if len(calls) == 3:
            with self._guard("write to"):
                raise sqlite3.OperationalError("database or disk is full")
        return add(self, *args, **kwargs)

    monkeypatch.setattr(Store, "add_result", fills_up)
    assert cli.main(["bench", str(tiny), "--store", str(path)]) == 1
    err = capsys.readouterr().err.splitlines()[-1]
    assert err.startswith("failed:") and "disk is full" in err and "2 finished rows are kept" in err
    monkeypatch.setattr(Store, "add_result", add)
    result = run(suite.load(tiny), path)
    assert (len(result["records"]), result["resumed"]) == (2, 2)
    db = Store(path, write=False)
    assert not db.db.execute("select * from claims").fetchall() and len(db.results()) == 4
    db.close()


def dead_pid():
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def test_claims_of_a_live_writer_are_left_and_a_dead_ones_taken(tiny, tmp_path, fake):
    """Issue 11: two runs on one store both ran every pair. A pair claimed by a live `ocp bench` is
    left to it (a note says so) and the rows timed meanwhile say so; a claim of a dead process
    (its pid gone) is taken over; once the other ends, the same command runs what it left."""
    path, the_suite = tmp_path / "shared.sqlite", suite.load(tiny)
    (c1, m1), (c2, m2) = the_suite.pairs()[:2]
    db = Store(path)
    live = db.open_session("other", "test", {})
    dead = db.open_session("crashed", "test", {})
    db.db.execute("update sessions set pid = ? where id = ?", (dead_pid(), dead))
    assert db.claim(c1.key, m1.key, the_suite.settings_key, live) == "mine"
    assert db.claim(c2.key, m2.key, the_suite.settings_key, dead) == "mine"
    result = run(the_suite, path)
    assert len(result["records"]) == 3 and result["claimed_elsewhere"] == 1
    assert any("another ocp bench" in note for note in result["notes"])
    assert all(r.timing.concurrent_sessions == (live,) and "another ocp bench" in r.timing.note
               for r in result["records"])
    db.end_session(live)
    again = run(the_suite, path)
    assert len(again["records"]) == 1 and again["resumed"] == 3 and again["claimed_elsewhere"] == 0
    assert again["records"][0].timing.note == "timed alone"
    db.close()


def test_concurrent_writers_run_each_pair_once(tmp_path, fake, monkeypatch):
    """Issue 11: two `ocp bench` sessions writing one store at the same time (threads here, each with
    its own connection) run every pair exactly once between them."""
    path = tmp_path / "suite.toml"
    path.write_text(SUITE.replace("kappa = [1.0, 0.5]", "kappa = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0]"))
    the_suite, measured = suite.load(path), []

    def slow(case, method, repeats=1, miss_tol=1e-6, time_limit_s=None):
        measured.append((case.key, method.key))
        time.sleep(0.02)
        return fake_measure(case, method)

    monkeypatch.setattr(runner, "measure", slow)
    Store(tmp_path / "s.sqlite").close()
    results = []
    threads = [threading.Thread(target=lambda: results.append(run(the_suite, tmp_path / "s.sqlite"))) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(measured) == sorted({(c.key, m.key) for c, m in the_suite.pairs()})
    assert sum(len(r["records"]) for r in results) == len(the_suite.pairs()) == 12


def test_a_changed_setting_runs_the_pair_again(tiny, tmp_path, fake):
    """Issue 11: settings outside a row's key (miss_tol, time_limit_s, repeats) left stale rows after
    the suite was fixed. A row is resumed only with the settings it was run with; otherwise the pair
    runs again and its row is replaced."""
    path, first = tmp_path / "s.sqlite", suite.load(tiny)
    assert len(run(first, path)["records"]) == 4
    for change in ({"miss_tol": 1e-3}, {"time_limit_s": 5.0}, {"repeats": 2}):
        fixed = suite.Suite(**{**first.__dict__, **change})
        result = run(fixed, path)
        assert (len(result["records"]), result["resumed"]) == (4, 0)
        assert all(getattr(r, k) == v for r in result["records"] for k, v in change.items())
        assert run(fixed, path)["resumed"] == 4
    db = Store(path, write=False)
    assert len(db.results()) == 4
    db.close()


def children(pid):
    """The pids of the processes whose parent is `pid` (Linux /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid and fields[0] != "Z":
            found.append(int(stat.parent.name))
    return found


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_workers_die_with_a_killed_parent_and_its_claims_are_recovered(tiny, tmp_path, fake):
    """Issue 11: after SIGKILL of a `--jobs 2` parent its workers ran on as orphans. Now they end with
    it, and the next run takes over the pairs it had claimed."""
    path = tmp_path / "killed.sqlite"
    script = ("import sys, time\nfrom ocp import cli\nfrom ocp.bench import runner\nfrom ocp.bench.row import Reference\n"
              "def reference(case):\n"
              "    return Reference(problem=case.problem_key, T=None, T_error=None, source='none')\n"
              "def measure(*args):\n"
              "    time.sleep(600)\n"
              "runner.reference, runner.measure = reference, measure\n"
              f"sys.exit(cli.main(['bench', {str(tiny)!r}, '--store', {str(path)!r}, '--jobs', '2']))\n")
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.time() + 120
        claims = []
        while time.time() < deadline and len(claims) < 2:
            time.sleep(0.2)
            if path.exists():
                try:
                    with sqlite3.connect(path, timeout=10) as db:
                        claims = db.execute("select * from claims").fetchall()
                except sqlite3.OperationalError:         # not created yet
                    claims = []
        workers = children(proc.pid)
        assert len(claims) >= 2 and len(workers) >= 2
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    deadline = time.time() + 20
    while time.time() < deadline and any(store_module.process_alive(w) for w in workers):
        time.sleep(0.2)
    assert not any(store_module.process_alive(w) for w in workers)
    result = run(suite.load(tiny), path)
    assert len(result["records"]) == 4 and result["claimed_elsewhere"] == 0
