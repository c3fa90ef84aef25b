"""A long stage's heartbeat: while a block runs, a line on a stream every EVERY_S seconds once it
has run QUIET_S seconds (`ocp.core.output.QUIET_S`), so that no command is silent for longer; a
block that ends sooner prints nothing (a failure stays one line)."""

import contextlib
import threading
import time

from .output import QUIET_S

EVERY_S = 5.0


@contextlib.contextmanager
def heartbeat(stream, what):
    """Meanwhile, "`what()`: N s" on `stream` (None: nothing) every EVERY_S seconds from QUIET_S on."""
    if stream is None:
        yield
        return
    begun, done = time.perf_counter(), threading.Event()

    def beat():
        wait = QUIET_S
        while not done.wait(wait):
            print(f"{what()}: {time.perf_counter() - begun:.0f} s", file=stream, flush=True)
            wait = EVERY_S

    thread = threading.Thread(target=beat, daemon=True)
    thread.start()
    try:
        yield
    finally:
        done.set()
        thread.join()
