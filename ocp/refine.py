"""Refinement: the switching-time problem of a bang-bang structure, to integrator precision.

For arcs u = s_1, ..., s_n (fixed signs) of durations d_1, ..., d_n (the unknowns):

    minimise T = sum(d)   subject to   x(T; d) = target.

Its first-order conditions are Pontryagin's (maximum principle, H = p1*omega + p2*(kappa*u -
sin(theta)) - 1, p' = -dH/dx, u = sign(p2), H = 0 for free final time): with p(0) as 2 more
unknowns, the square system

    x(T) - target = 0                       (2 equations)
    p2(t_j) = 0 at each switch t_j          (n - 1)
    H(0) = 0                                (1)

in (d, p(0)) (n + 2 unknowns) is solved by Newton's method, the state and costate integrated by
CVODES and differentiated by its forward sensitivities: iterations at rtol = atol = TOL_COARSE,
then polished at TOL. Newton starts from the switching-time problem itself solved by IPOPT
(d >= 0; RK4 with fixed steps per arc, about STEP_ANGLE rad of rotation each, the count rounded up
to one of STEP_COUNTS: a globalised, moderately accurate first stage) and from the p(0) that solves
the conditions (linear in p(0)) in least squares along those durations. The Lagrange multiplier of
the end constraint is -p(T).

The accuracy of T and of the switch times is estimated (`with_error_estimate`) by solving again at
TOL_CHECK, from the converged solution, and taking the difference. An arc that the first stage
shrinks below COLLAPSE * T has collapsed: the structure is then not an extremal of its own.
"""

import time
from dataclasses import dataclass, replace
from functools import lru_cache

import casadi as ca
import numpy as np

from . import model, simulate
from .errors import last_line
from .transcription import rk4_flow

TOL = 1e-14
TOL_CHECK = 1e-12
TOL_COARSE = 1e-10
STEP_ANGLE = 0.3
STEP_COUNTS = (50, 200, 800, 3200)
MAX_ITER = 100             # IPOPT iterations of the first stage: a feasible structure needs far fewer
COLLAPSE = 1e-7
MAX_STEPS = 100000         # CVODES steps per arc (a fast spin of ~100 rad needs ~10^4 at TOL)
RESIDUAL_TOL = 1e-10  # the conditions hold to integrator noise


@dataclass(frozen=True)
class Refined:
    """A bang-bang extremal: arc signs and durations, T, switch times and states, p(0), the
    Newton residual, and error estimates of T and of the switch times (from two tolerances)."""

    signs: tuple
    durations: tuple
    T: float
    switch_times: tuple
    switch_states: tuple
    final_state: tuple
    p0: tuple
    residual: float
    converged: bool
    status: str
    iterations: int
    T_error: float
    switch_time_error: float
    time_s: float

    @property
    def n_switches(self):
        return len(self.signs) - 1

    @property
    def first_u(self):
        return self.signs[0]

    def to_dict(self):
        return {
            "signs": list(self.signs), "durations": list(self.durations), "T": self.T,
            "switch_times": list(self.switch_times), "switch_states": [list(s) for s in self.switch_states],
            "final_state": list(self.final_state), "p0": list(self.p0), "residual": self.residual,
            "converged": self.converged, "status": self.status, "iterations": self.iterations, "T_error": self.T_error,
            "switch_time_error": self.switch_time_error, "time_s": self.time_s,
        }


@lru_cache(maxsize=4)
def state_costate_flow(tol):
    """Phi(y, u, d, kappa): y = (theta, omega, p1, p2) after time d under constant u (CVODES, tol)."""
    integ = ca.integrator("Phi", "cvodes", model.state_costate_dae(), 0, 1,
                          {"abstol": tol, "reltol": tol, "max_num_steps": MAX_STEPS})
    ys, us, ds, ks = ca.MX.sym("y", 4), ca.MX.sym("u"), ca.MX.sym("d"), ca.MX.sym("kappa")
    return ca.Function("Phi", [ys, us, ds, ks], [integ(x0=ys, p=ca.vertcat(us, ds, ks))["xf"]])


@lru_cache(maxsize=32)
def _newton(n, tol):
    """Newton solver of the n-arc conditions: (v0, params) -> v, v = (d_1..d_n, p1(0), p2(0)),
    params = (theta0, omega0, kappa, s_1..s_n, theta_T, omega_T).

    One arc (no switch) has no switching condition: d alone must meet theta(T) = theta_T (omega(T)
    is then checked by the residual), and p(0) is fixed by H(0) = 0 and p(0) parallel to f(x0)."""
    phi = state_costate_flow(tol)
    v = ca.MX.sym("v", n + 2)
    par = ca.MX.sym("par", 5 + n)
    x0, kappa, s, target = par[0:2], par[2], par[3:3 + n], par[3 + n:5 + n]
    y = ca.vertcat(x0, v[n:])
    f0 = model.rhs(x0, s[0], kappa)
    h0 = model.hamiltonian(x0, v[n:], s[0], kappa)
    at_switch = []
    for i in range(n):
        y = phi(y, s[i], v[i], kappa)
        if i < n - 1:
            at_switch.append(y[3])
    if n == 1:
        conditions = ca.vertcat(y[0] - target[0], h0, v[n] * f0[1] - v[n + 1] * f0[0])
        residual = ca.Function("R", [v, par], [ca.vertcat(y[0:2] - target, h0)])
        solver = ca.rootfinder("newton", "newton", ca.Function("C", [v, par], [conditions]), _newton_options(tol))
        return solver, residual
    residual = ca.Function("R", [v, par], [ca.vertcat(y[0:2] - target, *at_switch, h0)])
    solver = ca.rootfinder("newton", "newton", residual, _newton_options(tol))
    return solver, residual


def _newton_options(tol):
    """Stop at 10 * tol: below that the residual is integrator noise."""
    return {"abstol": 10 * tol, "abstolStep": 1e-15, "max_iter": 15, "error_on_fail": False}


@lru_cache(maxsize=32)
def _switching_time_nlp(n, steps):
    """IPOPT on min sum(d) s.t. x(T; d) = target, d >= 0 (RK4, `steps` per arc); params (theta0,
    omega0, kappa, s, target)."""
    d = ca.SX.sym("d", n)
    par = ca.SX.sym("par", 5 + n)
    x, kappa, s, target = par[0:2], par[2], par[3:3 + n], par[3 + n:5 + n]
    for i in range(n):
        x = rk4_flow(x, s[i], kappa, d[i], steps)
    nlp = {"x": d, "p": par, "f": ca.sum1(d), "g": x - target}
    return ca.nlpsol("switching_times", "ipopt", nlp, {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes",
                                                       "ipopt.tol": 1e-10, "ipopt.max_iter": MAX_ITER})


def switching_times(x0, kappa, target, signs, durations):
    """(durations, success): the switching-time problem by IPOPT from `durations` (first stage)."""
    n = len(signs)
    wanted = np.max(durations) * simulate.peak_speed(x0, signs, durations, kappa) / STEP_ANGLE
    solver = _switching_time_nlp(n, next((c for c in STEP_COUNTS if c >= wanted), STEP_COUNTS[-1]))
    par = np.concatenate([x0, [kappa], signs, target])
    d = solver(x0=np.maximum(durations, 1e-3), p=par, lbx=0.0, ubx=np.inf, lbg=0.0, ubg=0.0)["x"]
    return np.array(d).ravel(), bool(solver.stats()["success"])


def _trajectory(x0, p0, signs, durations, kappa, tol):
    """State-costate at the start and at the end of every arc: array (n + 1, 4)."""
    phi = state_costate_flow(tol)
    y = [np.concatenate([x0, p0])]
    for s, d in zip(signs, durations):
        y.append(np.array(phi(y[-1], s, d, kappa)).ravel())
    return np.array(y)


def costate_guess(x0, signs, durations, kappa):
    """p(0) minimising the residual of the conditions p2(t_j) = 0, H(0) = 0 (linear in p(0)) along
    fixed durations."""
    rows = []
    for p0 in (np.zeros(2), np.eye(2)[0], np.eye(2)[1]):
        y = _trajectory(np.asarray(x0, float), p0, signs, durations, kappa, 1e-10)
        rows.append(y[1:-1, 3])
    base, e1, e2 = rows
    f0 = model.rhs(x0, signs[0], kappa)
    A = np.vstack([np.column_stack([e1 - base, e2 - base]), f0])
    b = np.concatenate([-base, [1.0]])
    return np.linalg.lstsq(A, b, rcond=None)[0]


def refine(x0, kappa, target, signs, durations):
    """The extremal with arc signs `signs` nearest to the initial `durations` (see module doc);
    its T_error and switch_time_error are NaN until `with_error_estimate`."""
    start = time.perf_counter()
    signs = tuple(int(s) for s in signs)
    n = len(signs)
    x0 = np.asarray(x0, float)
    durations = np.asarray(durations, float)
    if n == 1:
        # one arc of u = s conserves omega^2/2 - cos(theta) - kappa*s*theta: x0 must share the target's value
        gap = abs(model.arc_invariant(x0, signs[0], kappa) - model.arc_invariant(np.asarray(target), signs[0], kappa))
        if gap > 1e-9:
            return _failed(signs, durations, f"x0 is not on the u = {signs[0]:+d} arc into the target "
                                             f"(arc invariants differ by {gap:.1e})", start)
    if n >= 2:
        durations, ok = switching_times(x0, kappa, target, signs, durations)
        if not ok:
            return _failed(signs, durations, "the switching-time problem has no solution from this start", start)
        short = [i for i, d in enumerate(durations) if d < COLLAPSE * np.sum(durations)]
        if short:
            return _failed(signs, durations, "collapsed: zero-length arc " + ", ".join(str(i + 1) for i in short), start)
    par = np.concatenate([x0, [kappa], signs, target])
    v = np.concatenate([durations, costate_guess(x0, signs, durations, kappa)])
    coarse = _solve(n, TOL_COARSE, v, par)[0]                         # cheap iterations first,
    v, res, iterations, failure = _solve(n, TOL, coarse if np.all(np.isfinite(coarse)) else v, par)  # then polish
    if failure:
        return _failed(signs, durations, failure, start)
    d = v[:n]
    y = _trajectory(x0, v[n:], signs, d, kappa, TOL)
    nan = float("nan")
    return Refined(
        signs=signs, durations=tuple(d), T=float(np.sum(d)), switch_times=tuple(np.cumsum(d)[:-1]),
        switch_states=tuple(tuple(row[:2]) for row in y[1:-1]), final_state=tuple(y[-1, :2]),
        p0=tuple(v[n:]), residual=res, converged=True, status="converged", iterations=iterations,
        T_error=nan, switch_time_error=nan, time_s=time.perf_counter() - start,
    )


def _solve(n, tol, v0, par):
    """(v, residual, iterations, failure or "") of the Newton solve of the n-arc conditions."""
    solver, residual = _newton(n, tol)
    try:
        v = np.array(solver(v0, par)).ravel()
    except RuntimeError as err:
        return v0, float("nan"), -1, f"Newton failed: {last_line(err)}"
    res = float(np.max(np.abs(np.array(residual(v, par)))))
    if not res < RESIDUAL_TOL:
        return v, res, -1, f"Newton did not converge (residual {res:.1e})"
    if np.any(v[:n] < 0):
        return v, res, -1, f"Newton converged to a negative arc duration ({np.min(v[:n]):.2e}): not this structure"
    return v, res, int(solver.stats().get("iter_count", -1)), ""


def with_error_estimate(refined, x0, kappa, target):
    """`refined` with T_error and switch_time_error: the change when solved again at TOL_CHECK."""
    n = len(refined.signs)
    par = np.concatenate([x0, [kappa], refined.signs, target])
    v, _, _, failure = _solve(n, TOL_CHECK, np.concatenate([refined.durations, refined.p0]), par)
    if failure:
        return replace(refined, status=f"converged; error estimate failed: {failure}")
    d, d_check = np.array(refined.durations), v[:n]
    return replace(refined, T_error=float(abs(np.sum(d) - np.sum(d_check))),
                   switch_time_error=float(np.max(np.abs(np.cumsum(d)[:-1] - np.cumsum(d_check)[:-1]), initial=0.0)))


def _failed(signs, durations, status, start):
    nan = float("nan")
    return Refined(signs=signs, durations=tuple(durations), T=float(np.sum(durations)), switch_times=(),
                   switch_states=(), final_state=(nan, nan), p0=(nan, nan), residual=nan, converged=False,
                   status=status, iterations=-1, T_error=nan, switch_time_error=nan,
                   time_s=time.perf_counter() - start)
