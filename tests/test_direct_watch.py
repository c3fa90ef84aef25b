"""A direct solve bounded, interruptible and not silent: the NLP's size limit (measured by
benchmarks/direct_size.py), the layout of a transcription's extra variables, SIGINT
(`ocp.direct.watch`) and progress."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import ocp
from ocp.core.errors import InputError
from ocp.direct import watch
from ocp.direct.nlp import build


def test_an_nlp_larger_than_its_measured_limit_is_refused_with_what_is_accepted():
    with pytest.raises(InputError, match=r"N\*M = 320000 is too large .* accepted: N\*M <= 20000 \(that NLP takes"):
        ocp.MultipleShooting(N=5000, M=64)          # the 16.8 GB after 280 s, still growing


@pytest.mark.parametrize("largest, larger", [
    (dict(N=5000, M=4), dict(N=5000, M=5)),
    (dict(N=500, integrator="collocation", M=4), dict(N=501, integrator="collocation", M=4)),
    (dict(N=500, integrator="cvodes"), dict(N=501, integrator="cvodes")),
])
def test_each_integrator_accepts_up_to_its_limit(largest, larger):
    ocp.MultipleShooting(**largest)
    with pytest.raises(InputError, match="is too large"):
        ocp.MultipleShooting(**larger)


def test_direct_collocation_accepts_up_to_its_limit():
    assert ocp.DirectCollocation(N=5000, degree=3).size() == 45000        # the largest measured
    ocp.DirectCollocation(N=555, degree=9)
    with pytest.raises(InputError, match=r"N\*degree\^2 = 45036 is too large"):
        ocp.DirectCollocation(N=556, degree=9)


def test_extra_variables_are_laid_out_by_the_transcription():
    """Direct collocation's Radau states start at their interval's first node (`extra_guess`)."""
    nlp = build(ocp.DirectCollocation(N=3, degree=2))
    theta, omega = np.array([0.0, 1.0, 2.0, 3.0]), np.array([5.0, 6.0, 7.0, 8.0])
    w = nlp.pack(theta, omega, 4.0, np.zeros(3))
    assert w[nlp.extra_index()].tolist() == [[0.0, 5.0, 0.0, 5.0], [1.0, 6.0, 1.0, 6.0], [2.0, 7.0, 2.0, 7.0]]
    i_th, i_om, i_T, i_u = nlp.index()
    assert w[i_th].tolist() == theta.tolist() and w[i_om].tolist() == omega.tolist() and set(w[i_T]) == {4.0}
    assert nlp.n_w == 3 * (4 + 4) + 3 and build(ocp.MultipleShooting(N=3)).extra_index().shape == (3, 0)


def test_progress_says_which_start_and_iteration(monkeypatch):
    monkeypatch.setattr(watch, "QUIET_S", 0.0)
    monkeypatch.setattr(watch, "EVERY_S", 0.05)
    lines = []
    problem = ocp.swing_up(0.5)
    sol = ocp.direct.solve(problem, ocp.MultipleShooting(N=150), guess=ocp.direct.default_guesses(problem, 150)[1],
                           progress=lines.append)
    assert sol.success and lines and all(line.startswith("direct: ") and line.endswith(" s") for line in lines)
    assert any("ipopt, start 1 of 1 (backswing), iteration" in line for line in lines)


WATCHED_BLOCKS = """
import signal, threading, time
from ocp.direct import watch
watch.POLL_S = 3600.0
assert signal.getsignal(signal.SIGINT) is signal.default_int_handler   # the wake-up pipe is used
elapsed = []

def block():
    start = time.perf_counter()
    with watch.watched():
        time.sleep(0.05)        # the watcher is in its wait by then
    elapsed.append(time.perf_counter() - start)

block()
thread = threading.Thread(target=block)
thread.start()
thread.join()
print(max(elapsed))
"""


def test_the_end_of_a_watched_solve_wakes_the_watcher_at_once():
    """Leaving `watched` does not wait for the watcher's next look at the clock (it waited up to
    POLL_S, which rounded every direct solve's wall time up to a multiple of 0.1 s): in a process of
    its own (Python's SIGINT handler, the wake-up descriptor free), with POLL_S an hour, a block of
    0.05 s ends at once, in the main thread (the watcher selects on the SIGINT wake-up pipe) and in another (no
    pipe: it waits on the event the block's end sets)."""
    run = subprocess.run([sys.executable, "-c", WATCHED_BLOCKS], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert float(run.stdout) < 60.0


def test_sigint_stops_ipopt_at_its_next_iteration(monkeypatch):
    """In process: SIGINT while IPOPT iterates raises KeyboardInterrupt through its iteration
    callback, well within the grace after which the watcher would end the process (set long here)."""
    monkeypatch.setattr(watch, "QUIET_S", 0.0)
    monkeypatch.setattr(watch, "EVERY_S", 0.02)
    monkeypatch.setattr(watch, "GRACE_S", 60.0)
    sent = []

    def progress(line):
        if "iteration" in line and not sent:
            sent.append(time.perf_counter())
            os.kill(os.getpid(), signal.SIGINT)

    if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        pytest.skip("SIGINT is handled by the test runner here")
    with pytest.raises(KeyboardInterrupt):
        ocp.direct.solve(ocp.swing_up(0.5), ocp.MultipleShooting(N=200), progress=progress)
    assert sent and time.perf_counter() - sent[0] < 2.0
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler       # restored


def test_sigint_during_a_long_build_ends_the_command_with_130():
    """The NLP's construction runs in C++ (no Python handler can run): the watcher ends the process
    GRACE_S after the signal, with "interrupted" and exit 130."""
    proc = subprocess.Popen([sys.executable, "-m", "ocp.cli", "solve", "swing-up", "--kappa", "1", "--no-refine",
                             "--N", "2000"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(4.0)                     # the import and the start of the build (about 10 s alone)
    sent = time.perf_counter()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and err.strip().splitlines()[-1] == "interrupted"
    assert time.perf_counter() - sent < watch.GRACE_S + 2.0
