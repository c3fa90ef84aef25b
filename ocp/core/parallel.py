"""Parallel plumbing shared by the bench, the failure maps and the bifurcation values: one executor
interface (concurrent.futures) over this process, local worker processes or a Dask cluster, the
loop that feeds it, and a progress line.

    executor(jobs, scheduler)        (executor, workers, description): serial, local processes
                                     (workers end with their parent: `die_with_parent`), or Dask
                                     (`scheduler_address`: tcp:// or tls://, or a scheduler file)
    drain(pool, workers, tasks, ...) tasks submitted at most 2 per worker, each handled as it
                                     finishes (not in submission order); a task whose workers all
                                     died running it (`lost_worker`: Dask's, or a local one's, told
                                     apart by running the tasks then in flight again one at a time)
                                     handed to `lost`
    Progress(total, what)            a line on stderr from the first second: done/total, elapsed,
                                     an estimate of what is left, and what is running now
    timing_note(workers, others)     how a row was timed (alone, in parallel, beside other sessions)
"""

import concurrent.futures as cf
from concurrent.futures.process import BrokenProcessPool
import contextlib
import ctypes
import gc
import json
import os
import re
import signal
import socket
import ssl
import sys
import threading
import time
from pathlib import Path

from .errors import InputError, last_line

#: the Dask scheduler addresses accepted (an allow-list): tcp:// (plain) or tls:// (encrypted and
#: authenticated by the certificates of Dask's configuration), host (a name, IPv4 or [IPv6]) and port
SCHEDULER = re.compile(r"(tcp|tls)://([A-Za-z0-9.\-]+|\[[0-9A-Fa-f:]+\]):([0-9]{1,5})")
ACCEPTED = ("tcp://host:8786 or tls://host:8786, or the JSON file that `dask scheduler --scheduler-file FILE` "
            "writes")
#: the largest scheduler file read
SCHEDULER_FILE_BYTES = 100_000
#: seconds to reach a scheduler and hear its handshake
CONNECT_S = 10.0
PR_SET_PDEATHSIG = 1


class SerialExecutor(cf.Executor):
    """The concurrent.futures interface, run in this process at submit (`--jobs 1`)."""

    def submit(self, fn, /, *args, **kwargs):
        future = cf.Future()
        future.set_running_or_notify_cancel()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception as err:     # noqa: BLE001  (delivered through the future, as other executors do)
            future.set_exception(err)
        return future


def scheduler_address(value):
    """The scheduler address of --scheduler `value`: an address of the allow-list SCHEDULER (a port
    from 1 to 65535), or a file naming one (`dask scheduler --scheduler-file`: a JSON object whose
    "address" is such an address); InputError otherwise."""
    def refused(why):
        return InputError(f"--scheduler {value[:60]!r} {why}; accepted: {ACCEPTED}")

    def checked(address, why):
        match = isinstance(address, str) and SCHEDULER.fullmatch(address)
        if not match or not 1 <= int(match[3]) <= 65535:
            raise refused(why)
        return address

    if "://" in value or not value.strip():
        return checked(value, "is not an accepted scheduler address")
    path = Path(value)
    if not path.is_file():
        raise refused("is neither a scheduler address nor a scheduler file")
    try:
        with path.open("rb") as f:
            raw = f.read(SCHEDULER_FILE_BYTES + 1)
        if len(raw) > SCHEDULER_FILE_BYTES:
            raise ValueError("too long")
        data = json.loads(raw.decode())
    except (OSError, ValueError, RecursionError):
        raise refused("is not a scheduler file (JSON, at most 100 kB)") from None
    return checked(data.get("address") if isinstance(data, dict) else None,
                   "is a file without an accepted scheduler \"address\"")


def probe_scheduler(address, timeout=None):
    """InputError unless `address` accepts a connection and answers within `timeout` seconds (a
    server that accepts and says nothing would hold Dask's client past its own timeout; CONNECT_S by
    default): on tcp:// a Dask scheduler speaks first (its comm handshake is sent on accept); on
    tls:// the server answers the TLS handshake (checked here without certificates: it is Dask's
    client that authenticates, with those of Dask's configuration)."""
    timeout = CONNECT_S if timeout is None else timeout
    scheme, host, port = SCHEDULER.fullmatch(address).groups()
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=timeout) as s:
            s.settimeout(max(0.1, timeout))
            if scheme == "tls":
                _answers_tls(s, host.strip("[]"))
            elif not s.recv(1):
                raise InputError(f"the server at {address} closed the connection: it is not a Dask scheduler")
    except TimeoutError:
        raise InputError(f"the server at {address} accepted but sent no handshake within {timeout:g} s: "
                         f"it is not a Dask scheduler") from None
    except OSError as err:
        raise InputError(f"cannot reach the Dask scheduler at {address}: {last_line(err)}") from None


def _answers_tls(sock, host):
    """Return once the server on `sock` has answered a TLS handshake (completed or refused: it speaks
    TLS); TimeoutError when it says nothing."""
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    context.check_hostname, context.verify_mode = False, ssl.CERT_NONE
    with contextlib.suppress(ssl.SSLError, ConnectionResetError):
        with context.wrap_socket(sock, server_hostname=host, do_handshake_on_connect=False) as tls:
            tls.do_handshake()


@contextlib.contextmanager
def executor(jobs=1, scheduler=None):
    """(executor, workers, description): local processes (`jobs`), or a Dask distributed cluster at
    `scheduler` (an address or scheduler file, `scheduler_address`; the `dask` extra), all behind
    concurrent.futures.Executor."""
    if scheduler:
        try:
            import distributed
        except ImportError:
            raise InputError("--scheduler needs Dask distributed: pip install 'ocp[dask]'") from None
        scheduler = scheduler_address(scheduler)
        probe_scheduler(scheduler)
        try:
            client = distributed.Client(scheduler, timeout=CONNECT_S)
        except (OSError, TimeoutError, ValueError, TypeError) as err:
            # the half-built Client is collected now: its __del__, run later inside another
            # Client's start, deadlocks on the event loop's lock
            gc.collect()
            raise InputError(f"cannot reach the Dask scheduler at {scheduler}: {last_line(err)}") from None
        with client:
            yield client.get_executor(), max(1, sum(client.nthreads().values())), f"dask {scheduler}"
    elif jobs == 1:
        yield SerialExecutor(), 1, "serial (this process)"
    else:
        with LocalPool(jobs) as pool:
            yield pool, jobs, f"{jobs} local worker processes"


class LocalPool(cf.Executor):
    """`jobs` local worker processes that end with their parent (`die_with_parent`). When one dies
    (a crash, out of memory, a signal), every future of the pool fails with BrokenProcessPool;
    `renew` replaces the pool (and `drain` runs each task then in flight again, one at a time, so
    that a task whose worker dies is told apart from those that only shared the pool with it)."""

    def __init__(self, jobs):
        self.jobs = jobs
        self._pool = self._new()

    def _new(self):
        return cf.ProcessPoolExecutor(self.jobs, initializer=die_with_parent, initargs=(os.getpid(),))

    def submit(self, fn, /, *args, **kwargs):
        return self._pool.submit(fn, *args, **kwargs)

    def renew(self):
        self._pool.shutdown(wait=False, cancel_futures=True)
        self._pool = self._new()

    def shutdown(self, wait=True, *, cancel_futures=False):
        self._pool.shutdown(wait=wait, cancel_futures=cancel_futures)


def process_alive(pid):
    """Whether the process `pid` of this host runs (a zombie has ended; POSIX)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return True


def die_with_parent(parent):
    """Worker initializer: this process ends when the process `parent` does (a killed `ocp bench`
    leaves no orphans): Linux's parent-death signal where `parent` is the direct parent, and a
    thread that checks once a second."""
    if sys.platform.startswith("linux") and os.getppid() == parent:
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    threading.Thread(target=_watch, args=(parent,), daemon=True).start()


def _watch(parent):
    while process_alive(parent):
        time.sleep(1.0)
    os._exit(1)


class Progress:
    """A progress line on stderr: redrawn in place on a terminal every second, from the first; in
    a log, a line at the start, at each tenth done and after LOG_S without one. Each says done/total,
    the elapsed time, an estimate of what is left (once one task is done) and what is running."""

    LOG_S = 30.0

    def __init__(self, total, what, stream=None):
        self.total, self.what, self.done = total, what, 0
        self.stream = stream or sys.stderr
        self.start = time.perf_counter()
        self.tty = self.stream.isatty()
        self.shown, self.written, self.last = -1, self.start, ""
        self.running = lambda: ()
        self.lock, self.stopped = threading.Lock(), threading.Event()

    def begin(self, running=lambda: ()):
        """Draw the first line now and redraw once a second until `end`; `running()` names what runs."""
        self.running = running
        self._draw(force=True)
        threading.Thread(target=self._tick, daemon=True).start()

    def _tick(self):
        while not self.stopped.wait(1.0):
            self._draw(force=not self.tty and time.perf_counter() - self.written >= self.LOG_S, tick=True)

    def end(self):
        self.stopped.set()

    def step(self, note=""):
        """One task done; `note` says which and how it ended."""
        self.done += 1
        self.last = note
        self._draw(force=10 * self.done // max(self.total, 1) > self.shown or self.done == self.total)

    def line(self):
        elapsed = time.perf_counter() - self.start
        left = f"~{elapsed / self.done * (self.total - self.done):.0f} s left" if self.done else "estimating"
        filled = 30 * self.done // max(self.total, 1)
        names = list(self.running())
        running = f"  running: {'; '.join(names[:3])}{f' (+{len(names) - 3})' if len(names) > 3 else ''}" if names else ""
        last = f"  last: {self.last}" if self.last else ""
        return (f"[{'#' * filled}{'.' * (30 - filled)}] {self.done}/{self.total} {self.what}  "
                f"{elapsed:.0f} s, {left}{running}{last}")

    def _draw(self, force=False, tick=False):
        with self.lock:
            if tick and (self.stopped.is_set() or self.done == self.total):
                return
            if self.tty:
                self.stream.write("\r" + self.line()[:160].ljust(160) + ("\n" if self.done == self.total else ""))
            elif force:
                self.shown = max(self.shown, 10 * self.done // max(self.total, 1))
                self.written = time.perf_counter()
                self.stream.write(self.line() + "\n")
            self.stream.flush()


def drain(pool, workers, tasks, handle, progress, label=None, lost=None):
    """Submit tasks (fn, args, context), at most 2 per worker in flight; handle(context, result) each
    as it completes, in the order they finish; `label(context)` names a running task on the
    progress line. A task whose workers all died running it is handled with `lost(context, what)`
    as its result, `what` saying how (`lost_worker`; raised without `lost`): Dask runs a task again
    elsewhere when its worker dies, and gives up after `distributed.scheduler.allowed-failures`
    deaths; a `LocalPool` whose worker died is renewed, and the tasks then in flight run again one
    at a time, so that a task whose worker dies while it runs alone is the one lost. An interruption
    cancels what has not started; handled rows stay handled."""
    tasks, pending, submitting, suspects = iter(tasks), {}, [], []
    progress.begin(lambda: _running(pending, submitting, label) if label else ())
    try:
        while True:
            if suspects:                            # after a local worker's death: one at a time
                if not pending:
                    fn, args, context = suspects.pop(0)
                    pending[pool.submit(fn, *args)] = (fn, args, context, True)
            else:
                for fn, args, context in tasks:
                    submitting.append(context)      # a serial executor runs it inside submit
                    pending[pool.submit(fn, *args)] = (fn, args, context, False)
                    submitting.clear()
                    if len(pending) >= 2 * workers:
                        break
            if not pending:
                return
            done, _ = cf.wait(pending, return_when=cf.FIRST_COMPLETED)
            broken = False
            for future in [f for f in pending if f in done]:      # those done at once: in submission order
                fn, args, context, alone = pending.pop(future)
                try:
                    result = future.result()
                except Exception as err:
                    what = lost_worker(err, alone)
                    if lost is None or what is None:
                        raise
                    broken = broken or isinstance(err, BrokenProcessPool)
                    if what == SUSPECT:
                        suspects.append((fn, args, context))
                        continue
                    result = lost(context, what)
                progress.step(handle(context, result))
            if broken:                              # the pool's other tasks fail with it: suspects too
                suspects += [(fn, args, context) for fn, args, context, _ in pending.values()]
                pending.clear()
                pool.renew()
    finally:
        progress.end()
        for future in pending:
            future.cancel()


#: `lost_worker`'s word for a task in flight beside others in a local pool when one of its workers died
SUSPECT = "suspect"


def lost_worker(err, alone=True):
    """How the workers running a task died, in words, if `err` says they did (else None): Dask's
    KilledWorker (every worker that ran it died), or a local pool broken by the death of a worker
    (BrokenProcessPool): the task's own death if it ran `alone`, else SUSPECT (it shared the pool)."""
    if isinstance(err, BrokenProcessPool):
        return "the local worker process running it died (a crash, out of memory or a signal)" if alone else SUSPECT
    distributed = sys.modules.get("distributed")
    if distributed is not None and isinstance(err, distributed.KilledWorker):
        return (f"each of the {err.allowed_failures + 1} Dask workers that ran it died (a crash or out of memory; "
                f"the scheduler's distributed.scheduler.allowed-failures = {err.allowed_failures})")
    return None


def _running(pending, submitting, label):
    """The labels of the tasks running now: those their executor marks running (a process pool;
    Dask marks none: then every one not done), and the one being submitted to a serial executor."""
    items = [(f, task[2]) for f, task in list(pending.items())]
    running = [c for f, c in items if f.running()] or [c for f, c in items if not f.done()]
    return [label(c) for c in running + list(submitting)]


def timing_note(workers, others):
    """How a row was timed: alone, in parallel with its own workers, and/or while other `ocp bench`
    sessions (ids `others`) wrote to the same store."""
    parts = ["timed in parallel: workers share the machine"] if workers > 1 else []
    if others:
        parts.append(f"timed while another ocp bench wrote to this store (session {', '.join(map(str, others))}): "
                     f"it may have shared the machine")
    return "; ".join(parts) or "timed alone"
