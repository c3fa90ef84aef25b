"""The switching structure read off a piecewise-constant control.

Interval k is "bang" when |u_k| >= 1 - BANG_TOL, else "interior". Between two bang arcs, a run of
interior intervals is read as the bang-bang control with the same integral of u: one switch when the
arcs have opposite signs (at the time where the integral matches), a pulse of the opposite sign
(two switches) when they have the same sign. A switch inside an interval is thereby located to a
fraction of the grid spacing h; a run of more than one interior interval means the control is not
resolved as bang-bang there (singular arc or chattering), and `bang_bang` is False.
"""

from dataclasses import dataclass

import numpy as np

from ..core import simulate

BANG_TOL = 1e-3


@dataclass(frozen=True)
class Structure:
    """n_switches, first_u (+1/-1), the sign of each arc, switch times (t), switch states
    (theta, omega), the grid spacing h, the longest interior run, and whether every switch was
    resolved inside one interval (`bang_bang`)."""

    n_switches: int
    first_u: int
    arc_signs: tuple
    switch_times: tuple
    switch_states: tuple
    h: float
    longest_interior_run: int
    bang_bang: bool

    def to_dict(self):
        return {
            "n_switches": self.n_switches,
            "first_u": self.first_u,
            "arc_signs": list(self.arc_signs),
            "switch_times": list(self.switch_times),
            "switch_states": [list(s) for s in self.switch_states],
            "grid_spacing": self.h,
            "longest_interior_run": self.longest_interior_run,
            "bang_bang": self.bang_bang,
        }


def pattern(signs):
    """Arc signs as text: (1, -1) -> "+1 -1"."""
    return " ".join("+1" if s > 0 else "-1" for s in signs) or "(no arc)"


def _runs(labels):
    """[(label, start, stop)] of maximal runs of equal labels."""
    runs, start = [], 0
    for k in range(1, len(labels) + 1):
        if k == len(labels) or labels[k] != labels[start]:
            runs.append((labels[start], start, k))
            start = k
    return runs


def read(t, x, u, kappa):
    """The Structure of control u (N values) on grid t (N+1) with node states x (N+1, 2)."""
    t, x, u = np.asarray(t, float), np.asarray(x, float), np.asarray(u, float)
    labels = np.where(u >= 1 - BANG_TOL, 1, np.where(u <= -1 + BANG_TOL, -1, 0))
    runs = _runs(labels.tolist())
    h = float(np.max(np.diff(t)))
    # The piecewise bang-bang reading: a list of (sign, start time) pieces.
    pieces = []
    for i, (label, a, b) in enumerate(runs):
        if label != 0:
            pieces.append((label, t[a]))
            continue
        before = runs[i - 1][0] if i > 0 else None
        after = runs[i + 1][0] if i + 1 < len(runs) else None
        mean = float(np.sum(u[a:b] * np.diff(t[a:b + 1])) / (t[b] - t[a]))
        if before is None and after is None:
            first = int(np.sign(mean) or 1)
            last = -first
        elif before is None:
            first, last = -after, after
        elif after is None:
            first, last = before, -before
        else:
            first, last = before, after
        if first != last:
            # time at sign `first` such that first*d + last*(D - d) = mean*D
            d = (mean - last) / (first - last) * (t[b] - t[a])
            pieces += [(first, t[a]), (last, t[a] + d)]
        else:
            d = (first - mean) / 2 * (t[b] - t[a])        # duration of the opposite pulse
            centre = 0.5 * (t[a] + t[b])
            pieces += [(first, t[a]), (-first, centre - d / 2), (first, centre + d / 2)]
    signs, times = _clean(pieces, t[-1], 1e-9 * h)
    states = tuple(_switch_state(tau, sign, t, x, kappa) for tau, sign in zip(times, signs))
    interior = [b - a for label, a, b in runs if label == 0]
    longest = max(interior, default=0)
    return Structure(len(times), signs[0], signs, times, states, h, longest, longest <= 1)


def _switch_state(tau, sign, t, x, kappa):
    """State at the switch time tau: flow from the last node before tau under the arc's sign."""
    k = int(np.searchsorted(t, tau, side="right")) - 1
    return tuple(float(v) for v in simulate.flow(x[k], sign, tau - t[k], kappa))


def _clean(pieces, T, eps):
    """Signs of the arcs and the switch times, from (sign, start) pieces: arcs shorter than eps
    dropped, neighbours of equal sign merged."""
    ends = [start for _, start in pieces[1:]] + [T]
    kept = [(sign, start) for (sign, start), end in zip(pieces, ends) if end - start > eps]
    merged = kept[:1]
    for sign, start in kept[1:]:
        if sign != merged[-1][0]:
            merged.append((sign, start))
    return tuple(int(s) for s, _ in merged), tuple(float(s) for _, s in merged[1:])
