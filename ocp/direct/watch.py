"""A direct solve watched: interrupted by SIGINT within GRACE_S seconds, and its progress reported.

CasADi runs the NLP's construction and the solver in C++ with Python's lock released, where
Python's own SIGINT handler cannot run. So, meanwhile (`watched`):

- SIGINT sets a flag (Python's wake-up descriptor tells a watcher thread at once); the solvers that
  call CasADi's `iteration_callback` (IPOPT, sqpmethod) stop at their next iteration, and the solve
  raises KeyboardInterrupt when the solver returns;
- a solve still inside C++ GRACE_S after the signal (building a large NLP, or fatrop, which calls no
  callback) ends the process: "interrupted" on stderr, exit status 130, what a C program's default
  SIGINT does;
- after QUIET_S seconds, `progress(line)` is called every EVERY_S seconds with what runs: the
  stage (building, start i of n), the solver's iteration where it reports one, the time.

Interrupts are watched only in the main thread with Python's default SIGINT handler installed
(a caller that handles SIGINT itself keeps its own way) and the wake-up descriptor free.
"""

import contextlib
import os
import select
import signal
import threading
import time

from ..core.output import QUIET_S

GRACE_S = 1.5
EVERY_S = 1.0
#: how often the watcher looks at the clock (the grace after SIGINT, progress); the end of the solve
#: wakes it at once
POLL_S = 0.1


class Watch:
    """What the watched solve is doing (`doing`, `iteration`), since when, and whether SIGINT came."""

    def __init__(self, progress):
        self.progress = progress
        self.started = time.perf_counter()
        self.doing = "building the NLP"
        self.iteration = None
        self.interrupted = None          # the time SIGINT came

    def line(self):
        iteration = "" if self.iteration is None else f", iteration {self.iteration}"
        return f"direct: {self.doing}{iteration}, {time.perf_counter() - self.started:.0f} s"

    def stage(self, doing):
        """A new stage of the solve (KeyboardInterrupt if SIGINT came)."""
        self.check()
        self.doing, self.iteration = doing, None

    def check(self):
        if self.interrupted is not None:
            raise KeyboardInterrupt("interrupted")


#: the watch of the solve running in this process (one at a time), read by the iteration callback
_current = None


def iteration():
    """Called by the solver at each iteration (`callback`): 1 (stop) after SIGINT, else 0."""
    watch = _current
    if watch is None:
        return 0
    watch.iteration = 0 if watch.iteration is None else watch.iteration + 1
    return int(watch.interrupted is not None)


def check():
    """KeyboardInterrupt if SIGINT came during the watched solve (e.g. as the solver returns)."""
    if _current is not None:
        _current.check()


def callback(n_x, n_g, n_p):
    """CasADi's `iteration_callback` for an NLP of n_x variables, n_g constraints, n_p parameters:
    a casadi.Callback that calls `iteration` (its inputs, the iterate, unread). Keep a reference to
    it as long as the solver lives (CasADi does not)."""
    import casadi as ca

    sizes = {"f": 1, "x": n_x, "lam_x": n_x, "g": n_g, "lam_g": n_g, "lam_p": n_p}

    class Iteration(ca.Callback):
        def __init__(self):
            ca.Callback.__init__(self)
            self.construct("iteration", {})

        def get_n_in(self):
            return ca.nlpsol_n_out()

        def get_n_out(self):
            return 1

        def get_name_in(self, i):
            return ca.nlpsol_out(i)

        def get_name_out(self, i):
            return "stop"

        def get_sparsity_in(self, i):
            n = sizes.get(ca.nlpsol_out(i), 0)
            return ca.Sparsity.dense(n) if n else ca.Sparsity(0, 0)

        def eval(self, arg):
            return [iteration()]

    return Iteration()


@contextlib.contextmanager
def watched(progress=None):
    """Meanwhile, the solve is watched (the module doc); yields its Watch."""
    global _current
    watch = Watch(progress)
    done = threading.Event()
    restore = _take_sigint(watch)
    wake = restore[2][0] if restore and restore[2] else None
    thread = threading.Thread(target=_watcher, args=(watch, done, wake), daemon=True)
    previous, _current = _current, watch
    thread.start()
    try:
        yield watch
        watch.check()
    finally:
        done.set()
        if wake is not None:
            os.write(restore[2][1], b"\0")  # wakes the watcher's select at once (not SIGINT's byte)
        thread.join()
        _current = previous
        if restore:
            handler, old_fd, pipe = restore
            signal.signal(signal.SIGINT, handler)
            if pipe:
                signal.set_wakeup_fd(old_fd)
                os.close(pipe[0])
                os.close(pipe[1])


def _take_sigint(watch):
    """Install the SIGINT flag and, where the wake-up descriptor is free, a wake-up pipe: (old
    handler, old wake-up fd, (read, write) or None), or None where interrupts are not ours to watch.
    Where the descriptor is taken (the command line watches it too, `ocp.cli`), the flag is still
    set by the handler, which runs at the solver's next iteration callback."""
    if threading.current_thread() is not threading.main_thread() or \
            signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        return None
    read, write = os.pipe()
    os.set_blocking(write, False)
    old_fd, pipe = signal.set_wakeup_fd(write), (read, write)
    if old_fd != -1:                    # someone else's descriptor: it stays theirs
        signal.set_wakeup_fd(old_fd)
        os.close(read)
        os.close(write)
        pipe = None

    def handler(signum, frame):
        if watch.interrupted is None:
            watch.interrupted = time.perf_counter()
        raise KeyboardInterrupt("interrupted")

    return signal.signal(signal.SIGINT, handler), old_fd, pipe


def _watcher(watch, done, wake):
    """The watcher thread: SIGINT noted from the wake-up pipe, the process ended GRACE_S after it if
    the solve is still running, progress every EVERY_S after QUIET_S."""
    stderr = os.dup(2)                  # the real stderr: the NLP's build silences descriptor 2
    last = watch.started
    try:
        while not done.wait(0.0):
            if wake is None:
                done.wait(POLL_S)
            elif select.select([wake], [], [], POLL_S)[0] and signal.SIGINT in os.read(wake, 64):
                if watch.interrupted is None:
                    watch.interrupted = time.perf_counter()
            now = time.perf_counter()
            if watch.interrupted is not None and now - watch.interrupted > GRACE_S and not done.is_set():
                os.write(stderr, b"interrupted\n")
                os._exit(130)
            if watch.progress is not None and now - watch.started > QUIET_S and now - last >= EVERY_S:
                last = now
                watch.progress(watch.line())
    finally:
        os.close(stderr)


_stderr = None


def stderr_progress():
    """A progress callable writing each line to the process's stderr (descriptor 2 as it was at the
    first call, duplicated once, so that lines pass while the NLP's build silences descriptor 2)."""
    global _stderr
    if _stderr is None:
        _stderr = os.dup(2)
    fd = _stderr
    return lambda line: os.write(fd, (line + "\n").encode())
