"""`solve(problem, ...)`: the direct multiple-shooting solution of a minimum-time problem.

The initial guess is either given (a `Guess`, or a previous `Solution` to warm-start from) or the
default family `default_guesses(problem)`: each is solved and the best verified solution returned,
all starts recorded. A solution is verified by re-simulating its control independently
(`ocp.simulate`) and measuring how far it lands from the target.
"""

import math
import time
from dataclasses import dataclass

import numpy as np

from . import simulate, structure
from .errors import InputError, last_line
from .problems import Problem
from .result import Solution
from .transcription import MultipleShooting, T_BOUNDS, build

MISS_TOL = 1e-6


@dataclass(frozen=True)
class Guess:
    """An initial guess on normalised time s in [0, 1]: T, and theta, omega at the nodes `s`, u on
    the intervals (len(s) - 1 values). It is resampled to the transcription's grid (linear
    interpolation of the states, the control taken at interval midpoints)."""

    T: float
    s: tuple
    theta: tuple
    omega: tuple
    u: tuple
    label: str = "user"

    @classmethod
    def from_solution(cls, sol, label="warm start"):
        """The direct grid of a Solution (its T_direct: sol.T may be the refined time)."""
        T = sol.T_direct
        return cls(T, tuple(sol.t / T), tuple(sol.x[:, 0]), tuple(sol.x[:, 1]), tuple(sol.u), label)

    def on_grid(self, N):
        s = np.linspace(0.0, 1.0, N + 1)
        src = np.asarray(self.s, float)
        mid = 0.5 * (src[:-1] + src[1:])
        return (np.interp(s, src, self.theta), np.interp(s, src, self.omega),
                np.interp(0.5 * (s[:-1] + s[1:]), mid, self.u))


def default_guesses(problem, N=100):
    """Three guesses with u = 0: braking from x0 to rest at `problem.stop_angle` (theta'' =
    -kappa*sign(omega0), for t_b = |omega0|/kappa), then theta = stop + d*sigma + b*sin(pi*sigma),
    sigma from 0 to 1, d = target - stop (branch `problem.guess_branch`), for a detour b = 0, -1,
    +1 rad (straight at the target, or first swinging the other way: a backswing), in

        T_rest = max(2*sqrt(|d|/kappa), 1.2*|d|/kappa),

    the two limits of the optimal time from rest: a double integrator for large kappa, energy
    pumped at a rate of about kappa*|omega| for small kappa (from (0, 0) the optimum is
    1.20 pi/kappa at kappa = 0.3)."""
    theta0, omega0 = problem.x0
    kappa, stop = problem.kappa, problem.stop_angle
    d = problem.target(problem.guess_branch)[0] - stop
    t_brake = abs(omega0) / kappa
    T = t_brake + max(2 * math.sqrt(abs(d) / kappa), 1.2 * abs(d) / kappa)
    T = min(max(T, 2 * T_BOUNDS[0]), 0.5 * T_BOUNDS[1])
    s = np.linspace(0.0, 1.0, N + 1)
    t = s * T
    braking = theta0 + omega0 * t - math.copysign(kappa, omega0) * t * t / 2
    sigma = np.clip((t - t_brake) / (T - t_brake), 0.0, 1.0)
    direction = math.copysign(1.0, d) if d else 1.0
    guesses = []
    for b, name in ((0.0, "straight"), (-1.0, "backswing"), (1.0, "overswing")):
        theta = np.where(t < t_brake, braking, stop + d * sigma + direction * b * np.sin(math.pi * sigma))
        omega = np.gradient(theta, s) / T
        omega[0] = omega0
        guesses.append(Guess(T, tuple(s), tuple(theta), tuple(omega), (0.0,) * N, name))
    return guesses


def random_guess(problem, seed, N):
    """A seeded random Guess: ocp's straight guess with T scaled by a factor in [1/2, 2], theta
    displaced by three sine modes of amplitude up to 2 rad, and u uniform in [-1, 1]."""
    rng = np.random.default_rng(seed)
    base = default_guesses(problem, N)[0]
    s = np.asarray(base.s)
    T = base.T * math.exp(rng.uniform(-math.log(2), math.log(2)))
    theta = np.asarray(base.theta) + sum(rng.uniform(-2, 2) * np.sin(j * math.pi * s) for j in (1, 2, 3))
    omega = np.gradient(theta, s) / T
    omega[0] = problem.x0[1]
    return Guess(T, tuple(s), tuple(theta), tuple(omega), tuple(rng.uniform(-1, 1, N)), f"random (seed {seed})")


def solve(problem, method=None, solver="ipopt", options=None, guess=None, miss_tol=MISS_TOL):
    """Minimum-time solution of `problem` by direct multiple shooting (`method`, default
    MultipleShooting()), NLP solved by casadi.nlpsol(`solver`, `options`) (options untouched).

    `guess`: None (the default family, best verified of them returned), a Guess, or a Solution.
    Returns a `Solution`; `success` requires the independent re-simulation to land within
    `miss_tol` of the target."""
    if not isinstance(problem, Problem):
        raise InputError(f"problem must be an ocp Problem (ocp.swing_up / ocp.damping), not {type(problem).__name__}")
    method = MultipleShooting() if method is None else method
    if not (isinstance(miss_tol, (int, float)) and miss_tol > 0):
        raise InputError(f"miss_tol = {miss_tol!r} must be a number > 0")
    start = time.perf_counter()
    transcription = build(method, solver, options, free_branch=problem.branch is None)
    if guess is None:
        guesses = default_guesses(problem, method.N)
    elif isinstance(guess, Solution):
        guesses = [Guess.from_solution(guess)]
    elif isinstance(guess, Guess):
        guesses = [guess]
    else:
        raise InputError(f"guess must be None, an ocp Guess or an ocp Solution, not {type(guess).__name__}")
    best = best_of([_run(transcription, problem, g, miss_tol) for g in guesses])
    best.build_time_s = transcription.build_time_s
    best.total_time_s = time.perf_counter() - start
    return best


def best_of(runs):
    """The best of the Solutions of several starts (verified first, then converged, then the
    shortest T), with every start recorded in its `starts` and their solve times summed."""
    best = min(runs, key=lambda r: (not r.success, not r.solver_success, r.T if math.isfinite(r.T) else math.inf))
    best.starts = [{"guess": r.guess, "success": r.success, "status": r.status, "T": r.T,
                    "n_switches": r.n_switches, "iterations": r.iterations, "solve_time_s": r.solve_time_s}
                   for r in runs]
    best.solve_time_s = sum(r.solve_time_s for r in runs)
    return best


def verified(problem, method, t, x, u, solver_ok, status, iterations, miss_tol, build_time_s, solve_time_s, guess,
             branch=None):
    """The Solution of a direct answer (grid t, node states x, control u): the branch reached (the
    nearest to theta_N unless given), and the control re-simulated independently; success needs
    the solver's success and a miss within miss_tol."""
    branch = problem.nearest_branch(x[-1, 0]) if branch is None else branch
    final = simulate.piecewise(problem.x0, t, u, problem.kappa)[-1]
    miss = float(np.hypot(*(final - np.array(problem.target(branch)))))
    ok = solver_ok and miss <= miss_tol
    if solver_ok and not ok:
        status = f"{status}, but the re-simulated control misses the target by {miss:.1e} > {miss_tol:.0e}"
    return Solution(problem, method, float(t[-1]), t, x, u, branch, ok, status, solver_ok, iterations,
                    structure.read(t, x, u, problem.kappa), miss, miss_tol, build_time_s, solve_time_s,
                    solve_time_s, guess)


def _run(tr, problem, guess, miss_tol):
    N = tr.N
    theta, omega, u = guess.on_grid(N)
    w0 = tr.pack(theta, omega, guess.T, u)
    theta_end = None if problem.branch is None else problem.target(problem.branch)[0]
    lbx, ubx = tr.bounds(problem.x0, theta_end)
    w0 = np.clip(w0, lbx, ubx)
    start = time.perf_counter()
    try:
        w = np.array(tr.solver(x0=w0, lbx=lbx, ubx=ubx, lbg=tr.lbg, ubg=tr.ubg,
                               p=[problem.kappa, problem.target_base])["x"]).ravel()
        stats = tr.solver.stats()
        status = _status(stats)
    except RuntimeError as err:      # a solver that cannot run (e.g. a missing linear solver) fails this start
        w, stats, status = w0, {}, f"solver error: {last_line(err)}"
    i_th, i_om, i_T, i_u = tr.index()
    if not (np.all(np.isfinite(w)) and w[i_T[0]] > 0):   # e.g. bonmin's NaN or all-zero exit: a failed
        w, stats, status = w0, {}, f"{status}: the solver returned no usable point (T <= 0 or not finite)"
    solve_time = time.perf_counter() - start
    t = np.linspace(0.0, float(w[i_T[0]]), N + 1)
    x = np.column_stack([w[i_th], w[i_om]])
    method = dict(tr.settings.to_dict(), solver=tr.solver_name, options=tr.options)
    iterations = stats.get("iter_count", -1)
    iterations = int(iterations) if math.isfinite(iterations) else -1          # bonmin reports NaN
    return verified(problem, method, t, x, np.clip(w[i_u], -1.0, 1.0), bool(stats.get("success", False)), status,
                    iterations, miss_tol, tr.build_time_s, solve_time, guess.label, problem.branch)


def _status(stats):
    """The solver's own return status, or CasADi's unified one where the solver gives a number."""
    status = stats.get("return_status")
    return status if isinstance(status, str) else str(stats.get("unified_return_status", status))
