"""The optimal synthesis on a window of the phase plane, from the field of extremals that end at the
target.

Every extremal reaching the target (theta*, 0) ends with u_T = sign(p2(T)), and H = 0 there reads
p2(T) kappa u_T = 1: the final costate direction psi, p(T) = (cos psi, sin psi), is the one free
parameter (u_T = +1 on (0, pi), -1 on (pi, 2 pi); at 0 and pi the last arc has zero length).
Integrated backwards in time (`ocp.indirect.taylor.extremal`, direction -1), the family sweeps the
phase plane; a state x reached by the extremal psi after a time-to-go s can be steered to the
target in time s with the switches that extremal makes on the way, so the value function is

    V(x) = min over psi, and over the branches k of the target on the circle, of s(x; psi),

and the optimal switch count N(x) is that of the minimising extremal. The field is sampled at
equal times; neighbouring extremals and times span quadrilaterals, split in two triangles on which
s is interpolated linearly and drawn into the grid (the least s kept, `_raster`). A quadrilateral
wider than MAX_CELLS grid cells is not drawn: its extremals are refined (a new psi between them)
unless every grid cell at its corners already holds a value below its time (it is not optimal
there) and it does not cross the window's edge (then its inside is not seen from its corners),
down to a spacing of MIN_SPACING. Interpolation error: the value of a drawn cell is within
the curvature of the field over a few cells, checked against the complete search at random states
(`check`).

Switching curves: the switch points of the extremals where they are optimal (the raster's value
there equals their time). Dispersal curves: grid edges across which the optimal extremal jumps
(psi far apart, another final sign or another branch) with equal values on both sides.
"""

import math
import time
from dataclasses import dataclass

import numpy as np

from ..indirect import taylor
from . import _field

#: a quadrilateral of the field wider than this many grid cells is refined, not drawn
MAX_CELLS = 3.0
#: the finest spacing of the final costate angle
MIN_SPACING = 1e-9
#: a jump of the final costate angle between neighbouring cells larger than this marks a dispersal
MIN_JUMP = math.pi / 4
#: extremals per half-circle before refinement
BASE_PSI = 256
#: an extremal whose time at a point exceeds the value there by this much is not optimal there
DOMINATED = 1e-6


@dataclass(frozen=True)
class Window:
    """A grid of states: theta in [theta_lo, theta_hi] (n_theta points), omega in [omega_lo,
    omega_hi] (n_omega points)."""

    theta_lo: float
    theta_hi: float
    omega_lo: float
    omega_hi: float
    n_theta: int = 401
    n_omega: int = 301

    @property
    def theta(self):
        return np.linspace(self.theta_lo, self.theta_hi, self.n_theta)

    @property
    def omega(self):
        return np.linspace(self.omega_lo, self.omega_hi, self.n_omega)

    @property
    def steps(self):
        return ((self.theta_hi - self.theta_lo) / (self.n_theta - 1), (self.omega_hi - self.omega_lo) / (self.n_omega - 1))


def _strip(V, N, P, B, grid, A, C, ts, ident, circle, max_cells, wide):
    """Draw the strip between the sampled extremals A and C (rows (theta, omega, arcs) at times ts),
    shifted by every 2 pi k that brings it into the grid on the circle (k = 0 on the plane), as the
    two triangles of each quadrilateral of neighbouring times, into V (least time-to-go s,
    interpolated linearly on a triangle), N (switch count of the nearest vertex), P (the strip's
    interval of final costate angles, ident = (lo, hi)), B (the branch k); grid = (theta_lo,
    dtheta, omega_lo, domega). wide[j] = True where the quadrilateral from time j spans more than
    max_cells cells (not drawn). Returns their count. Compiled (`_field.c`)."""
    return _field.strip(V, N, P, B, grid, A, C, ts, ident, circle, max_cells, wide)


@dataclass(frozen=True)
class Synthesis:
    """The optimal synthesis on a Window: V (time to the target, inf where no drawn extremal
    reaches), N (optimal switch count, -1 where none), the interval of final costate angles `psi`
    (n_theta, n_omega, 2) of the field's strip and the target branch of the optimal extremal in
    each cell, the switch points of optimal extremals (theta,
    omega, time-to-go, which switch counted from the target), the dispersal cells, and how it was
    computed."""

    kind: str
    kappa: float
    reading: str
    window: Window
    horizon: float
    V: np.ndarray
    N: np.ndarray
    psi: np.ndarray
    branch: np.ndarray
    switch_points: np.ndarray
    dispersal: np.ndarray
    extremals: int
    unresolved: int
    time_s: float

    @property
    def covered(self):
        return float(np.mean(np.isfinite(self.V)))


class _Field:
    def __init__(self, kind, kappa, horizon, samples):
        from ..core.problem import KINDS

        self.base = KINDS[kind].target_base
        self.kappa = kappa
        self.ts = np.linspace(0.0, horizon, samples + 1)
        self.horizon = horizon
        self.switches = np.empty((256, 5))
        self.events = np.empty((16, 6))
        self.count = 0

    def extremal(self, psi, u):
        """(sampled rows (theta, omega, arcs), switch points (theta, omega, s, index)) of psi."""
        y0 = np.array([self.base, 0.0, math.cos(psi), 0.0 if abs(math.sin(psi)) < 1e-15 else math.sin(psi)])
        rows = np.empty((self.ts.shape[0], 3))
        tol, order = taylor.SCAN
        while True:
            n_sw, _, _, _, _ = taylor.extremal(y0, self.kappa, u, self.horizon, -1.0, tol, order, self.switches,
                                               self.events, self.ts, rows)
            if n_sw <= len(self.switches):
                break
            self.switches = np.empty((2 * n_sw, 5))
        self.count += 1
        sw = self.switches[:n_sw]
        points = np.column_stack([sw[:, 1], sw[:, 2], sw[:, 0], np.arange(1, n_sw + 1)])
        return rows, points


def synthesize(kind, kappa, reading, window, horizon, samples=400):
    """The Synthesis of `kind` ("swing-up", "damping") for bound kappa on `window`, read on the
    circle (every branch of the target) or the plane (branch 0 only), from the extremals whose
    time-to-go is at most `horizon` (states farther from the target stay uncovered)."""
    start = time.perf_counter()
    field = _Field(kind, kappa, horizon, samples)
    V = np.full((window.n_theta, window.n_omega), np.inf)
    N = np.full(V.shape, -1, dtype=np.int64)
    P = np.full(V.shape + (2,), np.nan)
    B = np.zeros(V.shape, dtype=np.int64)
    grid = np.array([window.theta_lo, window.steps[0], window.omega_lo, window.steps[1]])
    circle = reading == "circle"
    points, unresolved = [], 0
    wide = np.zeros(samples, dtype=np.bool_)
    pending = []
    for lo, hi, u in ((0.0, math.pi, 1.0), (math.pi, 2 * math.pi, -1.0)):
        psis = np.linspace(lo, hi, BASE_PSI + 1)
        psis[0] += MIN_SPACING
        psis[-1] -= MIN_SPACING
        rows = [field.extremal(p, u) for p in psis]
        for (pa, (ra, sa)), (pb, (rb, sb)) in zip(zip(psis, rows), zip(psis[1:], rows[1:])):
            pending.append((pa, ra, pb, rb, u))
        for r in rows:
            points.append(r[1])
    while pending:
        deferred = []
        for pa, ra, pb, rb, u in pending:
            count = _strip(V, N, P, B, grid, ra, rb, field.ts, np.array([pa, pb]), circle, MAX_CELLS, wide)
            if count:
                deferred.append((pa, ra, pb, rb, u, wide.copy()))
        pending = []
        for pa, ra, pb, rb, u, w in deferred:
            if not _undominated(V, grid, ra, rb, field.ts, w, circle):
                continue
            if pb - pa < 2 * MIN_SPACING:
                unresolved += 1
                continue
            pm = 0.5 * (pa + pb)
            rm = field.extremal(pm, u)
            points.append(rm[1])
            pending += [(pa, ra, pm, rm[0], u), (pm, rm[0], pb, rb, u)]
    switch_points = _optimal_switch_points(np.concatenate(points) if points else np.empty((0, 4)), V, grid, window,
                                           circle)
    return Synthesis(kind, kappa, reading, window, horizon, V, N, P, B, switch_points, _dispersal(V, P, B, window),
                     field.count, unresolved, time.perf_counter() - start)


def _cells(grid, window, theta, omega, circle):
    """The grid cells of the state (theta, omega): of every theta + 2 pi k on the circle."""
    j = int(round((omega - grid[2]) / grid[3]))
    if not 0 <= j < window.n_omega:
        return []
    if circle:
        ks = range(math.ceil((window.theta_lo - theta) / (2 * math.pi)), math.floor((window.theta_hi - theta) / (2 * math.pi)) + 1)
    else:
        ks = (0,)
    out = []
    for k in ks:
        i = int(round((theta + 2 * math.pi * k - grid[0]) / grid[1]))
        if 0 <= i < window.n_theta:
            out.append((i, j, 2 * math.pi * k))
    return out


def _undominated(V, grid, ra, rb, ts, wide, circle):
    """Whether a wide quadrilateral may be optimal somewhere in the grid, so that it must be
    refined: a corner lies in the grid (at any theta + 2 pi k on the circle) where no value below
    its time (minus DOMINATED) is drawn yet, or the quadrilateral overlaps the grid with a corner
    outside it (its inside is not seen from its corners). Compiled (`_field.c`)."""
    return _field.undominated(V, grid, ra, rb, ts, wide, circle, DOMINATED)


def _optimal_switch_points(points, V, grid, window, circle):
    """The switch points (theta, omega, time-to-go, index) of the field that lie on optimal
    extremals (the drawn value there within a cell's variation of their time), in the window."""
    keep = []
    dV = 2 * max(window.steps)
    for theta, omega, s, index in points:
        for i, j, sh in _cells(grid, window, theta, omega, circle):
            if abs(V[i, j] - s) <= dV * (1 + abs(omega) + 1):
                keep.append((theta + sh, omega, s, index))
    return np.array(keep) if keep else np.empty((0, 4))


def _dispersal(V, P, B, window):
    """Cells next to a neighbour whose optimal extremal goes to another branch, ends with the other
    control (the other half of final costate angles), or whose final costate angle differs by
    more than MIN_JUMP: where two sheets of the field meet with equal values, the dispersal curves
    (boolean array). Where the field is stretched thin (the costate angle changing fast from cell
    to cell) the criterion can flag a cell that is not on one."""
    psi = P.mean(axis=2)
    d = np.zeros(V.shape, dtype=bool)
    for axis in (0, 1):
        a = [slice(None), slice(None)]
        b = [slice(None), slice(None)]
        a[axis], b[axis] = slice(None, -1), slice(1, None)
        a, b = tuple(a), tuple(b)
        change = np.abs(psi[a] - psi[b])
        jump = (B[a] != B[b]) | ((psi[a] < math.pi) != (psi[b] < math.pi)) | (np.minimum(change, 2 * math.pi - change) > MIN_JUMP)
        jump &= np.isfinite(V[a]) & np.isfinite(V[b])
        d[a] |= jump
        d[b] |= jump
    return d


def interior_cells(synthesis):
    """The cells whose 3 x 3 neighbourhood is drawn, has one switch count and no dispersal cell:
    away from the switching and dispersal curves, where a map's cell is checked."""
    N, d, V = synthesis.N, synthesis.dispersal, synthesis.V
    ok = np.isfinite(V) & ~d
    same = np.ones(N.shape, dtype=bool)
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            shifted = np.roll(np.roll(N, di, 0), dj, 1)
            same &= (shifted == N) & np.roll(np.roll(ok, di, 0), dj, 1)
    same[[0, -1], :] = same[:, [0, -1]] = False
    return np.argwhere(same & ok)


def check(synthesis, count=20, seed=0):
    """Re-solve `count` random interior cells of the map by `ocp.solve` (the complete search from
    each state): [(theta, omega, V, N, T, n_switches)]."""
    from ..core.problem import make
    from ..solving import solve

    cells = interior_cells(synthesis)
    rng = np.random.default_rng(seed)
    w = synthesis.window
    rows = []
    for i, j in cells[rng.choice(len(cells), size=min(count, len(cells)), replace=False)]:
        theta, omega = float(w.theta[i]), float(w.omega[j])
        sol = solve(make(synthesis.kind, synthesis.kappa, (theta, omega), None if synthesis.reading == "circle" else 0))
        rows.append((theta, omega, float(synthesis.V[i, j]), int(synthesis.N[i, j]), sol.T, sol.n_switches))
    return rows


def save(synthesis, path):
    """The Synthesis as a compressed numpy file (arrays and the settings), written whole
    (`ocp.core.files`)."""
    from ..core.files import replacing

    w = synthesis.window
    with replacing(path, "wb") as f:
        np.savez_compressed(f, V=synthesis.V, N=synthesis.N, psi=synthesis.psi, branch=synthesis.branch,
                            switch_points=synthesis.switch_points, dispersal=synthesis.dispersal,
                            window=np.array([w.theta_lo, w.theta_hi, w.omega_lo, w.omega_hi, w.n_theta, w.n_omega]),
                            meta=np.array([synthesis.kind, synthesis.reading, repr(synthesis.kappa),
                                           repr(synthesis.horizon), str(synthesis.extremals), str(synthesis.unresolved),
                                           repr(synthesis.time_s)]))
    return path


def summary(synthesis):
    """Plain data: settings, switch counts and their cells, coverage, cost."""
    values, counts = np.unique(synthesis.N, return_counts=True)
    w = synthesis.window
    out = {"kind": synthesis.kind, "reading": synthesis.reading, "kappa": synthesis.kappa,
           "window": {"theta": [w.theta_lo, w.theta_hi], "omega": [w.omega_lo, w.omega_hi],
                      "grid": [w.n_theta, w.n_omega]},
           "horizon": synthesis.horizon, "covered": synthesis.covered,
           "switch_counts": {str(int(v)): int(c) for v, c in zip(values, counts) if v >= 0},
           "max_switches": int(synthesis.N.max()), "extremals": synthesis.extremals,
           "unresolved_strips": synthesis.unresolved, "time_s": synthesis.time_s}
    for n in values:
        if n >= 2:
            cells = np.argwhere(synthesis.N == n)
            out[f"states_with_{int(n)}_switches"] = {"theta": [float(w.theta[cells[:, 0]].min()), float(w.theta[cells[:, 0]].max())],
                                                     "omega": [float(w.omega[cells[:, 1]].min()), float(w.omega[cells[:, 1]].max())]}
    return out
