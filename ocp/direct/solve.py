"""The direct solve: a transcription (`ocp.direct.TRANSCRIPTIONS`) solved by an NLP solver from one
or several initial guesses, every start verified by re-simulating its control independently
(`ocp.core.simulate`: scipy's DOP853, nothing shared with the transcription but the model).

A direct answer's accuracy: the transcription states it (`Transcription.T_bound`): for multiple
shooting with rk4 at N <= BOUND_N_MAX = 400, `ocp.direct.base.grid_bound` (from the switch
states: 2 h^2 sum_i kappa / (4 |omega_i|), to leading order, plus the re-simulated miss's share);
elsewhere none. The former h^2/2 failed where a switch comes at low speed (kappa/(4 |omega_i|) >
1/2): on 14 of 208 random instances, by up to 3.6 times; the stated bound covered all 208, the
largest error half of it (benchmarks/direct_error.py --coverage, benchmarks/README.md, also at
N = 50 and 400; at N = 800 IPOPT's tolerance leaves more). The bound was measured with IPOPT at its default tolerance; it is stated for any solver and options (tests/test_direct.py
checks fatrop and sqpmethod at N = 40), and a solver option that loosens the tolerance voids it.

A long solve reports its progress (`progress`, `ocp.direct.watch`) and SIGINT ends it within
`watch.GRACE_S` seconds.
"""

import enum
import math
import time
from dataclasses import dataclass, replace

import numpy as np

from ..core import simulate
from ..core.errors import InputError, last_line
from ..core.problem import Problem
from . import structure, watch
from .guess import Guess, default_guesses
from .nlp import build
from .options import checked
from .shooting import MultipleShooting

MISS_TOL = 1e-6
#: accepted values of miss_tol (the command line's --miss-tol, a suite's miss_tol)
MISS_TOL_RANGE = (1e-15, 1.0)


class DirectStatus(enum.IntEnum):
    """How a direct solve ended (MESSAGES says it in words); success is VERIFIED alone."""

    VERIFIED = 0
    MISSES_TARGET = 1
    NOT_CONVERGED = 2
    SOLVER_ERROR = 3


MESSAGES = {
    DirectStatus.VERIFIED: "converged; the control re-simulated independently lands on the target",
    DirectStatus.MISSES_TARGET: "converged, but the control re-simulated independently misses the target",
    DirectStatus.NOT_CONVERGED: "the NLP solver did not converge",
    DirectStatus.SOLVER_ERROR: "the NLP solver raised an error or returned no usable point",
}


@dataclass(frozen=True)
class Start:
    """One initial guess solved: its label, status, the solver's own message, T, switch count,
    iterations and solve time."""

    guess: str
    status: DirectStatus
    solver_message: str
    T: float
    n_switches: int
    iterations: int
    solve_time_s: float


@dataclass(frozen=True)
class DirectSolution:
    """The best start of a direct solve (verified first, then converged, then the least T).

    T, the grid t (N+1), node states x (N+1, 2), the piecewise-constant control u (N), its
    `structure` (`ocp.direct.structure.Structure`), the target `branch` reached (the nearest to
    theta_N, or the pinned one); `status` (DirectStatus) and the solver's own `solver_message`;
    `resim_miss`: the distance in (theta, omega) from the target of the control re-simulated
    independently (success needs it <= miss_tol); `T_bound`: the stated bound of the error of T
    (None where none has been measured); timings; every start tried (`starts`)."""

    problem: Problem
    method: dict
    status: DirectStatus
    solver_message: str
    T: float
    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    branch: int
    iterations: int
    structure: structure.Structure
    resim_miss: float
    miss_tol: float
    T_bound: float | None
    build_time_s: float
    solve_time_s: float
    total_time_s: float
    guess: str
    starts: tuple

    @property
    def success(self):
        return self.status == DirectStatus.VERIFIED

    @property
    def converged(self):
        return self.status in (DirectStatus.VERIFIED, DirectStatus.MISSES_TARGET)

    @property
    def message(self):
        return MESSAGES[self.status]

    def to_dict(self):
        return {
            "success": self.success, "status": self.status.name.lower(), "message": self.message,
            "solver_message": self.solver_message, "method": self.method, "T": self.T, "T_bound": self.T_bound,
            "branch": self.branch, "iterations": self.iterations, "structure": self.structure.to_dict(),
            "resim_miss": self.resim_miss, "miss_tol": self.miss_tol, "guess": self.guess,
            "build_time_s": self.build_time_s, "solve_time_s": self.solve_time_s, "total_time_s": self.total_time_s,
            "starts": [dict(s.__dict__, status=s.status.name.lower()) for s in self.starts],
        }


def solve(problem, method=None, solver="ipopt", options=None, guess=None, miss_tol=MISS_TOL, trusted=False,
          progress=None):
    """The direct solution of `problem` by `method` (a transcription; default MultipleShooting()),
    NLP solved by casadi.nlpsol(`solver`, `options`) (options untouched, those that run a program
    or touch a file refused unless `trusted`: `ocp.direct.options`).

    `guess`: None (the default family, `default_guesses`), a Guess, or a DirectSolution.
    `progress`: None or a callable given a line of text (what runs, e.g. "direct: ipopt, start 2 of
    3 (backswing), iteration 40, 12 s") every second once the solve has run 2 s; SIGINT raises
    KeyboardInterrupt within a second or two (`ocp.direct.watch`)."""
    if not isinstance(problem, Problem):
        raise InputError(f"problem must be an ocp Problem (ocp.swing_up / ocp.damping), not {type(problem).__name__}")
    method = MultipleShooting() if method is None else method
    if not (isinstance(miss_tol, (int, float)) and 0 < miss_tol < 1):
        raise InputError(f"miss_tol = {miss_tol!r} must be a number in (0, 1)")
    if guess is None:
        guesses = default_guesses(problem, method.N)
    elif isinstance(guess, DirectSolution):
        guesses = [Guess.from_solution(guess)]
    elif isinstance(guess, Guess):
        guesses = [guess]
    else:
        raise InputError(f"guess must be None, an ocp Guess or a direct solution, not {type(guess).__name__}")
    start = time.perf_counter()
    options = checked(options, trusted, solver=solver)
    with watch.watched(progress) as watching:
        watching.stage(f"building the NLP of {method.describe()}")
        nlp = build(method, solver, options, problem.reading)
        runs = []
        for i, g in enumerate(guesses):
            watching.stage(f"{solver}, start {i + 1} of {len(guesses)} ({g.label})")
            runs.append(_run(nlp, problem, g, miss_tol))
    return best_of(runs, nlp.build_time_s, time.perf_counter() - start)


def best_of(runs, build_time_s, total_time_s):
    """The best of the runs of several starts (verified first, then converged, then the least T),
    with every start recorded and their solve times summed."""
    best = min(runs, key=lambda r: (r.status, r.T if math.isfinite(r.T) else math.inf))
    starts = tuple(Start(r.guess, r.status, r.solver_message, r.T, r.structure.n_switches, r.iterations,
                         r.solve_time_s) for r in runs)
    return replace(best, starts=starts, solve_time_s=sum(r.solve_time_s for r in runs),
                   build_time_s=build_time_s, total_time_s=total_time_s)


def verified(problem, method, settings, t, x, u, converged, solver_message, iterations, miss_tol, solve_time_s,
             guess, branch=None):
    """The DirectSolution of one start (grid t, node states x, control u): the branch reached (the
    nearest to theta_N unless given) and the control re-simulated independently; its T bound the
    transcription's (`settings`; None: another program's, no bound)."""
    branch = problem.nearest_branch(x[-1, 0]) if branch is None else branch
    final = simulate.piecewise(problem.x0, t, u, problem.kappa)[-1]
    miss = float(np.hypot(*(final - np.array(problem.target(branch)))))
    if converged is None:
        status = DirectStatus.SOLVER_ERROR
    elif not converged:
        status = DirectStatus.NOT_CONVERGED
    else:
        status = DirectStatus.VERIFIED if miss <= miss_tol else DirectStatus.MISSES_TARGET
    read = structure.read(t, x, u, problem.kappa)
    return DirectSolution(problem, method, status, solver_message, float(t[-1]), t, x, u, branch, iterations, read,
                          miss, miss_tol, None if settings is None or status != DirectStatus.VERIFIED
                          else settings.T_bound(read, problem.kappa, miss),
                          0.0, solve_time_s, solve_time_s, guess, ())


def _run(nlp, problem, guess, miss_tol):
    N = nlp.N
    theta, omega, u = guess.on_grid(N)
    lbx, ubx = nlp.bounds(problem.x0, problem.nlp_target, (0.5 * problem.lower_bound, math.inf))
    w0 = np.clip(nlp.pack(theta, omega, guess.T, u), lbx, ubx)
    start = time.perf_counter()
    converged = None
    try:
        w = np.array(nlp.solver(x0=w0, lbx=lbx, ubx=ubx, lbg=nlp.lbg, ubg=nlp.ubg,
                                p=[problem.kappa, problem.nlp_target])["x"]).ravel()
        stats = nlp.solver.stats()
        message = _message(stats)
        converged = bool(stats.get("success", False))
    except RuntimeError as err:      # a solver that cannot run (e.g. a missing linear solver) fails this start
        w, stats, message = w0, {}, f"solver error: {last_line(err)}"
    watch.check()                    # stopped by SIGINT: the start is not an answer
    i_th, i_om, i_T, i_u = nlp.index()
    if not (np.all(np.isfinite(w)) and w[i_T[0]] > 0):   # e.g. bonmin's NaN or all-zero exit
        w, stats, converged = w0, {}, None
        message += ": the solver returned no usable point (T <= 0 or not finite)"
    t = np.linspace(0.0, float(w[i_T[0]]), N + 1)
    x = np.column_stack([w[i_th], w[i_om]])
    method = dict(nlp.settings.to_dict(), solver=nlp.solver_name, options=nlp.options)
    iterations = stats.get("iter_count", -1)
    iterations = int(iterations) if math.isfinite(iterations) else -1          # bonmin reports NaN
    return verified(problem, method, nlp.settings, t, x, np.clip(w[i_u], -1.0, 1.0), converged, message,
                    iterations, miss_tol, time.perf_counter() - start, guess.label, problem.branch)


def _message(stats):
    """The solver's own return status, or CasADi's unified one where the solver gives a number."""
    status = stats.get("return_status")
    return status if isinstance(status, str) else str(stats.get("unified_return_status", status))
