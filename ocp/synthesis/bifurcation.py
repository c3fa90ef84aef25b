"""The bifurcation values of N_kappa: kappa_n = inf{kappa : N_kappa <= n}.

N_kappa(x) is the switch count of the minimum-time control from x, N_kappa its supremum over the
phase space (the cylinder on the circle, the plane with one pinned target). A state x needs n + 1
switches exactly when an extremal of the field ending at the target (final costate angle psi,
`ocp.synthesis.field`) is optimal just upstream of its (n + 1)-th switch counted backwards from the
target, x_{n+1}(psi), reached after a time-to-go s_{n+1}(psi). The criterion is the gap

    G(psi) = s_{n+1}(psi) - T_other(x_{n+1}(psi)),

T_other the least time from that state over every other extremal (the complete search,
`ocp.indirect.searching`, without the field's own extremal): G < 0 where the field's extremal wins
there, and then states with n + 1 switches exist nearby; G > 0 where another extremal is faster.
The switch must also be crossed (`crossing`): where the arriving arc and the departing arc point
to opposite sides of the switching curve, the arriving arc is not optimal just upstream (an
extremal switching earlier is faster there) whatever G says at the switch itself. So
N_kappa <= n exactly when G >= 0 for every psi where the switching curve is crossed, and kappa_n
is the root of

    m(kappa) = min over crossed psi of G(psi; kappa)

(m > 0 above kappa_n). Near the root the minimum is attained on one competitor, a labelled
extremal (its arc signs and branch), whose time is smooth in the state: G_L is smooth, its minimum
over psi is a smooth function of kappa, and the root is found by Brent's method on that minimum,
each minimum by Brent's method in psi. The mechanism is read off the solution: an interior
minimum is a tie with the competitor, tangent at the switching point (a dispersal curve touching
the (n + 1)-th switching curve); a minimum at the end of the psi range where the switch exists is
an arc collapsing; a switch time growing without bound, a limit at high energy.

Error bars: the whole computation is repeated at the Taylor accuracy CHECK and PRECISE and with
a tenfold tighter psi tolerance; the spread of the results is the error bar.
"""

import math
from dataclasses import dataclass

import numpy as np

from ..core.problem import KINDS, Problem
from ..core.roots import brent
from ..indirect import taylor
from ..indirect.searching import search

#: backward switches are followed up to this time-to-go
S_MAX = 60.0
#: the gap given to angles whose switch is not crossed (a finite penalty keeps Brent's method exact)
NOT_CROSSED = 1e3


@dataclass(frozen=True)
class SwitchPoint:
    """The n-th switch counted backwards from the target on the field's extremal psi (final
    control u_T): the state x, the time-to-go s, and the forward arc signs from x."""

    psi: float
    n: int
    s: float
    x: tuple
    signs: tuple


def switch_point(kind, kappa, psi, n, accuracy=taylor.PRECISE, s_max=S_MAX):
    """The SwitchPoint (n >= 1) of the extremal psi, or None when it switches fewer than n times
    within s_max."""
    u_T = 1.0 if math.sin(psi) > 0 else -1.0
    y0 = np.array([KINDS[kind].target_base, 0.0, math.cos(psi), math.sin(psi)])
    switches, events = np.empty((n + 2, 5)), np.empty((4, 6))
    n_sw, *_ = taylor.extremal(y0, kappa, u_T, s_max, -1.0, accuracy[0], accuracy[1], switches, events,
                               np.empty(0), np.empty((0, 3)))
    if n_sw < n:
        return None
    signs = tuple(int(u_T * (-1) ** (n - 1 - i)) for i in range(n))
    return SwitchPoint(psi, n, float(switches[n - 1, 0]), (float(switches[n - 1, 1]), float(switches[n - 1, 2])), signs)


def others(kind, kappa, reading, point):
    """The extremals from point.x other than the field's own (same final arcs and branch 0, and
    the same time to 1e-8): a list of (T, signs, branch), fastest first (the runner-up's scan never
    cut: the gap needs the fastest other however far)."""
    problem = Problem(kind, kappa, point.x, None if reading == "circle" else 0)
    found = search(problem, horizon=1.3 * point.s, runner_up_budget=math.inf)
    own = lambda a: a.branch == 0 and abs(a.T - point.s) <= 1e-8 * max(1.0, point.s) and \
        tuple(a.signs[-point.n:]) == point.signs
    return [(a.T, tuple(a.signs), a.branch) for a in found.arrivals if not own(a)]


def gap(kind, kappa, reading, psi, n, label=None, accuracy=taylor.PRECISE):
    """(G, competitor label (signs, branch), the SwitchPoint) at psi for n switches (G = s_n -
    T_other; against `label` only when given); None where the n-th switch does not exist or the
    competitor is not found."""
    point = switch_point(kind, kappa, psi, n, accuracy)
    if point is None:
        return None
    rivals = others(kind, kappa, reading, point)
    if label is not None:
        rivals = [r for r in rivals if (r[1], r[2]) == label]
    if not rivals:
        return None
    T, signs, branch = rivals[0]
    return point.s - T, (signs, branch), point


def profile(kind, kappa, reading, n, psis, accuracy=taylor.CHECK):
    """[(psi, G, competitor label, SwitchPoint)] at the angles psis (both halves of the circle of
    final costate angles; the seams 0 and pi are avoided), where the n-th switch exists and its
    switching curve is crossed."""
    rows = []
    for psi in psis:
        try:
            if switch_point(kind, kappa, float(psi), n, accuracy) is None:
                continue
            up, down = crossing(kind, kappa, float(psi), n, accuracy)
            if not up * down > 0:
                continue
            found = gap(kind, kappa, reading, float(psi), n, accuracy=accuracy)
        except ValueError:          # a switch point outside the accepted states (|omega| > 50)
            continue
        if found is not None:
            rows.append((float(psi), *found))
    return rows


def crossing(kind, kappa, psi, n, accuracy=taylor.PRECISE, h=1e-6):
    """(det[t, f(x_n, u_up)], det[t, f(x_n, u_down)]): t = d x_n / d psi the tangent of the n-th
    switching curve (central difference of step h), u_up the control just upstream of the switch,
    u_down just downstream. The field's trajectories cross the switching curve (a regular switch)
    where both have the same sign; where they differ the arriving arc would turn back to the side
    it came from, and the switch is not optimal upstream (another extremal, switching earlier,
    is faster there)."""
    from ..core.model import rhs

    p, q, r = (switch_point(kind, kappa, v, n, accuracy) for v in (psi - h, psi, psi + h))
    if p is None or q is None or r is None:         # the n-th switch appears or disappears here
        return math.nan, math.nan
    t = (np.array(r.x) - np.array(p.x)) / (2 * h)
    up, down = rhs(np.array(q.x), -q.signs[0], kappa), rhs(np.array(q.x), q.signs[0], kappa)
    return float(t[0] * up[1] - t[1] * up[0]), float(t[0] * down[1] - t[1] * down[0])


def tangency(kind, kappa, psi, n, accuracy=taylor.PRECISE, h=1e-6):
    """det[t, f(x_n, u_up)] of `crossing`: zero where the n-th switching curve is tangent to the
    arriving trajectories, where it stops being crossed (a fold of the field)."""
    return crossing(kind, kappa, psi, n, accuracy, h)[0]


def least_gap(kind, kappa, reading, n, psi_lo, psi_hi, accuracy=taylor.PRECISE, xtol=1e-10, samples=24):
    """(m, psi, label): the least gap G over psi in [psi_lo, psi_hi] against every other extremal,
    where the field's trajectories cross the n-th switching curve (`crossing`; elsewhere the
    switch is not optimal upstream), sampled then refined by bounded Brent minimisation around the
    best sample."""
    from scipy.optimize import minimize_scalar

    def g(psi):
        up, down = crossing(kind, kappa, psi, n, accuracy)
        try:
            found = gap(kind, kappa, reading, psi, n, accuracy=accuracy) if up * down > 0 else None
        except ValueError:          # a switch point outside the accepted states (|omega| > 50)
            found = None
        return (NOT_CROSSED, None) if found is None else found[:2]

    grid = np.linspace(psi_lo, psi_hi, samples)
    values = [g(p)[0] for p in grid]
    i = int(np.argmin(values))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, samples - 1)]
    best = minimize_scalar(lambda p: g(p)[0], bounds=(lo, hi), method="bounded", options={"xatol": xtol})
    value, label = g(best.x)
    return float(value), float(best.x), label


def root_in_kappa(kind, reading, n, kappa_lo, kappa_hi, psi_lo, psi_hi, accuracy=taylor.PRECISE, xtol=1e-10,
                  ktol=1e-12, trace=None, samples=24):
    """kappa_n: the root of the least gap m(kappa) over the case's window [psi_lo, psi_hi] of final
    costate angles in [kappa_lo, kappa_hi] (m < 0 at kappa_lo, > 0 at kappa_hi). The window stays
    fixed: followed from one kappa to the next it drifted to angles whose switch lies 50 time units
    upstream, where every gap costs a long search. Returns (kappa, psi, label) at the root."""
    state = {"psi": 0.5 * (psi_lo + psi_hi), "label": None}

    def m(kappa):
        value, psi, label = least_gap(kind, kappa, reading, n, psi_lo, psi_hi, accuracy, xtol, samples)
        if label is not None:                     # the last angle where the switch is crossed
            state.update(psi=psi, label=label)
        if trace:
            trace(kappa, value, psi, label)
        return value

    kappa = brent(m, kappa_lo, kappa_hi, ktol)
    return kappa, state["psi"], state["label"]


def tangency_tie(kind, reading, n, kappa_lo, kappa_hi, psi_lo, psi_hi, label, accuracy=taylor.PRECISE, ktol=1e-13):
    """The mechanism's own equations: psi_b(kappa), where the n-th switching curve is tangent to the
    crossing trajectories (`tangency` = 0, Brent in [psi_lo, psi_hi]), and the tie there with the
    competitor `label`, G_label(psi_b(kappa), kappa) = 0 (Brent in kappa). Returns (kappa, psi_b)."""
    state = {}

    def tie(kappa):
        psi = brent(lambda p: tangency(kind, kappa, p, n, accuracy), psi_lo, psi_hi, 1e-14)
        found = gap(kind, kappa, reading, psi, n, label, accuracy)
        state["psi"] = psi
        return found[0]

    kappa = brent(tie, kappa_lo, kappa_hi, ktol)
    return kappa, state["psi"]


@dataclass(frozen=True)
class Bifurcation:
    """kappa_n = inf{kappa : N_kappa <= n} of a problem kind and reading, with its error bar (the
    spread of the routes, each a value of kappa), where the supremum is attained (the state x on
    the field's extremal psi at its (n + 1)-th switch, time-to-go s), the competitor it ties with,
    and the mechanism in words."""

    kind: str
    reading: str
    n: int
    kappa: float
    error: float
    psi: float
    state: tuple
    time_to_go: float
    competitor: tuple
    mechanism: str
    routes: dict

    def to_dict(self):
        return {"kind": self.kind, "reading": self.reading, "n": self.n, "kappa": self.kappa, "error": self.error,
                "psi": self.psi, "state": list(self.state), "time_to_go": self.time_to_go,
                "competitor": {"arc_signs": list(self.competitor[0]), "branch": self.competitor[1]},
                "mechanism": self.mechanism, "routes": self.routes}


def bifurcation(kind, reading, n, kappa_lo, kappa_hi, psi_lo, psi_hi, trace=None):
    """The Bifurcation kappa_n (n >= 1) bracketed by [kappa_lo, kappa_hi] (states with n + 1
    switches at kappa_lo, none at kappa_hi, their field extremals at final costate angles in
    [psi_lo, psi_hi]): the root of the least gap at two Taylor accuracies and two psi tolerances;
    where the minimiser is a fold of the switching curve (`tangency` changes sign within the psi
    tolerance), also the fold-and-tie equations. The error bar is the spread of the routes plus
    the tolerance of kappa."""
    routes = {}
    k, psi, label = root_in_kappa(kind, reading, n + 1, kappa_lo, kappa_hi, psi_lo, psi_hi, taylor.PRECISE, 1e-10,
                                  1e-13, trace)
    routes["least gap, PRECISE, psi to 1e-10"] = k
    routes["least gap, CHECK, psi to 1e-9"] = root_in_kappa(kind, reading, n + 1, kappa_lo, kappa_hi, psi_lo, psi_hi,
                                                            taylor.CHECK, 1e-9, 1e-13)[0]
    point = switch_point(kind, k, psi, n + 1)
    mechanism = (f"a tie, tangent at the {ordinal(n + 1)} switching point, with the extremal {label[0]} to "
                 f"branch {label[1]}")
    above = least_gap(kind, k + 1e-9, reading, n + 1, psi - 0.5 * (psi_hi - psi_lo), psi + 0.5 * (psi_hi - psi_lo))[0]
    if above >= NOT_CROSSED / 2:
        # the least gap jumps: the region ends where its switching curve stops being crossed, and
        # the root is the edge of the crossed angles, found as finely as they are sampled
        routes["least gap, PRECISE, psi sampled 4x finer"] = root_in_kappa(
            kind, reading, n + 1, kappa_lo, kappa_hi, psi_lo, psi_hi, taylor.PRECISE, 1e-10, 1e-13, samples=96)[0]
        mechanism = (f"the region of {n + 1} switches vanishes where the {ordinal(n + 1)} switching curve stops "
                     f"being crossed by the arriving trajectories (its crossed part shrinks to a point) while it "
                     f"still beats every other extremal; located by sampling the final costate angle")
    w = 1e-4
    if np.sign(tangency(kind, k, psi - w, n + 1)) != np.sign(tangency(kind, k, psi + w, n + 1)):
        dk = 1e-3 * (kappa_hi - kappa_lo)
        fold = tangency_tie(kind, reading, n + 1, k - dk, k + dk, psi - 10 * w, psi + 10 * w, label)
        if abs(fold[1] - psi) < 1e-6:
            routes["fold and tie equations, PRECISE"] = fold[0]
            mechanism = (f"the {ordinal(n + 1)} switching curve folds (becomes tangent to the trajectories that "
                         f"cross it) where it ties with the extremal {label[0]} to branch {label[1]}: the region of "
                         f"{n + 1} switches is born at that point")
    values = list(routes.values())
    error = max(values) - min(values) + 1e-13
    return Bifurcation(kind, reading, n, k, error, psi, point.x, point.s, label, mechanism, routes)


def ordinal(k):
    return {1: "first", 2: "second", 3: "third", 4: "fourth", 5: "fifth", 6: "sixth", 7: "seventh"}.get(k, f"{k}th")


def fold_and_tie(kind, reading, n, kappa_lo, kappa_hi, psi_lo, psi_hi, label, ktol=1e-12):
    """The Bifurcation where the region of n + 1 switches carried by the field's extremals at
    psi in [psi_lo, psi_hi] ends by the fold-and-tie mechanism alone (`tangency_tie` against the
    competitor `label`, at the Taylor accuracies PRECISE and CHECK): the value where that region
    vanishes, a lower bound of kappa_n (kappa_n itself when no other region of n + 1 switches remains,
    `ocp.synthesis.results.evidence`). Error
    bar: the spread of the two accuracies plus ktol."""
    routes = {f"fold and tie equations, {name}, kappa to {ktol:g}":
              tangency_tie(kind, reading, n + 1, kappa_lo, kappa_hi, psi_lo, psi_hi, label, accuracy, ktol)
              for name, accuracy in (("PRECISE", taylor.PRECISE), ("CHECK", taylor.CHECK))}
    (k, psi), values = next(iter(routes.values())), [r[0] for r in routes.values()]
    point = switch_point(kind, k, psi, n + 1)
    mechanism = (f"the {ordinal(n + 1)} switching curve folds where it ties with the extremal {label[0]} to branch "
                 f"{label[1]}: the region of {n + 1} switches of the extremals at psi in [{psi_lo:g}, {psi_hi:g}] ends "
                 f"there")
    return Bifurcation(kind, reading, n, k, max(values) - min(values) + ktol, psi, point.x, point.s, label, mechanism,
                       {name: r[0] for name, r in routes.items()})


def scan(kind, kappa, reading, n, psis, s_max, accuracy=taylor.CHECK):
    """Rows {kappa, psi, s, state, crossed_and_found, G, competitor, time_s}, one an angle psi, of the
    gap at the n-th switch (`profile`'s test; s None where the extremal switches fewer than n times
    within the time-to-go s_max): m(kappa) > 0 at this kappa when every crossed row has G > 0."""
    import time

    for psi in psis:
        start = time.perf_counter()
        point = switch_point(kind, kappa, float(psi), n, accuracy, s_max)
        if point is None:
            yield {"kappa": kappa, "psi": float(psi), "s": None, "state": None, "crossed_and_found": False, "G": None,
                   "competitor": None, "time_s": time.perf_counter() - start}
            continue
        try:
            up, down = crossing(kind, kappa, float(psi), n, accuracy)
            found = gap(kind, kappa, reading, float(psi), n, accuracy=accuracy) if up * down > 0 else None
        except ValueError:          # a switch point outside the accepted states (|omega| > 50)
            found = None
        yield {"kappa": kappa, "psi": float(psi), "s": point.s, "state": list(point.x),
               "crossed_and_found": found is not None, "G": None if found is None else found[0],
               "competitor": None if found is None else [list(found[1][0]), found[1][1]],
               "time_s": time.perf_counter() - start}


def confirm(kind, kappa, reading, psi, n, dt=0.01):
    """The complete search (`ocp.solve`) at the state dt before the n-th switch point of the extremal
    psi, on its arriving arc: {kappa, psi, x0, T, switches, arc_signs}. Where G < 0 and the switch is
    crossed, the optimum there switches n times; where every gap is positive, fewer."""
    from scipy.integrate import solve_ivp

    from ..core.model import rhs
    from ..core.problem import make
    from ..solving import solve

    point = switch_point(kind, kappa, psi, n)
    u = -point.signs[0]
    back = solve_ivp(lambda t, x: -rhs(x, u, kappa), (0.0, dt), np.array(point.x), "DOP853", rtol=1e-12, atol=1e-12)
    x0 = back.y[:, -1]
    s = solve(make(kind, kappa, (float(x0[0]), float(x0[1])), branch=None if reading == "circle" else 0))
    return {"kappa": kappa, "psi": psi, "x0": [float(v) for v in x0], "T": s.T, "switches": s.n_switches,
            "arc_signs": list(s.arc_signs)}
