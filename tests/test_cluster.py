"""The suite on a real Dask cluster (issue 21, item 4), started as a user starts one: a `dask
scheduler` process and two `dask worker` processes on 127.0.0.1 (random ports), `ocp bench
--scheduler FILE` (the scheduler file) in a process of its own. Workers are SIGKILLed in the
middle of pairs (seen running through the scheduler's call stacks of its workers): a pair whose
worker died once runs again elsewhere and its row is stored once; a pair that killed its worker
every time it ran is stored once as a failure row (Dask gives up after
`distributed.scheduler.allowed-failures` deaths, set to 1 here), not retried forever. Every row
is written by the bench's process alone, each pair once.

Dask's documentation: "Why did my worker die?" (KilledWorker, allowed-failures) and the scheduler's
worker-saturation (1.0 here, so that a worker holds only the task it runs: a kill marks that task
alone as suspicious).
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
N = 40
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


@pytest.fixture
def cluster(tmp_path):
    """(scheduler file, a Client of the test, logs): a scheduler and two single-threaded workers
    (each with its nanny, which restarts a killed worker), all ended at teardown."""
    distributed = pytest.importorskip("distributed")
    dask = Path(sys.executable).with_name("dask")
    if not dask.exists():
        pytest.skip("the dask command line is not installed beside this Python")
    env = dict(os.environ, PYTHONPATH=str(ROOT), DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES="1",
               DASK_DISTRIBUTED__SCHEDULER__WORKER_SATURATION="1.0")
    file, procs, logs = tmp_path / "scheduler.json", [], [tmp_path / f"{n}.log" for n in ("scheduler", "w1", "w2")]
    client = None
    try:
        procs.append(_start([dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                             "--scheduler-file", file], logs[0], env))
        begun = time.monotonic()
        while not file.exists() and procs[0].poll() is None and time.monotonic() - begun < 60:
            time.sleep(0.05)
        address = json.loads(file.read_text())["address"]
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


def _running(client):
    """{task key: worker address} of the pairs being solved by a direct method now: the tasks whose
    call stack on their worker is inside `ocp.bench.measurement.measure` and `ocp.direct`."""
    inside = (f"{os.sep}ocp{os.sep}bench{os.sep}measurement.py", f"{os.sep}ocp{os.sep}direct{os.sep}")
    return {key: worker for worker, tasks in client.call_stack().items() for key, frames in tasks.items()
            if all(any(part in frame for frame in frames) for part in inside)}


def test_workers_killed_mid_pair_lose_nothing_and_duplicate_nothing(cluster, tmp_path):
    file, client, logs = cluster
    suite, store = tmp_path / "cluster.toml", tmp_path / "cluster.sqlite"
    suite.write_text(SUITE)
    bench = subprocess.Popen([sys.executable, "-c", BENCH, "bench", suite, "--store", store, "--scheduler", file,
                              "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env=dict(os.environ, PYTHONPATH=str(ROOT)))
    # the first pair seen running: its worker killed once; the second: each time it runs (twice)
    kills, seen_again, dead = {}, set(), set()
    try:
        while bench.poll() is None:
            try:
                running = {k: w for k, w in _running(client).items() if w not in dead}
            except OSError:                 # a worker that died while asked
                continue
            for key, worker in running.items():
                first, second = (list(kills) + [None, None])[:2]
                if key not in kills and second is None or key == second and kills[key] == 1:
                    pid = client.run(os.getpid, workers=[worker], on_error="ignore").get(worker)
                    if pid:
                        os.kill(pid, signal.SIGKILL)
                        kills[key] = kills.get(key, 0) + 1
                        dead.add(worker)
                elif key == first:
                    seen_again.add(key)
            time.sleep(0.05)
        out, err = bench.communicate(timeout=60)
    finally:
        if bench.poll() is None:
            bench.kill()
            bench.wait()
    assert bench.returncode == 0, err[-3000:]
    summary = json.loads(out)
    first, second = list(kills)
    assert kills == {first: 1, second: 2} and seen_again == {first}       # the first ran again elsewhere
    with sqlite3.connect(store) as db:
        rows = db.execute("select case_key, method_key, session, record from results").fetchall()
        claims = db.execute("select count(*) from claims").fetchone()[0]
    records = [json.loads(r[3]) for r in rows]
    assert len(rows) == len({r[:2] for r in rows}) == 4 == summary["run_now"] and claims == 0
    assert {r[2] for r in rows} == {summary["session"]}                   # written by the bench's process alone
    lost = [r for r in records if r["outcome"] == "solver error"]
    assert len(lost) == 1 and "each of the 2 Dask workers that ran it died" in lost[0]["message"]
    assert "allowed-failures = 1" in lost[0]["message"] and lost[0]["N"] == 40
    assert all(r["outcome"] == "ok" and r["total_time_s"] > 0 for r in records if r not in lost), \
        [(r["label"], r["outcome"]) for r in records]
    assert all(r["timing"]["executor"] == f"dask {json.loads(file.read_text())['address']}" for r in records)


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
