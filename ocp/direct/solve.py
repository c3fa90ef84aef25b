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

A converged start whose control, re-simulated, misses the target by more than miss_tol is judged
against the transcription's own accuracy at its N (`Transcription.integration_error`: its map at
h and at two half steps; for rk4 and Radau collocation at kappa = 0.5, N = 25 its Richardson value
is within 10 % of the re-simulated miss, tests/test_solver_time.py):
within miss_tol plus it, a discretisation result (DISCRETISATION, with its T bound); beyond it, the
solver's success on a control that misses (MISSES_TARGET, the reason with both numbers). Each start
runs under the solver's own limits (`ocp.direct.solvers.limits`), its end read from the solver's
status (`limited`), its wall and CPU time from the solver's own stats (CasADi's `record_time`).

A long solve reports its progress (`progress`, `ocp.direct.watch`) and SIGINT ends it within
`watch.GRACE_S` seconds.
"""

import enum
import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..core import simulate
from ..core.errors import InputError, last_line
from ..core.numbers import order
from ..core.problem import Problem
from . import solvers, structure, watch
from .guess import Guess, default_guesses
from .nlp import build
from .options import checked
from .shooting import MultipleShooting

MISS_TOL = 1e-6
#: accepted values of miss_tol (the command line's --miss-tol, a suite's miss_tol)
MISS_TOL_RANGE = (1e-15, 1.0)


class DirectStatus(enum.IntEnum):
    """How a direct solve ended (MESSAGES says it in words; str: its name); success is VERIFIED
    alone. The numbers are stored (a bench row's direct_status): a new status is appended; the
    order of preference of the starts is ORDER."""

    VERIFIED = 0
    MISSES_TARGET = 1
    NOT_CONVERGED = 2
    SOLVER_ERROR = 3
    DISCRETISATION = 4

    def __str__(self):
        return self.name.lower()

    def __format__(self, spec):
        return format(str(self), spec)


MESSAGES = {
    DirectStatus.VERIFIED: "converged; the control re-simulated independently lands on the target",
    DirectStatus.DISCRETISATION: "converged; the control re-simulated independently misses the target by no more "
                                 "than the transcription's own accuracy at this N (a discretisation result)",
    DirectStatus.MISSES_TARGET: "converged, but the control re-simulated independently misses the target by more "
                                "than the transcription's own accuracy at this N",
    DirectStatus.NOT_CONVERGED: "the NLP solver did not converge",
    DirectStatus.SOLVER_ERROR: "the NLP solver raised an error or returned no usable point",
}
#: the starts' order of preference (`best_of`): verified, then within the transcription's accuracy
ORDER = (DirectStatus.VERIFIED, DirectStatus.DISCRETISATION, DirectStatus.MISSES_TARGET, DirectStatus.NOT_CONVERGED,
         DirectStatus.SOLVER_ERROR)


@dataclass(frozen=True, kw_only=True)
class Start:
    """One initial guess solved: its label, status and why (`message`), the solver's own return
    status, whether it stopped at its iteration or time limit (`limited`), T, switch count,
    iterations, the re-simulated miss and the largest accepted as a discretisation result, and the
    solver's own wall and CPU time of the solve."""

    guess: str
    status: DirectStatus
    message: str
    solver_message: str
    limited: bool
    T: float
    n_switches: int
    iterations: int
    resim_miss: float
    miss_bound: float | None
    solve_time_s: float
    cpu_time_s: float


@dataclass(frozen=True)
class DirectSolution:
    """The best start of a direct solve (ORDER, then the least T).

    T, the grid t (N+1), node states x (N+1, 2), the piecewise-constant control u (N), its
    `structure` (`ocp.direct.structure.Structure`), the target `branch` reached (the nearest to
    theta_N, or the pinned one); `status` (DirectStatus), why (`message`) and the solver's own
    `solver_message`; `limited`: it stopped at its iteration or time limit (`limits`: the solver's
    options of them and their values); `resim_miss`: the distance in (theta, omega) from the target
    of the control re-simulated independently (nan where the solver did not converge: not
    re-simulated; success needs it <= miss_tol; a converged answer
    within `miss_bound`, miss_tol plus the transcription's own estimate of its integration error
    at this N, is a discretisation result); `T_bound`: the stated bound of the error of T (None
    where none has been measured); timings: the solver's own wall and CPU time (`cpu_time_s`),
    build and solves; every start tried (`starts`)."""

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
    message: str = ""
    limited: bool = False
    miss_bound: float | None = None
    cpu_time_s: float | None = None
    limits: dict = field(default_factory=dict)

    @property
    def success(self):
        return self.status == DirectStatus.VERIFIED

    @property
    def lands_on_target(self):
        """Verified, or a discretisation result: the control lands within miss_tol, or within the
        transcription's own accuracy at this N."""
        return self.status in (DirectStatus.VERIFIED, DirectStatus.DISCRETISATION)

    @property
    def converged(self):
        return self.status in (DirectStatus.VERIFIED, DirectStatus.DISCRETISATION, DirectStatus.MISSES_TARGET)

    def to_dict(self):
        return {
            "success": self.success, "status": str(self.status), "message": self.message,
            "solver_message": self.solver_message, "limited": self.limited, "limits": self.limits,
            "method": self.method, "T": self.T, "T_bound": self.T_bound,
            "branch": self.branch, "iterations": self.iterations, "structure": self.structure.to_dict(),
            "resim_miss": self.resim_miss, "miss_tol": self.miss_tol, "miss_bound": self.miss_bound,
            "guess": self.guess, "build_time_s": self.build_time_s, "solve_time_s": self.solve_time_s,
            "cpu_time_s": self.cpu_time_s, "total_time_s": self.total_time_s,
            "starts": [dict(s.__dict__, status=str(s.status)) for s in self.starts],
        }


def solve(problem, method=None, solver="ipopt", options=None, guess=None, miss_tol=MISS_TOL, trusted=False,
          progress=None, time_limit_s=math.inf):
    """The direct solution of `problem` by `method` (a transcription; default MultipleShooting()),
    NLP solved by casadi.nlpsol(`solver`, `options`) (options untouched, those that run a program
    or touch a file refused unless `trusted`: `ocp.direct.options`), each start under the solver's
    own limits (`ocp.direct.solvers.limits`: its iterations, and its CPU seconds `time_limit_s`
    where it has such an option), recorded.

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
    limits = solvers.limits(solver, options, time_limit_s)
    options = dict(options, **limits)
    with watch.watched(progress) as watching:
        watching.stage(f"building the NLP of {method.describe()}")
        nlp = build(method, solver, options, problem.reading)
        runs = []
        for i, g in enumerate(guesses):
            watching.stage(f"{solver}, start {i + 1} of {len(guesses)} ({g.label})")
            runs.append(_run(nlp, problem, g, miss_tol))
    return best_of(runs, nlp.build_time_s, time.perf_counter() - start, nlp.build_cpu_time_s, limits)


def best_of(runs, build_time_s, total_time_s, build_cpu_time_s, limits):
    """The best of the runs of several starts (ORDER, then the least T), with every start recorded,
    their solve times summed, and the solver's own CPU time of the build and every solve."""
    best = min(runs, key=lambda r: (ORDER.index(r.status), r.T if math.isfinite(r.T) else math.inf))
    starts = tuple(Start(guess=r.guess, status=r.status, message=r.message, solver_message=r.solver_message,
                         limited=r.limited, T=r.T, n_switches=r.structure.n_switches, iterations=r.iterations,
                         resim_miss=r.resim_miss, miss_bound=r.miss_bound, solve_time_s=r.solve_time_s,
                         cpu_time_s=r.cpu_time_s) for r in runs)
    return replace(best, starts=starts, solve_time_s=sum(r.solve_time_s for r in runs), build_time_s=build_time_s,
                   total_time_s=total_time_s, cpu_time_s=build_cpu_time_s + sum(r.cpu_time_s for r in runs),
                   limits=limits)


def verified(problem, method, settings, t, x, u, converged, solver_message, iterations, miss_tol, solve_time_s,
             guess, branch=None, *, limited=False, cpu_time_s=0.0, integration=None):
    """The DirectSolution of one start (grid t, node states x, control u): the branch reached (the
    nearest to theta_N unless given) and the control re-simulated independently. A converged start
    that misses by more than miss_tol is a discretisation result when within miss_tol plus the
    transcription's own estimate of its integration error (`integration`, default `settings`:
    `Transcription.integration_error`), else it misses the target. Its T bound the transcription's
    (`settings`; None: another program's, no bound). Only a converged start is re-simulated (its miss
    decides its class); a diverged one's control may run for thousands of time units at angular
    velocities of thousands, where DOP853 at 1e-13 takes minutes, and its miss would decide nothing."""
    branch = problem.nearest_branch(x[-1, 0]) if branch is None else branch
    miss = math.nan                 # a start the solver did not finish is not re-simulated: nothing rests on it
    if converged:
        final = simulate.piecewise(problem.x0, t, u, problem.kappa)[-1]
        miss = float(np.hypot(*(final - np.array(problem.target(branch)))))
    integration = settings if integration is None else integration
    bound = None
    if converged is None:
        status = DirectStatus.SOLVER_ERROR
    elif not converged:
        status = DirectStatus.NOT_CONVERGED
    elif miss <= miss_tol:
        status = DirectStatus.VERIFIED
    else:
        error = None if integration is None else integration.integration_error(t, u, problem.x0, problem.kappa)
        bound = None if error is None else miss_tol + error
        status = DirectStatus.DISCRETISATION if bound is not None and miss <= bound else DirectStatus.MISSES_TARGET
    read = structure.read(t, x, u, problem.kappa)
    T_bound = None if settings is None or status not in (DirectStatus.VERIFIED, DirectStatus.DISCRETISATION) \
        else settings.T_bound(read, problem.kappa, miss)
    return DirectSolution(problem, method, status, solver_message, float(t[-1]), t, x, u, branch, iterations, read,
                          miss, miss_tol, T_bound, 0.0, solve_time_s, solve_time_s, guess, (),
                          _why(status, solver_message, limited, miss, miss_tol, bound), limited, bound, cpu_time_s)


def _why(status, solver_message, limited, miss, miss_tol, bound):
    """A start's status in words, with the solver's own return status and the numbers that decided it."""
    if status == DirectStatus.MISSES_TARGET:
        accuracy = (f"the transcription's own accuracy at this N ({order(bound)})" if bound is not None else
                    f"miss_tol = {miss_tol:g} (the transcription states no accuracy of its integration)")
        return (f"the solver reported success ({solver_message}), but its control, re-simulated independently, misses "
                f"the target by {order(miss)}, more than {accuracy}")
    if status == DirectStatus.DISCRETISATION:
        return (f"converged ({solver_message}); the control re-simulated independently misses the target by "
                f"{order(miss)}, more than miss_tol = {miss_tol:g} but within the transcription's own accuracy at "
                f"this N ({order(bound)}): a discretisation result")
    if status == DirectStatus.NOT_CONVERGED:
        return f"{MESSAGES[status]} ({solver_message}" + ("; it stopped at its limit)" if limited else ")")
    return f"{MESSAGES[status]} ({solver_message})"


def _run(nlp, problem, guess, miss_tol):
    N = nlp.N
    theta, omega, u = guess.on_grid(N)
    lbx, ubx = nlp.bounds(problem.x0, problem.nlp_target, (0.5 * problem.double_integrator_bound, math.inf))
    w0 = np.clip(nlp.pack(theta, omega, guess.T, u), lbx, ubx)
    start, cpu = time.perf_counter(), time.process_time()
    converged = None
    try:
        w = np.array(nlp.solver(x0=w0, lbx=lbx, ubx=ubx, lbg=nlp.lbg, ubg=nlp.ubg,
                                p=[problem.kappa, problem.nlp_target])["x"]).ravel()
        stats = nlp.solver.stats()
        message = _message(stats)
        converged = bool(stats.get("success", False))
    except RuntimeError as err:      # a solver that cannot run (e.g. a missing linear solver) fails this start
        w, stats, message = w0, {}, f"solver error: {last_line(err)}"
    wall, cpu = own_times(stats, time.perf_counter() - start, time.process_time() - cpu)
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
                    iterations, miss_tol, wall, guess.label, problem.branch, limited=limited(stats), cpu_time_s=cpu)


def own_times(stats, wall, cpu):
    """(wall, CPU) seconds of one solver call: the solver's own (CasADi's record_time stats,
    t_wall_total and t_proc_total), else those measured around the call (`wall`, `cpu`: the
    process's CPU time)."""
    return float(stats.get("t_wall_total", wall)), float(stats.get("t_proc_total", cpu))


def limited(stats):
    """Whether the solver stopped at one of its limits (CasADi's unified return status, from the
    solver's own: iterations, CPU or wall time)."""
    return stats.get("unified_return_status") == "SOLVER_RET_LIMITED"


def _message(stats):
    """The solver's own return status, or CasADi's unified one where the solver gives a number."""
    status = stats.get("return_status")
    return status if isinstance(status, str) else str(stats.get("unified_return_status", status))
