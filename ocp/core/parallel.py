"""Parallel plumbing shared by the bench, the failure maps and the bifurcation values: one executor
interface (concurrent.futures) over this process, local worker processes or a Dask cluster, the
loop that feeds it, and a progress line.

    executor(jobs, scheduler)        (executor, workers, description): serial, local processes
                                     (workers end with their parent: `die_with_parent`), or Dask
    drain(pool, workers, tasks, ...) tasks submitted at most 2 per worker, each handled as it
                                     finishes (not in submission order)
    Progress(total, what)            a line on stderr from the first second: done/total, elapsed,
                                     an estimate of what is left, and what is running now
    timing_note(workers, others)     how a row was timed (alone, in parallel, beside other sessions)
"""

import concurrent.futures as cf
import contextlib
import ctypes
import gc
import os
import re
import signal
import socket
import sys
import threading
import time
from pathlib import Path

from .errors import InputError, last_line

#: a Dask scheduler address: scheme://host:port
SCHEDULER = re.compile(r"(tcp|tls|ws|wss|ucx)://([A-Za-z0-9.\-]+|\[[0-9A-Fa-f:]+\]):([0-9]{1,5})")
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


def probe_scheduler(address, timeout=None):
    """InputError unless a tcp:// `address` accepts a connection and speaks first within `timeout`
    seconds, as a Dask scheduler does (its comm handshake is sent on accept); a server that accepts
    and says nothing would hold Dask's client past its own timeout (CONNECT_S by default). Other schemes (tls, ws, ucx)
    open with the client's message: they are left to Dask's timeout."""
    timeout = CONNECT_S if timeout is None else timeout
    scheme, host, port = SCHEDULER.fullmatch(address).groups()
    if scheme != "tcp":
        return
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=timeout) as s:
            s.settimeout(max(0.1, timeout))
            if not s.recv(1):
                raise InputError(f"the server at {address} closed the connection: it is not a Dask scheduler")
    except TimeoutError:
        raise InputError(f"the server at {address} accepted but sent no Dask handshake within {timeout:g} s: "
                         f"it is not a Dask scheduler") from None
    except OSError as err:
        raise InputError(f"cannot reach the Dask scheduler at {address}: {last_line(err)}") from None


@contextlib.contextmanager
def executor(jobs=1, scheduler=None):
    """(executor, workers, description): local processes (`jobs`), or a Dask distributed cluster at
    `scheduler` (the `dask` extra), all behind concurrent.futures.Executor."""
    if scheduler:
        try:
            import distributed
        except ImportError:
            raise InputError("--scheduler needs Dask distributed: pip install 'ocp[dask]'") from None
        if not SCHEDULER.fullmatch(scheduler):
            raise InputError(f"--scheduler {scheduler[:60]!r} is not a scheduler address; accepted: an address such as "
                             f"tcp://host:8786 (tcp, tls, ws, wss, ucx)")
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
        with cf.ProcessPoolExecutor(jobs, initializer=die_with_parent, initargs=(os.getpid(),)) as pool:
            yield pool, jobs, f"{jobs} local worker processes"


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


def drain(pool, workers, tasks, handle, progress, label=None):
    """Submit tasks (fn, args, context), at most 2 per worker in flight; handle(context, result) each
    as it completes, in the order they finish; `label(context)` names a running task on the
    progress line. An interruption cancels what has not started; handled rows stay handled."""
    tasks, pending, submitting = iter(tasks), {}, []
    progress.begin(lambda: _running(pending, submitting, label) if label else ())
    try:
        while True:
            for fn, args, context in tasks:
                submitting.append(context)          # a serial executor runs it inside submit
                pending[pool.submit(fn, *args)] = context
                submitting.clear()
                if len(pending) >= 2 * workers:
                    break
            if not pending:
                return
            done, _ = cf.wait(pending, return_when=cf.FIRST_COMPLETED)
            for future in [f for f in pending if f in done]:      # those done at once: in submission order
                context = pending.pop(future)
                progress.step(handle(context, future.result()))
    finally:
        progress.end()
        for future in pending:
            future.cancel()


def _running(pending, submitting, label):
    """The labels of the tasks running now: those their executor marks running (a process pool;
    Dask marks none: then every one not done), and the one being submitted to a serial executor."""
    items = list(pending.items())
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
