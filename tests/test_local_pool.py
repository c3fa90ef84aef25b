"""A local worker process that dies (a crash, out of memory, SIGKILL) breaks its whole pool: every
future of a concurrent.futures.ProcessPoolExecutor then fails with BrokenProcessPool (Python's
documentation of ProcessPoolExecutor). `drain` renews the pool and runs the tasks that were in
flight again one at a time: the task whose worker dies alone is the one lost, the others' results
are kept, and the rest of the run goes on."""

import io
import os
import signal
import time
from concurrent.futures.process import BrokenProcessPool

import pytest

from ocp.core.parallel import LocalPool, Progress, drain


def task(kind, x):
    time.sleep(0.2)                     # the tasks share the pool when one dies
    if kind == "die":
        os.kill(os.getpid(), signal.SIGKILL)
    return x * x


def run(tasks, lost):
    handled = []
    with LocalPool(2) as pool:
        drain(pool, 2, [(task, t, t) for t in tasks], lambda c, r: handled.append((c, r)),
              Progress(len(tasks), "tasks", io.StringIO()), lost=lost)
    return handled


def test_a_task_that_kills_its_worker_is_lost_alone_and_every_other_task_is_kept():
    tasks = [("ok", 1), ("ok", 2), ("die", 3), ("ok", 4), ("ok", 5), ("ok", 6)]
    handled = run(tasks, lost=lambda context, what: ("lost", what))
    assert sorted(c for c, _ in handled) == sorted(tasks)          # each once
    results = dict(handled)
    assert results[("die", 3)][0] == "lost" and "local worker process running it died" in results[("die", 3)][1]
    assert all(results[t] == t[1] ** 2 for t in tasks if t[0] == "ok")


def test_without_a_handler_of_lost_tasks_the_broken_pool_is_raised():
    with pytest.raises(BrokenProcessPool):
        run([("ok", 1), ("die", 2)], lost=None)
