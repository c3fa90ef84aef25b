"""A solution's trajectory at any times, in the spirit of rockit's `sample` and scipy's dense output:
theta, omega, u and, along an extremal, the costate p = (p1, p2).

A control is a sequence of arcs, u = values[i] on [knots[i], knots[i+1]) (bang arcs of an extremal,
or the runs of equal u of a direct answer's piecewise-constant control). The state, and the costate
where p(0) is given, are integrated arc by arc from x0 by scipy's DOP853 at RTOL, restarted at every
knot and never across one:

    theta' = omega,   omega' = kappa u - sin(theta),   p1' = p2 cos(theta),   p2' = -p1

(the costate equation of H = p . f(x, u) - 1, `ocp.core.model.costate_rhs`). u is right-continuous:
at a knot it is the value of the arc that begins there (at the final time, the last arc's), so that
holding each sample's u until the next sample time is the control exactly when every knot is a
sample time (`times`).
"""

import csv
import io
import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .core.errors import InputError
from .core.files import write_text
from .core.numbers import decimals

RTOL = 1e-13
#: the looser integration whose change from RTOL's estimates the integration error
CHECK_RTOL = 1e-11
COLUMNS = ("t", "theta", "omega", "u", "p1", "p2")


@dataclass(frozen=True)
class Samples:
    """The trajectory at the times t (increasing, nondimensional), each field an array of len(t):

    theta, omega   the state (rad, rad per time unit)
    u              the control (right-continuous at a switch)
    p1, p2         the costate of the extremal (H = p . f - 1 = 0), None for a direct answer (the NLP's
                   multipliers are not a costate this suite checks)
    state_error    estimate of the error of theta and omega: the change between integrations at RTOL
                   and CHECK_RTOL (at least RTOL relative per arc, summed over the arcs), plus at each
                   knot its time error times the jump of omega' there
    costate_error  the same for p1 and p2 (None without a costate)
    miss           the distance in (theta, omega) of the integrated final state from the target
    source         what was sampled, in words
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    u: np.ndarray
    p1: np.ndarray | None
    p2: np.ndarray | None
    state_error: float
    costate_error: float | None
    miss: float
    source: str

    def to_dict(self):
        out = {name: None if getattr(self, name) is None else getattr(self, name).tolist() for name in COLUMNS}
        out.update(state_error=self.state_error, costate_error=self.costate_error, miss=self.miss, source=self.source)
        return out

    def csv_text(self):
        """CSV with the header t,theta,omega,u,p1,p2: t exact (the sample time itself), the state and
        costate to the decimals their error defends, p1 and p2 empty without a costate."""
        state, costate = decimals(self.state_error), decimals(self.costate_error or 0.0)
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(COLUMNS)
        for k, t in enumerate(self.t):
            u = float(self.u[k])
            row = [repr(float(t)), f"{self.theta[k]:.{state}f}", f"{self.omega[k]:.{state}f}",
                   str(int(u)) if u.is_integer() else repr(u)]
            row += ["", ""] if self.p1 is None else [f"{self.p1[k]:.{costate}f}", f"{self.p2[k]:.{costate}f}"]
            writer.writerow(row)
        return out.getvalue()

    def write_csv(self, path):
        """The CSV written whole (`ocp.core.files`: Fault if it cannot be); returns the path."""
        return write_text(path, self.csv_text())


def times(knots, every):
    """Sample times 0, every, 2 every, ... below the final time, with every knot (switch) and the
    final time: holding each sample's u until the next is then the control exactly."""
    if not (isinstance(every, (int, float)) and math.isfinite(every) and every > 0):
        raise InputError(f"sample spacing {every!r}: accepted a positive number of time units")
    end = float(knots[-1])
    if end / every > 1e6:
        raise InputError(f"sample spacing {every:g}: more than a million samples over T = {end:g}; accepted >= {end / 1e6:g}")
    grid = every * np.arange(math.ceil(end / every))
    return np.unique(np.concatenate([grid[grid < end], np.asarray(knots, float)]))


def runs(t, u):
    """(knots, values) of a piecewise-constant control u[k] on [t[k], t[k+1]]: runs of equal u merged."""
    t, u = np.asarray(t, float), np.asarray(u, float)
    starts = np.flatnonzero(np.r_[True, u[1:] != u[:-1]])
    return np.r_[t[starts], t[-1]], u[starts]


def _integrate(x0, p0, kappa, knots, values, t, rtol):
    """States (and costates) (len(t), 2 or 4) at the sorted times t, and the final one, arc by arc."""
    y = np.array([*x0, *(p0 or ())], float)
    out = np.empty((len(t), len(y)))
    for i, u in enumerate(values):
        a, b = knots[i], knots[i + 1]
        inside = (t >= a) & ((t < b) | ((i == len(values) - 1) & (t <= b)))
        if b <= a:
            out[inside] = y
            continue

        def f(_, z, u=u):
            dz = [z[1], kappa * u - math.sin(z[0])]
            return dz + [z[3] * math.cos(z[0]), -z[2]] if len(z) == 4 else dz

        at = t[inside]
        ends = not len(at) or at[-1] < b              # b itself is integrated to, sampled or not
        sol = solve_ivp(f, (a, b), y, method="DOP853", rtol=rtol, atol=rtol, t_eval=np.r_[at, b] if ends else at)
        if not sol.success:
            raise ArithmeticError(f"the sampling integration failed on arc {i}: {sol.message}")
        out[inside] = sol.y[:, :len(at)].T
        y = sol.y[:, -1]
    return out, y


def sample(x0, kappa, knots, values, t, target, source, p0=None, knot_error=0.0):
    """Samples of the control `values` on the arcs between `knots` from x0 at the times t (a number
    or an array within [knots[0], knots[-1]]); `target` the state the trajectory should end at;
    `knot_error` the error of the knots (the switch times); p0 the costate at t = 0, if any."""
    t = np.atleast_1d(np.asarray(t, float))
    if t.ndim != 1 or not np.all(np.isfinite(t)):
        raise InputError("sample times: accepted a number or a one-dimensional array of finite numbers")
    end = float(knots[-1])
    if len(t) and (t.min() < knots[0] or t.max() > end):
        raise InputError(f"sample times must lie in [0, T] = [0, {end:.6g}]; got [{t.min():.6g}, {t.max():.6g}]")
    order = np.argsort(t, kind="stable")
    ts = t[order]
    if not len(values):                  # a start on the target: no arc, no control
        y = np.tile(np.asarray(x0, float), (len(t), 1))
        return Samples(t, y[:, 0], y[:, 1], np.zeros(len(t)), None, None, 0.0, None,
                       float(np.hypot(*np.subtract(x0, target))), source)
    fine, y_end = _integrate(x0, p0, kappa, knots, values, ts, RTOL)
    rough, _ = _integrate(x0, p0, kappa, knots, values, ts, CHECK_RTOL)
    spread = np.abs(fine - rough).max(axis=0) if len(ts) else np.zeros(fine.shape[1])
    # where both integrations take the same steps their change is no estimate: at least RTOL
    # relative on every arc, summed over the arcs
    floor = RTOL * len(values) * np.maximum(1.0, np.abs(fine).max(axis=0, initial=0.0))
    spread = np.maximum(spread, floor)
    jumps = kappa * np.abs(np.diff(values)).sum()        # omega' jumps by kappa |du| at a switch
    state_error = float(spread[:2].max() + knot_error * jumps)
    costate_error = None if p0 is None else float(spread[2:].max() + knot_error * jumps)
    values = np.asarray(values, float)
    arc = np.clip(np.searchsorted(knots, ts, side="right") - 1, 0, len(values) - 1)
    states = np.empty_like(fine)
    states[order] = fine
    u = np.empty(len(t))
    u[order] = values[arc]
    return Samples(t, states[:, 0], states[:, 1], u, None if p0 is None else states[:, 2],
                   None if p0 is None else states[:, 3], state_error, costate_error,
                   float(np.hypot(*np.subtract(y_end[:2], target))), source)
