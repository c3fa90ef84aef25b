"""The peer: rockit (rockit-meco, a dependency of ocp), solving the same cases with its own
multiple shooting (`rockit.MultipleShooting(N, M, intg="rk")`, free final time), on a uniform grid
or on rockit's FreeGrid (every interval's length a variable), from the same initial guesses,
verified by ocp's independent re-simulation on the grid rockit solved, read by ocp's structure
reader.

Like `ocp.direct.solve`, every guess is solved and the best verified answer kept, each under the
solver's own limits (`ocp.direct.solvers.limits`, passed through rockit to its solver); the NLP
is transcribed once per call (rockit has no cache across calls), and that is its build time. A
converged answer's miss is judged against the integration error of rockit's "rk" (M RK4 steps per
interval, ocp's rk4 multiple shooting) on the grid it solved.
"""

import importlib.util
import math
import time

import numpy as np

from .. import direct
from ..core.errors import last_line
from ..core.problem import CONTROL_BOUNDS, dynamics, terminal_bounds, terminal_constraints
from ..direct import solvers
from ..direct.solve import best_of, limited, own_times, verified
from .suite import PEER_FREE_GRID

MISSING = "rockit is not installed (pip install rockit-meco, a dependency of ocp): its runs are skipped"


def available():
    return importlib.util.find_spec("rockit") is not None


def _ocp(problem, method, T_guess, limits):
    """The rockit Ocp of `problem`: dynamics, control bounds and terminal set as declared in
    `ocp.core.problem`; its solver under `limits` and the options of `method`."""
    import casadi as ca
    import rockit

    oc = rockit.Ocp(T=rockit.FreeTime(T_guess))
    theta, omega, u = oc.state(), oc.state(), oc.control()
    f = dynamics(ca.vertcat(theta, omega), u, problem.kappa)
    oc.set_der(theta, f[0])
    oc.set_der(omega, f[1])
    oc.subject_to(CONTROL_BOUNDS[0] <= (u <= CONTROL_BOUNDS[1]))
    oc.subject_to(oc.at_t0(theta) == problem.x0[0])
    oc.subject_to(oc.at_t0(omega) == problem.x0[1])
    for name, value in terminal_bounds(problem.reading, problem.nlp_target).items():
        if value is not None:
            oc.subject_to(oc.at_tf({"theta": theta, "omega": omega}[name]) == value)
    for expression, lower, upper in terminal_constraints(problem.reading, oc.at_tf(theta), oc.at_tf(omega),
                                                         problem.nlp_target):
        if lower == upper:
            oc.subject_to(expression == lower)
        else:
            oc.subject_to(expression >= lower)
    oc.add_objective(oc.T)
    settings = method.transcription_object()
    grid = rockit.FreeGrid() if method.transcription == PEER_FREE_GRID else rockit.UniformGrid()
    oc.method(rockit.MultipleShooting(N=settings.N, M=settings.M, intg="rk", grid=grid))
    solvers.require("nlpsol", method.solver)
    quiet = {"expand": True, "print_time": False, "record_time": True, **solvers.solver(method.solver).quiet}
    oc.solver(method.solver, quiet | method.applied | limits)
    return oc, (theta, omega, u)


def solve(problem, method, guess=None, miss_tol=direct.MISS_TOL, time_limit_s=math.inf):
    """An ocp `Solution` of `problem` by rockit; `guess` None (ocp's default starts) or a Guess;
    every start under the solver's limits (`time_limit_s`: its CPU seconds where it has such an
    option). Returns (solution, (n_w, n_g)), the NLP size as rockit built it."""
    with solvers.loading():             # rockit's nlpsol loads its plugins here: never from the working folder
        return _solve(problem, method, guess, miss_tol, time_limit_s)


def _solve(problem, method, guess, miss_tol, time_limit_s):
    start, cpu = time.perf_counter(), time.process_time()
    settings = method.transcription_object()
    guesses = direct.default_guesses(problem, settings.N) if guess is None else [guess]
    limits = solvers.limits(method.solver, method.applied, time_limit_s)
    oc, (theta, omega, u) = _ocp(problem, method, guesses[0].T, limits)
    oc._transcribe()           # rockit transcribes lazily on solve; done here so the build is timed alone
    build_time, build_cpu = time.perf_counter() - start, time.process_time() - cpu
    runs = []
    opti = oc._method.opti
    # rockit's own set_initial of a sampled array takes seconds (it evaluates an interpolant at
    # every node symbolically); the grid values go straight to the Opti variables instead
    nodes = [oc.sample(v, grid="control")[1] for v in (oc.T, theta, omega, u)]
    N = settings.N
    for g in guesses:
        for var, values, n in zip(nodes, (g.T, *g.on_grid(N)), (1, N + 1, N + 1, N)):
            opti.set_initial(var[:, :n], values)
        if method.transcription == PEER_FREE_GRID:          # each interval's length: a variable of its own
            for length in oc._method.T_local:
                opti.set_initial(length, g.T / N)
        runs.append(_run(oc, (theta, omega, u), problem, method, g, miss_tol))
    return best_of(runs, build_time, time.perf_counter() - start, build_cpu, limits), (opti.nx, opti.ng)


def _run(oc, variables, problem, method, guess, miss_tol):
    theta, omega, u = variables
    start, cpu = time.perf_counter(), time.process_time()
    try:
        sol = oc.solve()
        stats = sol.stats
    except RuntimeError as err:       # rockit raises when the solver does not succeed
        sol, stats = oc.non_converged_solution, {"return_status": f"not converged: {last_line(err)}"}
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    stats = dict(oc._method.opti.stats(), **stats)
    wall, cpu = own_times(stats, wall, cpu)
    t, theta_k = sol.sample(theta, grid="control")          # the control grid rockit solved (free or uniform)
    x = np.column_stack([theta_k, sol.sample(omega, grid="control")[1]])
    info = dict(method.to_dict(), transcription=f"{method.transcription} multiple shooting", integrator="rk")
    return verified(problem, info, None, t, x, np.clip(sol.sample(u, grid="control")[1][:-1], -1.0, 1.0),
                    bool(stats.get("success", False)), str(stats.get("return_status")),
                    int(stats.get("iter_count", -1)), miss_tol, wall, guess.label, problem.branch,
                    limited=limited(stats), cpu_time_s=cpu,
                    integration=method.transcription_object())
