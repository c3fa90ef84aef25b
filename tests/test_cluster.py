"""The suite on a real Dask cluster (issue 21, item 4), started as a user starts one: a `dask
scheduler` process and two `dask worker` processes on 127.0.0.1 (random ports, each worker with
its nanny, which restarts it), `ocp bench --scheduler FILE` (the scheduler file) in a process of
its own. Workers are SIGKILLed in the middle of a pair (seen running in the worker's own call
stacks): killed once, its pairs run again elsewhere and every row is stored once, each a solve's
answer; killed every time it runs, the pair is given up after `distributed.scheduler.allowed-failures`
+ 1 deaths (1 + 1 here) and stored once as a failure row, not retried forever. Every row is written
by the bench's process alone. Bad --scheduler values: one line, exit 2.

Dask's documentation: "Why did my worker die?" (KilledWorker, allowed-failures); a killed worker's
tasks, running or held, are each counted once (`Scheduler.remove_worker`).
"""

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

import ocp
from ocp import cli
from ocp.core import parallel

ROOT = Path(ocp.__file__).resolve().parents[1]
SUITE = """
name = "cluster"
repeats = 1
[[cases]]
kind = "swing-up"
kappa = [1.0, 2.0]
[[methods]]
transcription = "extremal-search"
[[methods]]
N = 100
"""
BENCH = "import sys; from ocp import cli; sys.exit(cli.main(sys.argv[1:]))"


def _start(argv, log, env):
    """A process in a group of its own (ended with its children by `_end`), its output to `log`."""
    with open(log, "w") as out:
        return subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT, env=env, start_new_session=True)


def _end(proc):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """(scheduler file, a Client of the test, logs): a scheduler and two single-threaded workers
    (each with its nanny, which restarts a killed worker), all ended at teardown."""
    distributed = pytest.importorskip("distributed")
    dask = Path(sys.executable).with_name("dask")
    if not dask.exists():
        pytest.skip("the dask command line is not installed beside this Python")
    env = dict(os.environ, PYTHONPATH=str(ROOT), DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES="1")
    tmp_path = tmp_path_factory.mktemp("cluster")
    file, procs, logs = tmp_path / "scheduler.json", [], [tmp_path / f"{n}.log" for n in ("scheduler", "w1", "w2")]
    client = None
    try:
        procs.append(_start([dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                             "--scheduler-file", file], logs[0], env))
        begun, address = time.monotonic(), None
        while address is None and procs[0].poll() is None and time.monotonic() - begun < 60:
            time.sleep(0.05)
            try:
                address = json.loads(file.read_text())["address"]
            except (OSError, ValueError):       # not yet written, or written in part
                pass
        assert address, logs[0].read_text()[-2000:]
        for log in logs[1:]:
            procs.append(_start([dask, "worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard",
                                 "--host", "127.0.0.1", "--local-directory", tmp_path / "work"], log, env))
        client = distributed.Client(address, timeout=60)
        client.wait_for_workers(2, timeout=120)
        yield file, client, logs
    finally:
        if client is not None:
            client.close()
        for proc in reversed(procs):
            _end(proc)


def _running(client, dead):
    """{task key: (worker address, pid)} of the pairs being solved by a direct method now on the
    workers not killed (`dead`): the tasks whose call stack on their worker is inside
    `ocp.bench.measurement.measure` and `ocp.direct` (asked of each worker, not through the
    scheduler, which would wait for a killed one)."""
    inside = (f"{os.sep}ocp{os.sep}bench{os.sep}measurement.py", f"{os.sep}ocp{os.sep}direct{os.sep}")
    alive = [w for w in client.scheduler_info()["workers"] if w not in dead]
    stacks = client.run(lambda dask_worker: (os.getpid(), dask_worker.get_call_stack()), workers=alive,
                        on_error="ignore") if alive else {}
    return {key: (worker, pid) for worker, (pid, tasks) in stacks.items() for key, frames in tasks.items()
            if all(any(part in frame for frame in frames) for part in inside)}


def _bench_killing(cluster, tmp_path, name, suite, times):
    """`ocp bench` of `suite` on the cluster, the worker running the first direct pair seen SIGKILLed
    each time that pair runs, `times` times: (its JSON summary, its rows as stored, kills, whether
    the pair was seen running again after the last kill)."""
    file, client, _ = cluster
    path, store = tmp_path / f"{name}.toml", tmp_path / f"{name}.sqlite"
    path.write_text(suite)
    bench = subprocess.Popen([sys.executable, "-c", BENCH, "bench", path, "--store", store, "--scheduler", file,
                              "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env=dict(os.environ, PYTHONPATH=str(ROOT)))
    target, kills, again, dead = None, 0, False, set()
    try:
        while bench.poll() is None:
            try:
                running = _running(client, dead)
            except OSError:                 # a worker that died while asked
                continue
            for key, (worker, pid) in running.items():
                target = target or key
                if key == target and kills < times:
                    os.kill(pid, signal.SIGKILL)
                    kills, again = kills + 1, False
                    dead.add(worker)
                elif key == target:
                    again = True
            time.sleep(0.02)
        out, err = bench.communicate(timeout=60)
    finally:
        if bench.poll() is None:
            bench.kill()
            bench.wait()
    assert bench.returncode == 0, err[-3000:]
    summary = json.loads(out)
    with sqlite3.connect(store) as db:
        rows = db.execute("select case_key, method_key, session, record from results").fetchall()
        assert db.execute("select count(*) from claims").fetchone()[0] == 0
    assert len(rows) == len({r[:2] for r in rows}) == summary["pairs"] == summary["run_now"]     # each pair once
    assert {r[2] for r in rows} == {summary["session"]}                   # written by the bench's process alone
    address = json.loads(file.read_text())["address"]
    records = [json.loads(r[3]) for r in rows]
    assert all(r["timing"]["executor"] == f"dask {address}" for r in records)
    return summary, records, kills, again


def test_a_worker_killed_mid_pair_loses_nothing_and_duplicates_nothing(cluster, tmp_path):
    """Killed once in the middle of a pair, its worker's pairs run again elsewhere: every row once,
    each a solve's answer."""
    summary, records, kills, again = _bench_killing(cluster, tmp_path, "once", SUITE, 1)
    assert kills == 1 and again and len(records) == 4
    assert all(r["outcome"] == "ok" and r["total_time_s"] > 0 for r in records), \
        [(r["label"], r["outcome"], r["message"]) for r in records]


def test_a_pair_that_kills_every_worker_is_a_failure_row(cluster, tmp_path):
    """Its worker killed each time it runs, the pair is given up after allowed-failures + 1 = 2
    deaths: its row is a solver error saying so, stored once."""
    one = SUITE.replace("kappa = [1.0, 2.0]", "kappa = 1.0").replace('transcription = "extremal-search"\n[[methods]]\n',
                                                                     "")
    summary, records, kills, again = _bench_killing(cluster, tmp_path, "always", one, 2)
    assert kills == 2 and not again and len(records) == 1
    row = records[0]
    assert row["outcome"] == "solver error" and row["N"] == 100 and row["label"].endswith("N=100")
    assert "each of the 2 Dask workers that ran it died" in row["message"] and "allowed-failures = 1" in row["message"]


@pytest.mark.parametrize("text, words", [
    ('{"address": "ws://127.0.0.1:8786"}', "without an accepted scheduler \"address\""),
    ('{"address": "tcp://127.0.0.1:70000"}', "without an accepted scheduler \"address\""),
    ('["tcp://127.0.0.1:8786"]', "without an accepted scheduler \"address\""),
    ("tcp://127.0.0.1:8786", "is not a scheduler file"),
])
def test_a_scheduler_file_must_name_an_accepted_address(text, words, tmp_path, capsys):
    """--scheduler FILE reads the JSON that `dask scheduler --scheduler-file` writes: only its
    "address", on the allow-list (tcp:// or tls://, a port from 1 to 65535)."""
    pytest.importorskip("distributed")
    path = tmp_path / "scheduler.json"
    path.write_text(text)
    assert cli.main(["bench", "quick", "--store", str(tmp_path / "s.sqlite"), "--scheduler", str(path)]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and "tcp://host:8786 or tls://host:8786" in err
    assert not (tmp_path / "s.sqlite").exists()


@pytest.mark.parametrize("address", ["ws://127.0.0.1:8786", "ucx://127.0.0.1:8786", "tcp://127.0.0.1:0",
                                     "inproc://x", "no-such-file.json"])
def test_only_tcp_and_tls_addresses_are_accepted(address, tmp_path, capsys):
    pytest.importorskip("distributed")
    assert cli.main(["bench", "quick", "--store", str(tmp_path / "s.sqlite"), "--scheduler", address]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--scheduler" in err and "tcp://host:8786 or tls://host:8786" in err


def test_a_silent_server_on_tls_is_refused_within_the_timeout(monkeypatch):
    """tls:// is probed too: a server that accepts and never answers the TLS handshake is refused."""
    import socket
    import threading

    server, held = socket.create_server(("127.0.0.1", 0)), []
    threading.Thread(target=lambda: held.append(server.accept()), daemon=True).start()
    begun = time.monotonic()
    with pytest.raises(ocp.core.errors.InputError, match="sent no handshake within 1 s"):
        parallel.probe_scheduler(f"tls://127.0.0.1:{server.getsockname()[1]}", timeout=1.0)
    server.close()
    assert time.monotonic() - begun < 5
