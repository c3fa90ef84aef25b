"""The complete search of extremals from a start: every Pontryagin extremal that reaches the target
set before a horizon, the least time among them the global minimum.

The extremals from x0 form a one-parameter family. The costate direction at t = 0,
p(0) = (cos phi, sin phi), fixes everything: u = sign(p2) switched at the zeros of p2, and the
scale of p is set by H = 0 (p . f(x0, u0) = 1), which needs p . f(x0, u0) > 0 (normal extremals;
= 0 are the abnormal ones, the end points of the admissible set). Singular arcs are impossible:
p2 = 0 on an interval forces p1 = -p2' = 0 there, so p = 0, which the maximum principle excludes.
The angle phi splits into two half-circles by the first control, u0 = +1 on (0, pi) and u0 = -1
on (pi, 2 pi); at their ends p2(0) = 0 and the first arc has zero length. Each half, cut to its
admissible interval, is scanned.

Along an extremal, the turning points (omega = 0) are labelled (arc, index within the arc).
Inside a half-interval a label is a smooth function of phi: switches are transversal (p2 = 0
gives p1*omega = 1), so a turning point cannot cross a switch, and turning points are created or
destroyed only where the trajectory would reach an equilibrium of its arc's field (never in finite
time) or at the horizon. An extremal reaches the target (theta*, 0) exactly when one of its turning
points has theta = theta*: arrivals are the roots of theta_label(phi) - theta*_k, for every branch
k (the circle) or the pinned one (the plane).

The scan samples phi (SAMPLES per half), then bisects adaptively, best first: an interval split
is examined again in the order of the earliest time an arrival may follow the turning point that
forced the split (`_soonest`: its time, plus the transit from its angles to the nearest allowed
target), so that the earliest arrivals are bracketed early and the acceptance falls early (below;
ordered by the turning point's time alone, a target far behind a fast start was sought last, after
the turning points of the far side: swing-up from (-1.411, 8.03) to branch -2 on the plane at
kappa = 0.2956, 51,527 extremals and 19 s; 3,567 and 1.1 s with the transit and the turn's lower
bound, below). Every extremal is integrated
with its variational equations in phi (`taylor.extremal_variations`): each turning point carries
its angle theta_label, its time t_label and their slopes in phi. An interval [a, b] with midpoint m
is resolved when, for every label, each half [x0, x1] (width h) is, by a bound of what theta_label
can do between its samples: if |theta_label''| <= M on the half, theta_label stays within
M h^2 / 8 of the chord of its end values, and it is monotone if its end slopes s0, s1 have one sign
and |s0 + s1| > M h (|theta_label'| >= (|s0 + s1| - M h) / 2 between). A half is resolved when the
first excludes every allowed target, or the second holds: then each target is crossed once
(bracketed by the sign change of the end values) or not at all. M is CURVATURE times the largest
second derivative, at the half's ends, of the cubic Hermite interpolants of theta_label's values and
slopes on [a, m] and [m, b] (at m, both). The time is bounded alike: a half whose least end time,
less M_t h^2 / 8, is after the acceptance holds no arrival. A turning point that no sample sees
(born and dying between two samples through the acceptance time t_a, as where an arc's switch comes
in from beyond the horizon) is caught by the same bound on omega(t_a, phi), integrated to t_a with
its slope at each sample: the turning points before t_a change only where one crosses t_a (zeros of
omega are transversal inside an arc and never at a switch, p1 omega = 1), a zero of omega(t_a, .),
so where a, m, b see the same turning points, a half on which the bound excludes a zero, or shows
omega(t_a, .) monotone (one crossing, seen by the samples), or bounds e(t_a, .) = omega^2 / 2 -
cos(theta) above 1 (a rotation, omega^2 / 2 > 1 + cos(theta) >= 0: where the family rotates fast,
omega(t_a, .) has the rotation's phase and e, smooth, has not; unless the energy of an arc before t_a
may be at a saddle's level on the half, `_may_pass_saddle`: there e(t_a, .) dips to the saddle's
-cos(theta_s) < 1 on a window narrower than the samples, where the extremals linger by the saddle
at t_a), hides none (where they see different
ones, a turning point crossing the horizon, the rules for those below decide: near an extremal that
reaches a saddle, omega(t_a, .) is too steep for the bound, and that check alone would bisect to
MIN_WIDTH, 4 times the extremals). The same bound settles the later labels on a half: where it
excludes a zero of omega(t_a, .) there (or shows it monotone) and the half's ends see the same
turning points before t_a, every phi of the half sees those, so a label not among them is after t_a,
or absent, on the whole half (that label only: one absent says nothing of the later ones). This resolves, at the spacing the
bound on omega(t_a, .) needs, what the rules for a label seen at some samples only would bisect far
finer: the turning points after an arc that runs into a saddle past t_a, whose switch and turning
points come in from beyond the horizon (swing-up from (0, 50) at kappa = 0.1: 4,520 extremals and
42 isolated to MIN_WIDTH before, 1,000 and none after; 690 with the bound on e, which settles the
halves still rotating at t_a, whose later turning points' times the bound on t_label leaves free
to dip before it). The turning points of one arc are also bounded together, by
its energy (`_energy_excludes`): on arc j (u = u_j) E_j = omega^2 / 2 - cos(theta) - kappa u_j theta
is constant, so its turning points lie where V_j(theta) = -cos(theta) - kappa u_j theta = E_j, and
E_j is a smooth function of phi (of the state at the switch that begins arc j and its variation
there), also where a turning point of arc j runs into a saddle of the arc's field: its angle jumps
there and its time diverges, but E_j passes the saddle's level smoothly. A label missing at some of
a, m, b, or one whose angle the bound above does not resolve, is resolved on [a, b] where the same
bound on E_j excludes V_j(theta*_k) for every allowed target; so is an interval where omega(t_a, .)
may have two zeros, if one arc j runs at t_a through [a, b] (the switches that begin and end it
bounded before and after t_a: `_runs_through`; a turning point crossing t_a unseen is of that arc,
it cannot cross a switch). Near a saddle theta_s the target's
level is about |cos(theta_s)| (theta_s - theta*)^2 / 2 from the saddle's (kappa^2 / 2 for the
upright at small kappa), so an extremal reaching it is isolated to a width of about that over
|dE_j / dphi|, not to MIN_WIDTH. The residual assumption of completeness is that bound: on every
half the scan resolved, |theta_label''|, |t_label''|, |omega(t_a, .)''|, |e(t_a, .)''|, |E_j''|, the switch
times' and (the transit bound, where the samples see the same switches and turning points before)
those of theta and e at the recorded times and the switches stay below CURVATURE times their
Hermite estimates (omega(t_a, .) and e(t_a, .) have a kink
where a switch crosses t_a, their slope jumping by 2 kappa dt_s/dphi, times omega for e: it too), and the time of a label seen by some
samples only stays above its tangents toward the others (`_dips`). By a saddle's passage the bound on
omega(t_a, .) is trusted as it is elsewhere, that on e(t_a, .) is not (`_may_pass_saddle`): guarding
omega's too would cost 3.4 times the extremals on the 156 searches of the fingerprint set, the guard
on e's 1.2 % more. What omega's bound leaves there is measured (benchmarks/search_saddle_audit.py:
on 5,000 random states, 76 of the 80,997 halves it settled by a saddle hid a turning point from the
samples, none an arrival before the search's best). A feature narrower than the half that shows in none of the values
and slopes at a, m, b (a pair of arrivals born at a fold between two samples) could break it; it is
not proven, it is measured (benchmarks/search_residual.py: the search against an exhaustive brute force on random
states and kappa; benchmarks/search_vs_maps.py: against the synthesis maps). One such feature is known:
damping on the plane from (5.4978, 2.25) at kappa = 0.23424, an island 4e-5 wide in phi where the optimal
extremal switches four times between samples that switch once, which bounds on its half alone call
resolved; the split of the whole interval, which its other half forces, samples it again and finds
it (tests/test_search.py). Judging each half alone would halve the cost of some fast starts; it lost this one.
And one the scan missed before `_may_pass_saddle` (map 609 of benchmarks/search_vs_maps-x.jsonl):
damping on the plane from (-pi/2, -1.8) at kappa = 0.35834, reported as 17.8644. Between two samples
6.8e-5 apart in phi, both rotating at t_a = 17.25 (e = 12.4 and 7.0), the second arc's energy crosses
the level of the saddle at theta = -2.775, and next to that crossing, on a window under 1e-4 wide,
an extremal with three switches reaches the target at 15.1777 (tests/test_search.py).
And arrivals the scan missed before `_turns_follow` (benchmarks/search_residual.py --large, 6 of
1,465 states at kappa 10 to 14 from |omega0| 38 to 48, the best found in each): where a turn's angle
sweeps several radians between two samples, the costate after it (p1' = p2 cos(theta), not averaged
out where theta lingers) and so the next switch's time change faster than omega's values and slopes
at t_a show; the bound on omega settles such a half only where every turn before t_a the samples
share moves by at most TURN_PHASE across it (damping on the plane from (-2.7706, -38.075) at kappa
= 11.057: the runner-up 8.7533, two switches, in a window of a half whose samples switch once).
A label present at some of a, m, b only (its turning point crosses the horizon)
before the acceptance horizon also forces a split, unless its time there is late (DIP) and stays
after the acceptance extrapolated along its slope to the samples that miss it (`_dips`). Intervals are not split
below MIN_WIDTH; such an interval that is still unresolved is reported. A bracket whose root is not
found (a sign change that is a jump, not a crossing, between samples whose values and slopes showed
one crossing: the residual assumption failing, and caught) is examined again and split, where the
acceptance without it is the one reached (it lowered nothing); else, or at MIN_WIDTH, it is reported
too. The labels are examined in time order
along the extremal: once one is after the acceptance on a whole half, so is every later one, and
so is every label of an arc that begins after a switch bounded after it there. The acceptance of a
half may be earlier than the scan's (`_arrivals_by`): an arrival at T (a turning point on a target,
F = sqrt(2 (e + 1)) = F* there) is at least `Problem.transit` away in time from every state of its
extremal (|dF/dt| <= kappa, |omega| <= F: the time to change F, and to cover the distance to the
nearest target; where omega's sign is known, a state moving away from an arrival after it, or toward
one before it, turns first: Problem.lower_bound's argument from any state), so none lies within
that of a state bounded on the half (at t_a and the other times the samples recorded, and at the
switches they share, where they see the same switches and turning points before it: omega's sign
is one along a switch, never 0 there, p1 omega = 1); descending from t_a, each window that reaches the acceptance lowers it (swing-up
from (-1.41, 8.03) to branch -2 on the plane at kappa = 0.296, whose extremals are near the bottom
65 pi away at t_a = 56: stopped at 38 s with 192,026 extremals before, 46,060 to the optimum after;
damping from (2.5, -0.3) at kappa = 0.1: 9,092 extremals before, 1,648 after), and a half whose
acceptance falls below the least time from the start (Problem.lower_bound: the transit from x0,
and back from its first turning point where the target is behind that)
holds no arrival (swing-up to branch 158 on the plane at kappa = 0.05, 996 rad away, whose extremals
mix near the bottom and the top for a long time: the scan to t_a = 297 stopped at 60 s with 20,727
extremals before, complete with 4,570 after). It is worked out
where a label would split an interval, while it pays (`_Payoff`). The
acceptance itself falls as arrivals are bracketed, to the runner-up's latest time (or 1 + margin
times the best's: `_Acceptance`), so that a fast start, whose turning points cross hundreds of
targets within 20 % of the best time, solves two of them, not all. When the acceptance falls below
RESCAN times the scan's own, the scan goes on as if to the horizon of the acceptance reached:
extremals sampled after are integrated to that horizon, the labels compared and omega checked as
for a scan to it (omega checked at the new acceptance, or at a later time the three samples recorded:
the turning points before that time are constant where it has no zero; an extremal sampled before,
which passed the new acceptance without a record, is integrated to it again from t = 0 only where
the three share no such time). Each bracketed arrival is
solved by safeguarded Newton in phi on theta_label - theta* (its slope from the variational
equations; bisection where a step would leave the bracket), with the SCAN integration from the root
of the cubic Hermite interpolant at the bracket's ends, then from that root with CHECK, and again
with PRECISE and PRECISE_ALT (another order and step, so another rounding), each iterated to
4 eps |phi| at its own accuracy: SAFETY times the largest difference, plus the rounding floor, is
its error estimate.

How the family is read (`search`): a start at the target's edge is solved in closed form
(`ocp.indirect.near`). A start at rest high up with the target below (damping from near the
upright) is scanned backwards in time (`_Backward`: from the target to the start, the same
extremals reversed), because forwards from near the saddle every passage by it splits the family,
and the scan resolves an exponentially growing fan of singular extremals (5e6 extremals for the
damping from (pi, 0) at kappa = 0.05, 2e3 backwards). A start symmetric under theta -> 2c - theta
(at rest on a multiple of pi, the circle) is scanned over one half-circle, the other mirrored. A
moving start near the upright is still scanned forwards, and may be slow: after a passage near the
saddle, the later arcs' energies and turning points change by 1e3 to 1e5 per radian of phi, sweeping
many targets' levels, which the scan resolves (damping from (2.5, -0.3) at kappa = 0.1: 1,503
extremals; 9,236 before the transit bound, 33,040 before the energy bound too, which isolates the
extremals reaching a saddle coarser; at kappa = 0.05, 7,711 extremals, and over 85,000 before the
transit bound); so does a fast start braking at small kappa to rest, whose braking ends near the
separatrix (damping from (0, 25) at kappa = 0.25: 5.2e3 extremals); so does a target many turns
away on the plane (swing-up to branch 20 at kappa = 0.5: 1.1e3 extremals to the optimum, 1.9e3
more to a runner-up 15 % slower: the scan for the runner-up integrates at most RUNNER_UP_BUDGET
times the extremals before it, or RUNNER_UP_FLOOR, and past that the optimum is reported without one). A fast start costs in the length of its
extremals more than in their number, where kappa is small: swing-up from (0, 50), 369 extremals at
kappa = 1 (T = 49), 733 of length 500 to 800 at kappa = 0.1 (T = 489), 773 at kappa = 0.05
(T = 976: the family brakes to the upright together, its first turning points within 1 % of T, and
each target their angle sweeps is a tooth of their time, ended by an extremal reaching the saddle). `time_limit` ends a scan with the best arrival so far (status "stopped", not proven
optimal).
"""

import bisect
import heapq
import itertools
import math
import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..core.problem import Problem
from ..core.roots import brent
from . import near, taylor

EPS = 2.220446049250313e-16
#: phi samples per admissible half-circle before adaptive bisection
SAMPLES = 16
#: the scan starts this far inside the ends of an admissible interval: there p2(0) = 0 (the first
#: arc has zero length; from rest a turning point is born at t = 0) or p . f(x0, u0) = 0 (abnormal
#: extremals, whose switches may meet a turning point). The ends themselves are checked apart.
END_OFFSET = 1e-9
#: an end extremal whose turning point comes this close to a target is reported, not scanned
END_NEAR = 1e-6
#: finest phi spacing of the bisection
MIN_WIDTH = 1e-10
#: the bound of a turning point's |d^2 theta / dphi^2| (and of |d^2 / dphi^2| of its time, of omega at
#: the acceptance, of an arc's energy, of a switch's time) on an interval: this many times the largest
#: of the cubic Hermite interpolants' of its values and slopes (the residual assumption of the scan's
#: completeness: the module's docstring)
CURVATURE = 2.0
#: safeguarded Newton iterations of a root (one extremal each) before it is given up
NEWTON_ITERATIONS = 40
#: ... which ends where a step no longer halves the previous one, both below this relative size
NEWTON_FLOOR = 1e-10
#: arrivals are accepted before horizon * (1 - HORIZON_BAND): the turning points between that and
#: the horizon are seen, so that one whose time dips before it between two samples is resolved
HORIZON_BAND = 0.2
#: the error estimate is this many times the spread of the solutions at the other accuracies
SAFETY = 3.0
#: arrivals within this relative time of the best, and the next one, are solved to PRECISE accuracy
TIE_WINDOW = 1e-6
#: a turning point missing at a sample is looked for up to this many horizons
EXTEND = 1.5
#: a turning point seen at some samples only is resolved when its time there is past the acceptance
#: by this fraction of the horizon band (it may dip before the acceptance between samples) and,
#: extrapolated along its slope to those that do not see it, still after the acceptance (`_dips`)
DIP = 0.5
#: a turning point that goes to infinite time this far from every target cannot hide an arrival
FAR = 1e-2
#: a turning point's angle changing by more than this over the finest spacing is discontinuous there
JUMP = 1.0
#: a half is settled by omega at the acceptance only where every turning point before it that its
#: samples share moves by at most this angle across it (`_turns_follow`): the costate after a turn
#: carries cos(theta) there
TURN_PHASE = math.pi / 2
#: a scan whose acceptance falls below this fraction of its own goes on with that acceptance's
#: horizon (new extremals integrated to it, omega checked at the acceptance): a check at a time far
#: past the acceptance sees turning points that cannot be arrivals (damping from (0, 25) at kappa =
#: 0.25, before the transit bound: 23,890 extremals at 0.9, 10,717 at 0.97, 10,483 with
#: `_accepting`; an extremal sampled before the fall may be integrated again, to the new acceptance,
#: where its neighbours were sampled after: 0.7 % more on the standard and random states of the
#: fingerprint set)
RESCAN = 0.97
#: the scan extends to the best arrival time times (1 + MARGIN), to report the runner-up
MARGIN = 0.2
#: ... integrating at most this many times the extremals of the scans before it (the optimum's), or
#: RUNNER_UP_FLOOR if more; past that, the search reports the optimum without a runner-up (swing-up
#: to branch 20 at kappa = 0.5: 1.1e3 extremals to the optimum, 1.9e3 more to a runner-up 15 %
#: slower; the standard swing-up at kappa = 0.05: 60, then 94 more)
RUNNER_UP_BUDGET = 1.0
RUNNER_UP_FLOOR = 2000
#: the horizon grows by this factor while no arrival is found, up to the larger of MAX_HORIZON and
#: REACH times Problem.time_estimate (|omega0| / kappa of braking alone: 1000 from |omega0| = 50 at
#: kappa = 0.05)
GROWTH = 1.5
MAX_HORIZON = 400.0
REACH = 3.0
#: on the circle (where Problem.time_estimate is calibrated: within 10 % of T from the standard
#: starts, within 8 % from (0, 50) at kappa = 1, where braking dominates) the first horizon is this
#: times the estimate, if above GROWTH times the lower bound: the runner-up's reach
#: (1 + MARGIN) / (1 - HORIZON_BAND) with 10 % to spare, one scan (a horizon too long costs little
#: once the acceptance falls: RESCAN)
HEADROOM = 1.1 * (1 + MARGIN) / (1 - HORIZON_BAND)
#: ... from rest for kappa from this up (below, the scans grown by GROWTH cost less: swing-up at
#: kappa = 0.05 from rest, 412 extremals against 745), from a moving start at every kappa (damping
#: from (0, 50) at kappa = 1: 2095 against 3339); on the plane the estimate is not calibrated
#: (1.2 d / kappa for a target d rad away) and the horizon grows from the lower bound
HEADROOM_KAPPA = 0.5
#: the transit bound (`_arrivals_by`) is worked out for an interval a label would split on the first
#: TRANSIT_TRIALS such intervals of a search, then where it has resolved at least one in TRANSIT_PAYOFF
#: of those it was tried on, and on every TRANSIT_PROBE-th (`_Payoff`: the standard swing-up at
#: kappa = 0.75 asks 21 times and it resolves none: tried on all, 23 % of the search's time, on 5
#: of them, 6 %; on the slow cases it resolves one in 3 to 6)
TRANSIT_TRIALS = 4
TRANSIT_PAYOFF = 8
TRANSIT_PROBE = 16
#: the unresolved and singular intervals kept in a Coverage (all are counted)
LISTED = 50
#: seconds between two progress reports
PROGRESS_EVERY = 1.0


@dataclass(frozen=True)
class Extremal:
    """An extremal that reaches the target (theta_k, 0) at time T: costate angle `phi` at t = 0
    (p(0) = (cos phi, sin phi) / (p . f(x0, u0)) so that H = 0), arc `signs`, `switch_times`,
    `switch_states` (theta, omega), and error estimates of T and of the switch times: `solved` is
    "precise" (PRECISE integration, the error from CHECK and PRECISE_ALT), "check" (CHECK, the error its
    change from SCAN), "exact" (a start on the target: T = 0, no arc) or "near" (the closed form of
    `ocp.indirect.near` at the target's edge, with its own error estimate). T_error adds the rounding
    accumulated over the Taylor steps (eps max(1, T) per step), and at least the effect of rounding
    the target state, eps (|theta*| max(|p1(T)|, 2/(kappa T)) + (kappa + 1)
    |p2(T)|) (dT = p(T) . dx*, and near the target T ~ 2 sqrt(d/kappa), dT/dd = 2/(kappa T)),
    which dominates for a transfer in a tiny time."""

    branch: int
    phi: float
    T: float
    signs: tuple
    switch_times: tuple
    switch_states: tuple
    p0: tuple
    T_error: float
    switch_time_error: float
    solved: str

    @property
    def n_switches(self):
        return max(len(self.signs) - 1, 0)

    def to_dict(self):
        return {"branch": self.branch, "T": self.T, "T_error": self.T_error, "arc_signs": list(self.signs),
                "switch_times": list(self.switch_times), "switch_time_error": self.switch_time_error,
                "switch_states": [list(x) for x in self.switch_states], "costate_angle": self.phi,
                "p0": list(self.p0), "solved": self.solved}

    @property
    def durations(self):
        return tuple(np.diff((0.0, *self.switch_times, self.T)))


@dataclass(frozen=True)
class Coverage:
    """What a scan examined (`basis` "scan"; "near target": the closed form of `ocp.indirect.near`,
    every extremal before `horizon` compared): the acceptance `horizon`, the admissible phi
    `intervals` (lo, hi, u0) scanned, the number of extremals integrated (from t = 0, by this scan and the
    search's earlier ones: a sample extended from where it ended counts once), the finest phi spacing
    reached, the intervals left unresolved at MIN_WIDTH or bracketed without a root (phi_lo, phi_hi,
    the nearest approach of a turning point to a target there, -1 if unknown), and the `singular` intervals: isolated to
    MIN_WIDTH around an extremal that reaches a saddle of its arc's field, whose turning point there
    stays at least FAR from every target (phi_lo, phi_hi, its distance). The lists keep the first
    LISTED; `n_unresolved`, `n_singular` count them all. `stopped`: the time limit ended the scan
    before it was complete. `reading`: how the family was scanned ("forwards"; "backwards": the
    problem reversed in time; "+ mirror": one half-circle, the other by the symmetry
    theta -> 2 theta0 - theta)."""

    horizon: float
    intervals: tuple
    extremals: int
    finest_spacing: float
    unresolved: tuple
    singular: tuple
    time_s: float
    basis: str = "scan"
    n_unresolved: int = 0
    n_singular: int = 0
    stopped: bool = False
    reading: str = "forwards"

    @property
    def complete(self):
        return not self.n_unresolved and not self.unresolved and not self.stopped

    def to_dict(self):
        return {"complete": self.complete, "horizon": self.horizon, "intervals": [list(i) for i in self.intervals],
                "extremals": self.extremals, "finest_spacing": self.finest_spacing,
                "unresolved": [list(u) for u in self.unresolved], "singular": [list(s) for s in self.singular],
                "n_unresolved": self.n_unresolved, "n_singular": self.n_singular, "stopped": self.stopped,
                "reading": self.reading, "description": self.describe(), "time_s": self.time_s, "basis": self.basis}

    def describe(self):
        """The scan in words: what a missed extremal would have to look like."""
        if self.basis == "near target":
            return (f"closed form at the target's edge: every extremal before t = {self.horizon:.3g} has at most one "
                    f"switch (zeros of p2 are >= pi apart) and stays within {near.NEAR_SCALE:g} rad of the target, "
                    f"where the field is kappa u -+ x to O(x^3); both orders of its arcs solved, other branches "
                    f"beyond reach")
        text = (f"complete scan of the costate angle ({self.reading}): {self.extremals} extremals over "
                f"{len(self.intervals)} admissible interval{'s' if len(self.intervals) != 1 else ''}, "
                f"finest spacing {self.finest_spacing:.1e} rad, every arrival before t = {self.horizon:.4g} "
                f"(assumed: between two samples, the second derivatives in phi of a turning point's angle and time, "
                f"of omega and omega^2 / 2 - cos(theta) at t = {self.horizon:.4g}, of an arc's energy, of a "
                f"switch's time and of the angle and e at the switches and recorded times the samples share "
                f"stay below {CURVATURE:g} x "
                f"their cubic Hermite estimates from the samples' values and slopes, and the time of a turning point "
                f"seen by some samples only stays above its tangents toward the others)")
        if self.stopped:
            text = "stopped by the time limit: " + text.replace("complete scan", "partial scan", 1).replace(
                "every arrival", "arrivals searched")
        if self.n_singular:
            text += (f"; {self.n_singular} extremal(s) reaching a saddle of their arc's field, where a turning "
                     f"point goes to infinite time, isolated to {MIN_WIDTH:.0e} rad (that turning point stays "
                     f">= {min(s[2] for s in self.singular):.2g} rad from every target)")
        if self.n_unresolved:
            worst = min(u[2] for u in self.unresolved)
            text += (f"; {self.n_unresolved} interval(s) of width {MIN_WIDTH:.0e} left unresolved "
                     f"(nearest approach to a target {worst:.1e} rad)")
        return text


@dataclass(frozen=True)
class Progress:
    """Where a search is, for a progress report: seconds `elapsed`, the `horizon` of the scan, the
    first control `u0` of the half-circle being scanned and the costate angle `phi` reached, the
    extremals integrated so far and the arrivals bracketed in this scan, the best time found before."""

    elapsed: float
    horizon: float
    u0: int
    phi: float
    extremals: int
    arrivals: int
    best: float

    def __str__(self):
        best = "none yet" if math.isnan(self.best) else f"{self.best:.6g}"
        return (f"search {self.elapsed:.0f} s: scanning arrivals before t = {self.horizon * (1 - HORIZON_BAND):.4g}, "
                f"half u0 = {self.u0:+d} at phi = {self.phi:.4f}, {self.extremals} extremals, {self.arrivals} "
                f"arrival(s) bracketed, best T so far {best}")


class _Clock:
    """The time limit (seconds, None: none), the `budget` of extremals (the runner-up's scan's) and the
    progress reports (every PROGRESS_EVERY s) of a search; `stopped`: why it ended the search, "the
    time limit" or "the budget", or None."""

    def __init__(self, time_limit, progress):
        self.begun = time.perf_counter()
        self.limit, self.progress, self.budget = time_limit, progress, math.inf
        self.due, self.stopped, self.best = 0.0, None, math.nan

    def tick(self, horizon, u0, phi, extremals, arrivals):
        """Whether the time limit has passed or the budget is spent; reports the progress when one is due."""
        elapsed = time.perf_counter() - self.begun
        if self.progress is not None and elapsed >= self.due:
            self.due = elapsed + PROGRESS_EVERY
            self.progress(Progress(elapsed, horizon, u0, phi, extremals, arrivals, self.best))
        if self.stopped is None:
            if self.limit is not None and elapsed > self.limit:
                self.stopped = "the time limit"
            elif extremals > self.budget:
                self.stopped = "the budget"
        return self.stopped is not None


@dataclass(frozen=True)
class Search:
    """The arrivals of a complete search, fastest first, its Coverage, and its `status`: a key of
    STATUS_MESSAGES."""

    arrivals: tuple
    coverage: Coverage
    notes: tuple = field(default_factory=tuple)

    @property
    def best(self):
        return self.arrivals[0] if self.arrivals else None

    @property
    def status(self):
        if self.coverage.complete:
            return "optimal" if self.arrivals else "none"
        if self.coverage.stopped:
            return "stopped" if self.arrivals else "stopped, none"
        return "best found" if self.arrivals else "unresolved, none"

    @property
    def message(self):
        return STATUS_MESSAGES[self.status]


STATUS_MESSAGES = {
    "optimal": "the least time among all extremals reaching the target before the horizon: the global optimum",
    "best found": "the least time among the extremals found; intervals left unresolved, optimality not proved",
    "stopped": "the time limit ended the scan: the best arrival found so far, not proven optimal",
    "stopped, none": "the time limit ended the scan before any arrival was found",
    "none": "no extremal reaches the target before the horizon",
    "unresolved, none": "no arrival found; intervals left unresolved, so that none reaches the target before the "
                        "horizon is not proved",
}


class _Sample:
    """One extremal of the scan, integrated for `duration`: its turning points by label (arc,
    index in arc) -> (t, theta) in `events` (in time order) and their derivatives in phi -> (dt/dphi,
    dtheta/dphi) in `slopes`, its angular velocity and that's derivative in phi at the end of each
    integration and at its acceptance time, t -> (omega, domega/dphi, e, de/dphi, theta, dtheta/dphi) in
    `ends` (e = omega^2 / 2 - cos(theta), the pendulum's energy without the torque's work), each arc's energy
    and its derivative in phi, arc -> (E, dE/dphi) in `energies` (`_energy`), the switches' times and
    their derivatives in phi in `switch_times`, `switch_slopes`, the state there, (theta, dtheta/dphi,
    e, de/dphi) in `switch_states` (derivatives along the switch, t_s(phi)), omega's sign there in
    `switch_signs` (never 0: p1 omega = 1 at a switch), where the integration ended (to extend it
    from there), and the sets `seen` returned, by time, in `labels_before`."""

    __slots__ = ("phi", "u0", "duration", "events", "slopes", "ends", "end", "energies", "switch_times",
                 "switch_slopes", "switch_states", "switch_signs", "labels_before")

    def seen(self, horizon):
        """The labels of the turning points before `horizon`, a set (kept once integrated past it: fixed)."""
        if self.duration <= horizon:
            return set(self.events)
        labels = self.labels_before.get(horizon)
        if labels is None:
            labels = self.labels_before[horizon] = {label for label, (t, _) in self.events.items() if t <= horizon}
        return labels

    def arc(self, t):
        """The arc running at elapsed time t (the switches before it)."""
        return bisect.bisect_left(self.switch_times, t)

    def omega(self, family, t):
        """(omega, domega/dphi, e, de/dphi, theta, dtheta/dphi) at elapsed time t (`_motion`): recorded, or integrated on to t, or (t
        passed without a record, the scan's acceptance lowered below an earlier one) integrated again
        from 0."""
        if t not in self.ends:
            if self.duration < t:
                self.integrate(family, t)
            else:
                _, _, _, _, (y, dy, _), _ = family.run(self.phi, self.u0, t, taylor.SCAN)
                self.ends[t] = _motion(y, dy)
        return self.ends[t]

    def __init__(self, family, phi, u0, duration):
        self.phi, self.u0, self.events, self.slopes, self.ends, self.labels_before = phi, u0, {}, {}, {}, {}
        self.duration, self.end = 0.0, None
        theta0, omega0 = family.x0
        self.energies = {0: (_energy(theta0, omega0, _torque(family.kappa, u0, 0)), 0.0)}
        self.switch_times, self.switch_slopes, self.switch_states, self.switch_signs = [], [], [], []
        self.integrate(family, duration)

    def integrate(self, family, duration):
        """Integrated on to `duration`, from where the last integration ended, in one integration
        that also records `ends` at the acceptance time duration * (1 - HORIZON_BAND) of a scan to
        that horizon (the step containing it evaluated there)."""
        accept = duration * (1 - HORIZON_BAND)
        mark = accept - self.duration if self.duration < accept else None
        n_sw, switches, _, events, end, marked = family.run(self.phi, self.u0, duration - self.duration,
                                                            taylor.SCAN, None if self.end is None else self.end[:3], mark)
        arcs, index = (0, 0) if self.end is None else self.end[3:]
        for j, (t, theta, omega, _, _, dt, dtheta, domega) in enumerate(switches.tolist(), arcs + 1):
            self.switch_times.append(t + self.duration)
            self.switch_slopes.append(dt)
            torque = _torque(family.kappa, self.u0, j)
            energy = self.energies[j] = (_energy(theta, omega, torque),
                                         omega * domega + (math.sin(theta) - torque) * dtheta)
            # e = E_j + torque theta; along the switch theta moves by dtheta (at the fixed time just after
            # it) + omega dt_s
            dtheta_s = dtheta + omega * dt
            self.switch_states.append((theta, dtheta_s, energy[0] + torque * theta, energy[1] + torque * dtheta_s))
            self.switch_signs.append(math.copysign(1.0, omega))
        last = 0
        for t, theta, arc, i, _, _, dtheta, dt in events.tolist():
            label = arcs + int(arc), int(i) + (index if arc == 0 else 0)
            self.events[label] = (t + self.duration, theta)
            self.slopes[label] = (dt, dtheta)
            last = last + 1 if arc == n_sw else last
        self.end = (*end, arcs + n_sw, last + (index if n_sw == 0 else 0))
        if marked is not None:
            self.ends[accept] = _motion(*marked)
        self.ends[duration] = _motion(end[0], end[1])
        self.duration = duration


def _motion(y, dy):
    """(omega, domega/dphi, e, de/dphi, theta, dtheta/dphi) of the state y and its variation dy:
    e = omega^2 / 2 - cos(theta) > 1 only where omega != 0."""
    (theta, omega, _, _), (dtheta, domega, _, _) = y.tolist(), dy.tolist()
    return omega, domega, _energy(theta, omega, 0.0), omega * domega + math.sin(theta) * dtheta, theta, dtheta


class _Payoff:
    """Whether a costly rule is worth working out where it is asked for: on the first TRANSIT_TRIALS
    asks, where it has decided at least one in TRANSIT_PAYOFF of its tries, and on every
    TRANSIT_PROBE-th ask (it may come to pay later)."""

    def __init__(self):
        self.asked = self.tried = self.decided = 0

    def wanted(self):
        self.asked += 1
        return (self.asked <= TRANSIT_TRIALS or self.decided * TRANSIT_PAYOFF >= self.tried
                or self.asked % TRANSIT_PROBE == 0)

    def record(self, decided):
        self.tried += 1
        self.decided += decided


class _Family:
    """The extremals from x0 for bound kappa, integrated on demand with their variational equations
    in phi (`taylor.extremal_variations`); `transit`: the _Payoff of the transit bound in its scans."""

    def __init__(self, x0, kappa):
        self.x0 = (float(x0[0]), float(x0[1]))
        self.kappa = float(kappa)
        self.count = 0
        self.transit = _Payoff()
        self._switches = np.empty((64, 8))
        self._events = np.empty((256, 8))
        self._samples = {}

    def run(self, phi, u0, duration, accuracy, start=None, mark=None):
        """(switch count, switches, event count, events, (final y, final dy/dphi, final u), (y, dy)
        at the elapsed time `mark` or None) of the extremal with costate angle phi, or of its
        continuation from `start` (a previous run's final (y, dy, u)); the rows of
        `taylor.extremal_variations`, views of the family's buffers that the next run overwrites
        (copy what is kept)."""
        tol, order = accuracy
        if start is None:
            sin, cos = math.sin(phi), math.cos(phi)
            y0, dy0, u_start = (*self.x0, cos, 0.0 if abs(sin) < 1e-15 else sin), (0.0, 0.0, -sin, cos), float(u0)
        else:
            y0, dy0, u_start = start
        while True:
            n_sw, n_ev, y, dy, u, steps, marked = taylor.extremal_variations(
                y0, dy0, self.kappa, u_start, duration, 1.0, tol, order, self._switches, self._events, mark)
            if n_sw <= len(self._switches) and n_ev <= len(self._events):
                break
            self._switches = np.empty((2 * max(n_sw, len(self._switches)), 8))
            self._events = np.empty((2 * max(n_ev, len(self._events)), 8))
        self.count += start is None
        self.steps_per_time = steps / duration
        return n_sw, self._switches[:n_sw], n_ev, self._events[:n_ev], (y, dy, u), marked

    def sample(self, phi, u0, duration):
        """The _Sample of phi integrated at least for `duration`: the one of an earlier scan (the
        same grid and midpoints at every horizon), extended if shorter."""
        sample = self._samples.get((phi, u0))
        if sample is None:
            sample = self._samples[phi, u0] = _Sample(self, phi, u0, duration)
        elif sample.duration < duration:
            sample.integrate(self, duration)
        return sample


def admissible_intervals(x0, kappa):
    """[(lo, hi, u0)]: the costate angles of normal extremals, p . f(x0, u0) > 0 with
    u0 = sign(sin phi), for u0 = +1 on (0, pi) and u0 = -1 on (pi, 2 pi)."""
    theta0, omega0 = x0
    out = []
    for u0, start in ((1, 0.0), (-1, math.pi)):
        # p . f = omega0 cos(phi) + (kappa*u0 - sin(theta0)) sin(phi) = R cos(phi - alpha) > 0
        if omega0 == 0.0 and kappa * u0 == math.sin(theta0):
            continue                # at rest on an equilibrium of u0: p . f = 0 for every phi, no normal extremal
        alpha = math.atan2(kappa * u0 - math.sin(theta0), omega0)
        s = (alpha - math.pi / 2 - start) % (2 * math.pi)
        lo, hi = (start + s, start + math.pi) if s < math.pi else (start, start + s - math.pi)
        if hi - lo > 1e-12:
            out.append((lo, hi, u0))
    return out


def _targets(problem, lo, hi):
    """The branches k whose target angle lies in [lo, hi] (the pinned one only, on the plane)."""
    base = problem.base
    ks = range(math.ceil((lo - base) / (2 * math.pi)), math.floor((hi - base) / (2 * math.pi)) + 1)
    return ks if problem.branch is None else [k for k in (problem.branch,) if k in ks]


def _torque(kappa, u0, arc):
    """kappa u_j on arc j of an extremal whose first control is u0: u_j = u0 (-1)^j."""
    return kappa * u0 * (-1) ** arc


def _energy(theta, omega, torque):
    """omega^2 / 2 - cos(theta) - torque theta: constant on an arc of that torque (kappa u)."""
    return 0.5 * omega * omega - math.cos(theta) - torque * theta


def _runs_through(a, m, b, arc, t, h):
    """Whether arc `arc` runs at elapsed time t on all of [a.phi, b.phi]: the switches that begin and
    end it recorded at a, m and b, and bounded (values and slopes, `_reaches`) before t and after t
    on both halves (a switch crossing t between the samples would bring another arc in)."""
    for switch, begins in ((arc - 1, True), (arc, False)):
        if switch < 0:
            continue                        # arc 0 begins at t = 0
        if not all(len(s.switch_times) > switch for s in (a, m, b)):
            return False
        (ta, tm, tb), (da, dm, db) = ([s.switch_times[switch] for s in (a, m, b)],
                                      [s.switch_slopes[switch] for s in (a, m, b)])
        ra, rb = _reaches(ta, tm, tb, da, dm, db, h)
        if begins and not (max(ta, tm) + ra < t and max(tm, tb) + rb < t):
            return False
        if not begins and not (min(ta, tm) - ra > t and min(tm, tb) - rb > t):
            return False
    return True


def _turns_follow(a, m, b, end, h):
    """For each half of [a.phi, b.phi], whether every turning point before `end` that a, m and b see
    moves by at most TURN_PHASE there: its angle's chord plus h times its steepest slope. On an arc
    the costate integrates p1' = p2 cos(theta), which a fast rotation averages out and a turn, where
    theta lingers, does not: where the turn's angle sweeps cos(theta) through a sign change between
    two samples, the costate after it, and the time of the next switch, may leave them and come back
    (a switch coming in before `end` and the turning points after it changing) unseen by omega's
    values and slopes at `end` (damping on the plane from (-2.7706, -38.075) at kappa = 11.057: turns
    at theta = -68 to -77 across a half 0.06 wide, and the arrivals of a window inside it missed;
    damping on the plane from (2.624, -29.54) at kappa = 0.6187: without this rule the search reported
    115.4599 as optimal, with it 114.9484, re-simulated by scipy's DOP853 to 2e-9 of the target)."""
    follow = [True, True]
    for label, (t, _) in a.events.items():
        if t >= end or label not in m.events or label not in b.events:
            continue
        angles = [s.events[label][1] for s in (a, m, b)]
        slopes = [abs(s.slopes[label][1]) for s in (a, m, b)]
        for half in (0, 1):
            sweep = abs(angles[half + 1] - angles[half]) + h * max(slopes[half], slopes[half + 1])
            follow[half] = follow[half] and sweep <= TURN_PHASE
    return follow


def _saddle_level(torque, k):
    """The level of saddle k of an arc's field (torque tau = kappa u_j, |tau| < 1): the maximum of
    V(theta) = -cos(theta) - tau theta at theta_k = pi - asin(tau) + 2 pi k (sin(theta_k) = tau,
    cos(theta_k) < 0), V(theta_k) = sqrt(1 - tau^2) - tau (pi - asin(tau) + 2 pi k)."""
    return math.sqrt(1 - torque * torque) - torque * (math.pi - math.asin(torque) + 2 * math.pi * k)


def _may_pass_saddle(kappa, u0, a, m, b, last_arc, h):
    """For each half of [a.phi, b.phi], whether the energy E_j of an arc j <= last_arc may lie at the
    level of a saddle of its field there (`_saddle_level`; |kappa u_j| >= 1: no equilibrium). An
    extremal whose arc j reaches a saddle stays there; its neighbours in phi leave it one way or the
    other after a time growing as log(1 / |phi - phi_s|), so their states at a later fixed time change
    across a window in phi narrower than any sample spacing (omega to 0 and back, e down to the
    saddle's -cos(theta_k) < 1), which the values and slopes at a, m, b need not show. E_j passes the
    level smoothly, bounded as theta_label is (`_reaches`); an arc some sample lacks may be at any."""
    may = [False, False]
    for arc in range(last_arc + 1):
        torque = _torque(kappa, u0, arc)
        if abs(torque) >= 1:
            continue
        values = [s.energies.get(arc) for s in (a, m, b)]
        if None in values:
            return True, True
        (ea, dea), (em, dem), (eb, deb) = values
        reach = _reaches(ea, em, eb, dea, dem, deb, h)
        first, step = _saddle_level(torque, 0), 2 * math.pi * torque      # level k: first - k step
        for half, (e0, e1) in enumerate(((ea, em), (em, eb))):
            lo, hi = min(e0, e1) - reach[half], max(e0, e1) + reach[half]
            ks = sorted(((first - lo) / step, (first - hi) / step))         # the k whose level is in [lo, hi]
            may[half] = may[half] or not math.isfinite(ks[0] + ks[1]) or math.floor(ks[1]) >= ks[0]
    return may[0], may[1]


def _energy_excludes(problem, a, m, b, arc, h):
    """Whether no turning point of arc `arc` lies on an allowed target anywhere in [a.phi, b.phi]: on
    arc j (u = u_j) the energy E_j = omega^2 / 2 - cos(theta) - kappa u_j theta is constant, so its
    turning points are where V_j(theta) = -cos(theta) - kappa u_j theta = E_j; E_j is a smooth
    function of phi (through a passage by a saddle too, where the turning points are not), bounded
    on each half as theta_label is (`_curvatures`), and a target theta*_k is excluded where
    V_j(theta*_k) = -cos(base) - kappa u_j theta*_k is outside those bounds."""
    values = [s.energies.get(arc) for s in (a, m, b)]
    if None in values:
        return False
    (ea, dea), (em, dem), (eb, deb) = values
    reach = max(_reaches(ea, em, eb, dea, dem, deb, h))
    if not math.isfinite(reach):
        return False
    torque = _torque(problem.kappa, a.u0, arc)
    level = -math.cos(problem.base)
    ends = ((level - min(ea, em, eb) + reach) / torque, (level - max(ea, em, eb) - reach) / torque)
    return not _targets(problem, min(ends), max(ends))


def _arrivals_by(problem, a, m, b, arrive, h):
    """For each half of [a.phi, b.phi] (width h), the latest time an arrival may have there, `arrive` or
    earlier. An arrival at T after a state of its extremal is `Problem.transit` later, one before it
    the transit with omega's sign reversed earlier (run backwards in time): none is within those of a
    state bounded on the half (at a time a, m and b recorded, `_Sample.ends`, omega's sign bounded too
    (`_signs`), or at a switch or a turning point they all see: its time, angle and e bounded by their
    values and slopes, `_reaches`; omega's sign at a switch, never 0 there (p1 omega = 1), is one
    along it, known where the three samples agree),
    where the three see the same switches and turning points before it (where they do not, the family
    changes between them in ways their values and slopes need not show: an abnormal end's switches,
    moving by thousands per radian). From the latest of those states down, each whose window reaches
    above the latest time left lowers it to the window's start; the first record or switch below it
    whose window does not ends that half's descent (a turning point does not: near a target its window
    is small, and the switch before it may reach far). Two facts tighten a window: along each
    extremal the shared switches and turning points come in their label order (switch k ends arc k),
    so each is no earlier than the least time bounded for any before it, and no later than the latest
    of any after it; and a turning point's e is -cos(theta), bounded by its angle's window."""
    samples = (a, m, b)
    # the turning points the three see alike, the first `shared` (`events` is in time order), and the
    # time of each sample's first that they do not
    shared = next((i for i, (la, lm, lb) in enumerate(zip(a.events, m.events, b.events)) if not la == lm == lb),
                  min(len(s.events) for s in samples))
    alike = list(itertools.islice(a.events, shared))
    differ = [next(itertools.islice(s.events.values(), shared, None), (math.inf,))[0] for s in samples]

    # the window of each shared switch (k, 1) and turning point (j, 0, i) on each half, (least, latest),
    # narrowed to the least times of those before it and the latest of those after it in label order
    switches = [k for k in range(min(len(s.switch_times) for s in samples))
                if all(s.switch_times[k] < d for s, d in zip(samples, differ))]
    order, windows = sorted([(k, 1) for k in switches] + [(j, 0, i) for j, i in alike]), {}
    for key in order:
        if len(key) == 2:
            times, slopes = [s.switch_times[key[0]] for s in samples], [s.switch_slopes[key[0]] for s in samples]
        else:
            times, slopes = [s.events[key[0], key[2]][0] for s in samples], [s.slopes[key[0], key[2]][0] for s in samples]
        reach = _reaches(*times, *slopes, h)
        windows[key] = [[min(t0, t1) - r, max(t0, t1) + r] for t0, t1, r in zip(times[:2], times[1:], reach)]
    for before, after in zip(order[:-1], order[1:]):
        for half in (0, 1):
            windows[after][half][0] = max(windows[after][half][0], windows[before][half][0])
    for before, after in zip(order[-2::-1], order[:0:-1]):
        for half in (0, 1):
            windows[before][half][1] = min(windows[before][half][1], windows[after][half][1])

    def recorded():
        for t in sorted(a.ends.keys() & m.ends.keys() & b.ends.keys(), reverse=True):
            if t < min(differ) and bisect.bisect_right(a.switch_times, t) == bisect.bisect_right(
                    m.switch_times, t) == bisect.bisect_right(b.switch_times, t):
                yield t, [s.ends[t][4:] + s.ends[t][2:4] for s in samples], True, \
                    _signs(*(s.ends[t][:2] for s in samples), h), ((t, t), (t, t))

    def switched():
        for k in reversed(switches):
            times = [s.switch_times[k] for s in samples]
            # omega's sign, never 0 at a switch, is one along it: known where the three agree
            sign = a.switch_signs[k] if a.switch_signs[k] == m.switch_signs[k] == b.switch_signs[k] else 0.0
            yield max(times), [s.switch_states[k] for s in samples], True, (sign, sign), windows[k, 1]

    def turned():
        for label in reversed(alike):
            yield max(s.events[label][0] for s in samples), [
                (x, dx, -math.cos(x), math.sin(x) * dx) for x, dx in ((s.events[label][1], s.slopes[label][1]) for s in samples)], \
                False, (0.0, 0.0), windows[label[0], 0, label[1]]

    latest, descending = [arrive, arrive], [True, True]
    for _, states, ends, signs, window in heapq.merge(recorded(), switched(), turned(),
                                                      key=lambda p: p[0], reverse=True):
        (xa, dxa, ea, dea), (xm, dxm, em, dem), (xb, dxb, eb, deb) = states
        reach_x, reach_e = _reaches(xa, xm, xb, dxa, dxm, dxb, h), _reaches(ea, em, eb, dea, dem, deb, h)
        for half, (x0, x1, e0, e1) in enumerate(((xa, xm, ea, em), (xm, xb, em, eb))):
            if not descending[half]:
                continue
            first, last = window[half]
            box = (min(x0, x1) - reach_x[half], max(x0, x1) + reach_x[half],
                   min(e0, e1) - reach_e[half], max(e0, e1) + reach_e[half])
            if not ends:                    # a turning point: e = -cos(theta) on its angle's window
                low, high = _cosine_range(box[0], box[1])
                if max(low, box[2]) <= min(high, box[3]):     # (disjoint, the cosine's range alone holds)
                    low, high = max(low, box[2]), min(high, box[3])
                box = (box[0], box[1], low, high)
            after = problem.transit(*box, signs[half])
            if first + after > latest[half]:       # no arrival after it: one before, by the way back in time
                latest[half] = min(latest[half], last - (problem.transit(*box, -signs[half]) if signs[half] else after))
            elif last <= latest[half] and ends:
                descending[half] = False
        if not (descending[0] or descending[1]):
            break
    return latest


def _cosine_range(lo, hi):
    """The range of -cos(theta) over theta in [lo, hi]: -1 where a multiple of 2 pi lies in it, 1 where an
    odd multiple of pi does, else the larger and smaller of its ends'."""
    ends = (-math.cos(lo), -math.cos(hi))
    low = -1.0 if math.floor(hi / (2 * math.pi)) * 2 * math.pi >= lo else min(ends)
    high = 1.0 if math.floor((hi - math.pi) / (2 * math.pi)) * 2 * math.pi + math.pi >= lo else max(ends)
    return low, high


def _signs(a, m, b, h):
    """For each half, omega's sign there (0: either) from its (value, slope) at a, m, b, bounded as
    `_reaches` bounds a function."""
    (wa, dwa), (wm, dwm), (wb, dwb) = a, m, b
    reach = _reaches(wa, wm, wb, dwa, dwm, dwb, h)
    return tuple(1.0 if min(w0, w1) - r > 0 else -1.0 if max(w0, w1) + r < 0 else 0.0
                 for w0, w1, r in ((wa, wm, reach[0]), (wm, wb, reach[1])))


def _dips(label, samples, values, arrive):
    """Whether the time of the turning point `label`, seen at some of the samples only (values None
    where not), extrapolated along its slope from a sample that sees it to one that does not, falls
    to `arrive` or before: it may dip before the acceptance between them (its time, late where seen,
    falling steeply toward where it is not, as it may where it runs into a saddle beyond)."""
    seen = [(s.phi, v[0], s.slopes[label][0]) for s, v in zip(samples, values) if v is not None]
    unseen = [s.phi for s, v in zip(samples, values) if v is None]
    return any(t + slope * (phi - x) <= arrive for x, t, slope in seen for phi in unseen)


def _soonest(problem, events):
    """The earliest time an arrival may follow a turning point seen at `events` ((t, theta) at some
    samples), judged by those: its least time there, plus the transit (`Problem.transit`, F in [0, 2] at rest)
    from the nearest of its angles to an allowed target (0 if a target lies between them)."""
    times, angles = zip(*events)
    return min(times) + problem.transit(min(angles), max(angles), -1.0, 1.0)


def _curvatures(fa, fm, fb, sa, sm, sb, h):
    """For each half of [a, b] (a, m = a + h, b = a + 2h), the largest |second derivative| of the
    cubic Hermite interpolants of a function's values f and slopes s at a, m, b at the ends of that
    half (where a cubic's, linear, is extreme), both interpolants' at m: local estimates of |f''|."""
    left, right = 6 * (fm - fa) / h, 6 * (fb - fm) / h
    at_left, at_m, at_right = abs(left - 4 * sa - 2 * sm), abs(-left + 2 * sa + 4 * sm), abs(-right + 2 * sm + 4 * sb)
    at_m_right = abs(right - 4 * sm - 2 * sb)
    # max() written as conditionals on the search's hot paths: a call of the builtin costs about nine
    # comparisons in CPython 3.11 (the same value, the first of equals, NaN propagated as max does)
    at_m = at_m_right if at_m_right > at_m else at_m
    return (at_m if at_m > at_left else at_left) / h, (at_right if at_right > at_m else at_m) / h


def _reaches(fa, fm, fb, sa, sm, sb, h):
    """For each half, how far the function may leave the chord of its end values there:
    M h^2 / 8 with M = CURVATURE * `_curvatures`."""
    left, right = _curvatures(fa, fm, fb, sa, sm, sb, h)
    scale = CURVATURE * h * h / 8
    return left * scale, right * scale


def _examine(problem, family, a, m, b, accept, extended, arrive=None):
    """(split, singular, brackets, soonest) for the interval [a.phi, b.phi] with midpoint m: whether it must
    be bisected, and if only because a turning point goes to infinite time inside it (the extremal
    reaches an equilibrium of its arc, a saddle), the nearest approach of that turning point to a
    target; and the brackets (phi_lo, phi_hi, label, branch, time, (earliest, latest)) it resolves
    (none if it is split and will be examined again in its halves; time: the later end's, earliest and
    latest: the bounds of the turning point's time on the bracket). Arrivals are sought before
    `arrive` (default `accept`, the time of the omega check below). A turning point present at some of
    a, m, b only is first looked for by integrating the others to `extended`.

    The bound (the module's docstring): on each half [x0, x1] (width h) of the interval, with
    |f''| <= M = CURVATURE * _curvatures, f = theta_label stays within M h^2 / 8 of the
    chord of its end values, and f' keeps the sign of its end slopes s0, s1 if s0 s1 > 0 and
    |s0 + s1| > M h (f' >= (s0 + s1 - M h) / 2 there). A half is resolved when the first excludes
    every target, or the second holds: then a target is crossed once or not at all, as the end
    values say. The turning point's time t_label is bounded alike: a half whose least time, less
    M_t h^2 / 8, is after `accept` holds no arrival; and omega at `accept` (or at a later time the
    three recorded): where a, m, b see the same turning points before the horizon (extended /
    EXTEND), a half where it may have two zeros may hide one no sample sees, and is split unless the
    arc running then runs through the interval and its energy excludes every target; a half where it
    has no zero (or one, monotone) and whose ends see the same turning points before that time
    (`settled`) has those only: a label not among them is after it, or absent, there. A
    label seen by some samples only splits the interval unless it is late and does not dip (`_dips`), or its arc's
    energy excludes every target (`_energy_excludes`), as it does for a label whose angle the bound
    leaves unresolved. `soonest`: the earliest an arrival may follow what forced a split (`_soonest`; the scan examines the
    halves in that order)."""
    split, singular, brackets, soonest = False, math.inf, [], math.inf
    arrive = accept if arrive is None else arrive
    h = 0.5 * (b.phi - a.phi)
    # the turning points before the acceptance t_a change on [a, b] only where one crosses it, a zero
    # of omega(t_a, phi): where a, m, b see the same ones before the horizon, a half where
    # omega(t_a, .) has no zero, or one (monotone), hides none; where they differ, the labels below decide
    horizon = extended / EXTEND
    seen = [s.seen(horizon) for s in (a, m, b)]
    alike = seen[0] == seen[1] == seen[2]
    # omega at t_a, or at a later time before the horizon the three recorded (a conservative check: the
    # turning points before it are constant where it has no zero, and those the labels below examine),
    # else recorded at t_a (integrated on, or again from t = 0)
    later = [t for t in a.ends.keys() & m.ends.keys() & b.ends.keys() if accept <= t <= horizon]
    end = min(later, default=accept)
    (wa, dwa, ea, dea, _, _), (wm, dwm, em, dem, _, _), (wb, dwb, eb, deb, _, _) = (
        s.omega(family, end) for s in (a, m, b))
    # per half: omega(end, .) has no zero there, or one (monotone), or e(end, .) > 1 there (a rotation:
    # omega^2 / 2 > 1 + cos(theta) >= 0; e has no fast phase where omega has, when the family rotates)
    quiet, e_reach, saddle, curvatures = [], None, None, _curvatures(wa, wm, wb, dwa, dwm, dwb, h)
    follow = _turns_follow(a, m, b, end, h)
    for half, (w0, w1, s0, s1, e0, e1) in enumerate(((wa, wm, dwa, dwm, ea, em), (wm, wb, dwm, dwb, em, eb))):
        bound = CURVATURE * curvatures[half]
        low, high = w1 if w1 < w0 else w0, w1 if w1 > w0 else w0       # min, max (as _curvatures writes them)
        calm = (low - bound * h * h / 8 > 0 or high + bound * h * h / 8 < 0
                or (s0 * s1 > 0 and abs(s0 + s1) > bound * h))
        if not calm:
            e_reach = e_reach or _reaches(ea, em, eb, dea, dem, deb, h)
            # e(end, .) > 1, unless an arc before `end` may pass by a saddle there (e dips below 1 unseen)
            if min(e0, e1) - e_reach[half] > 1:
                saddle = saddle or _may_pass_saddle(problem.kappa, a.u0, a, m, b,
                                                    max(a.arc(end), m.arc(end), b.arc(end)), h)
                calm = not saddle[half]
        quiet.append(calm and follow[half])
    hidden = not (quiet[0] and quiet[1])
    # a quiet half whose ends see the same turning points before `end` has no zero of omega(end, .) (one
    # would change them): every phi of it sees those, and a label after `end` at its ends is after it there
    before = [s.seen(end) for s in (a, m, b)] if quiet[0] or quiet[1] else [(), (), ()]
    settled = (quiet[0] and before[0] == before[1], quiet[1] and before[1] == before[2])
    if hidden and b.phi - a.phi > 2 * MIN_WIDTH and alike:
        # a turning point crossing that time unseen is of the arc running then (it cannot cross a switch):
        # none is an arrival where that arc runs through [a, b] then and its energy excludes every target
        arc = a.arc(end)
        if not (_runs_through(a, m, b, arc, end, h) and _energy_excludes(problem, a, m, b, arc, h)):
            split, soonest = True, accept
    # labels in time order along an extremal, (arc, index in arc): once a label's turning point is
    # after the acceptance on a whole half, every later one is too (at each phi, later in time; a label
    # absent there says nothing of the later ones: `after` is this label's only); so is every label from
    # arc j on where a switch before arc j that a, m and b record is after it on the whole half
    late, common, switched = [False, False], min(len(a.switch_times), len(m.switch_times), len(b.switch_times)), {}

    def switch_after(label, by):
        """For each half, whether the last switch a, m and b record before `label`'s arc is after `by`
        (bounded by its values and slopes, `_reaches`) on the whole half: then so is the label."""
        switch = min(label[0], common) - 1
        if switch < 0:
            return False, False
        if (switch, by) not in switched:
            times = [s.switch_times[switch] for s in (a, m, b)]
            reach_s = _reaches(*times, *(s.switch_slopes[switch] for s in (a, m, b)), h)
            switched[switch, by] = (min(times[:2]) - reach_s[0] > by[0], min(times[1:]) - reach_s[1] > by[1])
        return switched[switch, by]

    def verdict(label, by):
        """What `label` asks of [a, b] where arrivals on each half are before `by`: None (nothing),
        ("split", soonest, nearest approach) or ("found", brackets); `late` updated."""
        nonlocal late
        after = (settled[0] and label not in before[0], settled[1] and label not in before[1])
        if (late[0] or after[0]) and (late[1] or after[1]):
            return None
        values = [s.events.get(label) for s in (a, m, b)]
        if None in values:
            for s, v in zip((a, m, b), values):
                if v is None and s.duration < extended:
                    s.integrate(family, extended)
            values = [s.events.get(label) for s in (a, m, b)]
            if None in values:                      # the switch before its arc: after the acceptance?
                late = [late[0] or switch_after(label, by)[0], late[1] or switch_after(label, by)[1]]
                if late[0] and late[1]:
                    return None
            if None in values:
                latest = max(by)
                if min(v[0] for v in values if v is not None) > latest + DIP * (extended / EXTEND - latest) \
                        and not _dips(label, (a, m, b), values, latest):
                    return None
                if _energy_excludes(problem, a, m, b, label[0], h):
                    return None
                return ("split", _soonest(problem, [v for v in values if v is not None]),
                        min(problem.gap(v[1], v[1]) for v in values if v is not None))
        (ta, tha), (tm, thm), (tb, thb) = values
        (dta, dtha), (dtm, dthm), (dtb, dthb) = a.slopes[label], m.slopes[label], b.slopes[label]
        early = (min(ta, tm) <= by[0] and not late[0], min(tm, tb) <= by[1] and not late[1])
        reach_t = None                      # how far the time may dip below its ends' on each half
        if not (early[0] and early[1]):     # a half after the acceptance at both ends: may it dip before?
            reach_t = _reaches(ta, tm, tb, dta, dtm, dtb, h)
            late = [late[0] or min(ta, tm) - reach_t[0] > by[0], late[1] or min(tm, tb) - reach_t[1] > by[1]]
            if not (late[0] and late[1]):   # or the switch before it (a turning point's time may dip far)
                late = [late[0] or switch_after(label, by)[0], late[1] or switch_after(label, by)[1]]
            early = (not late[0], not late[1])
        early = (early[0] and not after[0], early[1] and not after[1])
        if not (early[0] or early[1]):      # the turning point's time stays after the acceptance
            return None
        bounds = _curvatures(tha, thm, thb, dtha, dthm, dthb, h)
        found, resolved = [], math.isfinite(bounds[0] + bounds[1])
        reach = CURVATURE * max(bounds) * h * h / 8
        if resolved and not _targets(problem, min(tha, thm, thb) - reach, max(tha, thm, thb) + reach):
            return None                     # no target within reach on either half
        for half, x0, x1, t0, t1, f0, f1, s0, s1, bound, early_half in (
                (0, a.phi, m.phi, ta, tm, tha, thm, dtha, dthm, CURVATURE * bounds[0], early[0]),
                (1, m.phi, b.phi, tm, tb, thm, thb, dthm, dthb, CURVATURE * bounds[1], early[1])):
            if not (resolved and early_half):
                continue
            reach = bound * h * h / 8
            ks = _targets(problem, min(f0, f1) - reach, max(f0, f1) + reach)
            if not ks:
                continue
            if not (s0 * s1 > 0 and abs(s0 + s1) > bound * h):
                resolved = False
                break
            for k in ks:
                target = problem.target(k)[0]
                if (f0 - target) * (f1 - target) < 0 or f1 == target:
                    reach_t = reach_t or _reaches(ta, tm, tb, dta, dtm, dtb, h)
                    spread = reach_t[half]
                    found.append((x0, x1, label, k, max(t0, t1), (min(t0, t1) - spread, max(t0, t1) + spread)))
        if resolved:
            return "found", found
        if _energy_excludes(problem, a, m, b, label[0], h):
            return None
        # a jump of more than JUMP rad at the finest spacing is a discontinuity: the extremal
        # meets a saddle there (the turning point's time is unbounded), no crossing hides in it
        jump = b.phi - a.phi <= 2 * MIN_WIDTH and abs(thm - tha) + abs(thb - thm) > JUMP
        return "split", _soonest(problem, values), min(problem.gap(th, th) for th in (tha, thm, thb)) if jump else -1.0

    # arrivals on each half are before `arrive`, or (`_arrivals_by`, worked out where a label would split
    # the interval and, in a scan, its _Payoff says so) before the earlier time the transit from the
    # states its samples share allows
    by, payoff = None, family.transit if family is not None else None
    for label in sorted(seen[0] | seen[1] | seen[2]):
        if late[0] and late[1]:
            break
        outcome = verdict(label, by or (arrive, arrive))
        if outcome is not None and outcome[0] == "split" and by is None and (payoff is None or payoff.wanted()):
            by = tuple(_arrivals_by(problem, a, m, b, arrive, h))
            # a half whose arrivals would be before the least time from the start holds none
            least = problem.lower_bound
            late = [late[0] or by[0] < least, late[1] or by[1] < least]
            outcome = verdict(label, by)
            if payoff is not None:
                payoff.record(outcome is None or outcome[0] != "split")
        if outcome is None:
            continue
        if outcome[0] == "found":
            brackets += outcome[1]
        else:
            split, soonest, singular = True, min(soonest, outcome[1]), min(singular, outcome[2])
    if split and b.phi - a.phi > 2 * MIN_WIDTH:
        brackets = []           # found again in the halves
    return split, singular, brackets, soonest


def _root(family, problem, u0, label, branch, lo, hi, t_guess, accuracy, near=None):
    """(phi, switches, turning point, Taylor steps to it) of the extremal whose turning point `label`
    reaches the target of `branch`, phi in [lo, hi] (a sign change), or None: safeguarded Newton on
    g(phi) = theta_label(phi) - theta*, g' = dtheta_label/dphi, from `near` (a root at another
    accuracy) or the root of the cubic Hermite interpolant of the scan's samples at lo and hi, kept
    in the bracket (bisection where a step would leave it), to 4 eps |phi| as Brent's method. The
    last iterate is a root only if a Newton step from it, |g / g'|, stays within the final bracket
    (or the rounding floor): else the sign change is a jump of g, not a crossing (near an abnormal
    extremal, where a switch and a turning point swap order and the labels renumber), and None."""
    target = problem.target(branch)[0]
    duration = 1.05 * t_guess + 0.1

    def turning_point(phi):
        nonlocal duration
        while True:
            _, switches, _, events, _, _ = family.run(phi, u0, duration, accuracy)
            hit = [i for i, (arc, index) in enumerate(events[:, 2:4].tolist()) if (arc, index) == label]
            if hit or duration > 2 * t_guess + 10:
                return (events[hit[0]].copy() if hit else None), switches.copy()
            duration *= 1.5

    ends = [family._samples.get((phi, u0)) for phi in (lo, hi)]
    if all(s is not None and label in s.events for s in ends):
        (ga, da), (gb, db) = ((s.events[label][1] - target, s.slopes[label][1]) for s in ends)
    else:
        (ea, _), (eb, _) = turning_point(lo), turning_point(hi)
        if ea is None or eb is None:
            return None
        (ga, da), (gb, db) = (ea[1] - target, ea[6]), (eb[1] - target, eb[6])
    if not ga * gb <= 0:
        return None
    phi = _hermite_root(lo, hi, ga, gb, da, db) if near is None else min(max(near, lo), hi)
    negative_lo = ga < 0 if ga != 0 else gb > 0
    best, previous = None, math.inf
    for _ in range(NEWTON_ITERATIONS):
        event, switches = turning_point(phi)
        if event is None:
            return None
        g, slope = event[1] - target, event[6]
        if best is None or abs(g) < best[0]:
            best = (abs(g), phi, switches, event)
        if g == 0:
            break
        if (g < 0) == negative_lo:
            lo = phi
        else:
            hi = phi
        following = phi - g / slope if slope != 0 else math.nan
        if not lo <= following <= hi:
            following = 0.5 * (lo + hi)
        step = abs(following - phi)
        # converged, or at the rounding floor (a Newton step that no longer halves, already tiny)
        if step <= 4 * EPS * abs(phi) or (step > 0.5 * previous and step < NEWTON_FLOOR * max(1.0, abs(phi))):
            break
        phi, previous = following, step
    else:
        return None
    _, phi, switches, event = best
    if abs(event[1] - target) > abs(event[6]) * max(hi - lo, NEWTON_FLOOR * max(1.0, abs(phi))):
        return None
    return _Root(phi, switches, event, family.steps_per_time * event[0])


class _Root(NamedTuple):
    """An extremal solved by `_root`: its costate angle, its switches' rows (t, theta, omega, ...),
    the turning point's row of `_Sample.events` (t, theta, arc, index, ...), the Taylor steps to it."""

    phi: float
    switches: np.ndarray
    event: np.ndarray
    steps: float

    @property
    def T(self):
        return float(self.event[0])


def _hermite_root(lo, hi, ga, gb, da, db):
    """The root in [lo, hi] of the cubic Hermite interpolant of g (values ga, gb of opposite signs,
    slopes da, db at lo, hi), by a few safeguarded Newton steps on the cubic from the secant's root."""
    h = hi - lo
    c0, c1 = ga, da * h
    c2, c3 = 3 * (gb - ga) - (2 * da + db) * h, 2 * (ga - gb) + (da + db) * h
    x = ga / (ga - gb) if ga != gb else 0.5
    a, b = 0.0, 1.0
    for _ in range(8):
        value = c0 + x * (c1 + x * (c2 + x * c3))
        if (value < 0) == (ga < 0):
            a = x
        else:
            b = x
        slope = c1 + x * (2 * c2 + 3 * x * c3)
        following = x - value / slope if slope != 0 else 0.5 * (a + b)
        x = following if a < following < b else 0.5 * (a + b)
    return lo + x * h


def _arrival(x0, kappa, u0, branch, label, solution, error_of, solved, original=None):
    """The Extremal of a solved turning point, its errors SAFETY times the largest difference to the
    solutions in `error_of` (the same arrival at other accuracies), plus the rounding floor. With
    `original` (the scan was of `_Backward(original)`), the extremal read forwards in time:
    x(t) = (theta~(T - t) + theta*_k, -omega~(T - t)), u(t) = u~(T - t), p(t) = (-p1~, p2~)(T - t)
    for the original branch k = -branch."""
    phi, switches, event, steps = solution
    arc = label[0]
    times = tuple(float(t) for t in switches[:arc, 0])
    T_spread = max(abs(event[0] - other.event[0]) for other in error_of)
    times_spread = max((abs(a - float(b)) for other in error_of for a, b in zip(times, other.switches[:arc, 0])),
                       default=0.0)
    scale = x0[1] * math.cos(phi) + (kappa * u0 - math.sin(x0[0])) * math.sin(phi)
    # rounding of the target state moves T by p(T) . dx (H = 0 fixes p(T): p2(T) (kappa u_T - sin theta_T) = 1)
    u_T = u0 * (-1) ** arc
    theta_T = event[1]
    force_T = kappa * u_T - math.sin(theta_T)
    p1_T, p2_T = event[4] / (event[5] * force_T), 1 / force_T
    T = float(event[0])
    floor = EPS * (max(1.0, abs(theta_T)) * max(abs(p1_T), 2 / (kappa * T)) + (kappa + 1) * abs(p2_T))
    # the rounding accumulated over the Taylor steps, an error of eps * |y| per step carried to T
    floor += EPS * steps * max(1.0, T)
    signs = tuple(int(u0 * (-1) ** i) for i in range(arc + 1))
    states = tuple((float(s[1]), float(s[2])) for s in switches[:arc])
    p0 = (math.cos(phi) / scale, math.sin(phi) / scale)
    if original is not None:
        branch = -branch
        shift = original.target(branch)[0] - original.base
        signs, times = signs[::-1], tuple(T - t for t in times[::-1])
        states = tuple((theta + shift, -omega) for theta, omega in states[::-1])
        p0 = (-p1_T, p2_T)
        phi = math.atan2(p0[1], p0[0])
    return Extremal(
        branch=branch, phi=phi, T=T, signs=signs, switch_times=times, switch_states=states, p0=p0,
        T_error=SAFETY * float(T_spread) + floor,
        switch_time_error=SAFETY * times_spread + EPS * steps * max(1.0, T),
        solved=solved)


def _distinct(arrivals):
    """The arrivals with duplicates dropped: one trajectory reached from several costate angles (an
    arrival before the first switch does not depend on the costate) is one extremal."""
    kept = []
    for a in arrivals:
        if not any(a.signs == b.signs and a.branch == b.branch and abs(a.T - b.T) <= 10 * (a.T_error + b.T_error)
                   and np.allclose(a.switch_times, b.switch_times, rtol=0, atol=10 * (a.T_error + b.T_error))
                   for b in kept):
            kept.append(a)
    return kept


class _Acceptance:
    """The acceptance that bracketed arrivals with time bounds (earliest, latest) allow: with B the
    least latest bound (the best time T* <= B), (1 + margin) B, which every arrival within margin of
    the best precedes, and for margin <= MARGIN (the runner-up only) also the least latest bound of
    an arrival whose earliest is after B (1 + TIE_WINDOW): no tie of the best, so the runner-up
    precedes it; `value`, never above `start` nor below `floor`. Kept as brackets are added: B only
    falls, so a bracket once after B (1 + TIE_WINDOW) stays so, and only those that may tie the best
    are held to be looked at again."""

    def __init__(self, margin, start, floor):
        self.margin, self.start, self.floor, self.value = margin, start, floor, start
        self.best, self.later, self.ties, self.bounds = math.inf, math.inf, [], []

    def add(self, bound):
        """Lowers `value` to the acceptance once the bracket with these time bounds is added."""
        earliest, latest = bound
        self.bounds.append(bound)
        self.best = min(self.best, latest)
        self.ties.append(bound)
        tie = self.best * (1 + TIE_WINDOW)
        self.later = min([self.later] + [late for early, late in self.ties if early > tie])
        self.ties = [(early, late) for early, late in self.ties if early <= tie]
        allowed = min((1 + self.margin) * self.best, self.later if self.margin <= MARGIN else math.inf)
        self.value = min(self.value, max(self.floor, allowed))

    def without(self, bounds):
        """The acceptance of the brackets added, each of `bounds` once less."""
        kept, others = _Acceptance(self.margin, self.start, self.floor), list(self.bounds)
        for bound in bounds:
            others.remove(bound)
        for bound in others:
            kept.add(bound)
        return kept


class _Solved(NamedTuple):
    """A bracket's root: the bracket (u0, lo, hi), the turning point `label` reaching the target of
    `branch`, solved at SCAN (`rough`) and CHECK (`check`) accuracy (each a _Root)."""

    u0: float
    lo: float
    hi: float
    label: tuple
    branch: int
    rough: "_Root"
    check: "_Root"

    @property
    def T(self):
        return self.check.T


def _accepting(arrive):
    """(accept, horizon) of a scan that goes on to the acceptance `arrive`: the horizon whose
    acceptance, horizon * (1 - HORIZON_BAND) as a sample records it (`_Sample.integrate`), is
    `arrive` or the next float above it (not a float below: omega is checked at it)."""
    horizon = arrive / (1 - HORIZON_BAND)
    while horizon * (1 - HORIZON_BAND) < arrive:
        horizon = math.nextafter(horizon, math.inf)
    return horizon * (1 - HORIZON_BAND), horizon


def scan(problem, horizon, original=None, clock=None, halves=2, family=None, margin=MARGIN, floor=0.0):
    """(arrivals, Coverage) of every extremal reaching the target before the acceptance: horizon *
    (1 - HORIZON_BAND), lowered as arrivals are bracketed (`_Acceptance`), never below `floor`; the
    Coverage's horizon is the acceptance reached (`original`: `problem` is `_Backward(original)`, the arrivals
    are read forwards; `halves` = 1: the first admissible half-circle only; `clock`: a _Clock whose
    time limit may end the scan; `family`: the _Family of `problem` of an earlier scan, whose samples
    are reused)."""
    start = time.perf_counter()
    clock = clock or _Clock(None, None)
    family = family or _Family(problem.x0, problem.kappa)
    accept = arrive = horizon * (1 - HORIZON_BAND)
    intervals = admissible_intervals(problem.x0, problem.kappa)[:halves]
    brackets, unresolved, singular, finest = [], [], [], math.inf
    acceptance, queue, order = _Acceptance(margin, arrive, floor), [], itertools.count()
    for lo, hi, u0 in intervals:
        for end in (family.sample(lo, u0, horizon), family.sample(hi, u0, horizon)):
            closest = min((problem.gap(th, th) for t, th in end.events.values() if t <= accept), default=math.inf)
            if closest < END_NEAR:
                unresolved.append((end.phi, end.phi, closest))
        grid = [family.sample(phi, u0, horizon) for phi in np.linspace(lo + END_OFFSET, hi - END_OFFSET, SAMPLES + 1)]
        queue += [(0.0, next(order), u0, a, b) for a, b in zip(grid[:-1], grid[1:])]
    solved = []
    while True:
        while queue and not clock.tick(horizon, queue[0][2], queue[0][3].phi, family.count, len(brackets)):
            _, _, u0, a, b = heapq.heappop(queue)
            m = family.sample(0.5 * (a.phi + b.phi), u0, horizon)
            split, closest, found, soonest = _examine(problem, family, a, m, b, accept, EXTEND * horizon, arrive)
            brackets += [(u0, f) for f in found]
            for f in found:
                acceptance.add(f[5])
            arrive = acceptance.value
            if arrive < RESCAN * accept:        # on, to the horizon of the acceptance reached
                accept, horizon = _accepting(arrive)
            finest = min(finest, 0.5 * (b.phi - a.phi))
            if split and b.phi - a.phi > 2 * MIN_WIDTH:
                heapq.heappush(queue, (soonest, next(order), u0, a, m))
                heapq.heappush(queue, (soonest, next(order), u0, m, b))
            elif split and closest >= FAR:
                singular.append((a.phi, b.phi, closest))
            elif split:
                unresolved.append((a.phi, b.phi, closest))
        # every arrival solved to CHECK accuracy (its error: the change from SCAN), ranked; the best, those
        # within TIE_WINDOW of it and the runner-up then to PRECISE (their error: the change from CHECK)
        # (earliest first; once the time limit has passed, only until one is solved: the best so far)
        failed = []
        for u0, (lo, hi, label, branch, t_guess, (earliest, latest)) in sorted(brackets, key=lambda b: b[1][5][0]):
            if earliest > arrive:
                continue                        # bracketed before the acceptance was lowered below it
            if any((s.u0, s.label, s.branch) == (u0, label, branch) and lo <= s.check.phi <= hi for s in solved):
                continue                        # its root solved (found again where a failed bracket's was examined again)
            if solved and clock.tick(horizon, u0, lo, family.count, len(brackets)):
                unresolved.append((lo, hi, -1.0))   # the time limit passed: not solved, reported
                continue
            rough = _root(family, problem, u0, label, branch, lo, hi, t_guess, taylor.SCAN)
            check = rough and _root(family, problem, u0, label, branch, lo, hi, t_guess, taylor.CHECK, rough.phi)
            if check is None:
                failed.append((u0, lo, hi, (earliest, latest)))
            elif check.T <= arrive:
                solved.append(_Solved(u0, lo, hi, label, branch, rough, check))
        brackets = []
        # a bracket without a root (a jump between its samples that their values and slopes did not show)
        # is examined again, split, where the acceptance is the one of the others: it did not lower it;
        # else, or at MIN_WIDTH, it is reported unresolved, never dropped
        kept = acceptance.without(f[3] for f in failed)
        again = failed and not clock.stopped and arrive == kept.value
        pushed = set()
        for u0, lo, hi, (earliest, _) in failed:
            if again and hi - lo > 2 * MIN_WIDTH:
                if (u0, lo, hi) not in pushed:      # two brackets of one interval: examined once
                    pushed.add((u0, lo, hi))
                    heapq.heappush(queue, (earliest, next(order), u0, family.sample(lo, u0, horizon),
                                           family.sample(hi, u0, horizon)))
            else:
                unresolved.append((lo, hi, -1.0))
        if not queue or not again:
            break
        acceptance = kept
    # a complete scan reports the arrivals before the acceptance it reached (an earlier round compared its
    # own with a higher one); one stopped or left with a bracket unsolved keeps every arrival solved
    solved = sorted((s for s in solved if clock.stopped or failed or s.T <= arrive), key=lambda s: s.T)
    arrivals = []
    for i, (u0, lo, hi, label, branch, rough, check) in enumerate(solved):
        important = check.T <= solved[0].T * (1 + TIE_WINDOW) or \
            i == next((j for j, s in enumerate(solved) if s.T > solved[0].T * (1 + TIE_WINDOW)), -1)
        precise = important and _root(family, problem, u0, label, branch, lo, hi, check.T, taylor.PRECISE, check.phi)
        alternative = precise and _root(family, problem, u0, label, branch, lo, hi, check.T, taylor.PRECISE_ALT,
                                        precise.phi)
        if precise and alternative:
            arrivals.append(_arrival(family.x0, family.kappa, u0, branch, label, precise, (check, alternative),
                                     "precise", original))
        else:
            arrivals.append(_arrival(family.x0, family.kappa, u0, branch, label, check, (rough,), "check", original))
    if halves == 1:
        arrivals += [_mirrored(original or problem, a) for a in arrivals]
    arrivals = _distinct(sorted(arrivals, key=lambda r: r.T))
    reading = ("backwards" if original is not None else "forwards") + (" + mirror" if halves == 1 else "")
    coverage = Coverage(arrive, tuple(intervals), family.count, finest, tuple(unresolved[:LISTED]),
                        tuple(singular[:LISTED]), time.perf_counter() - start, "scan", len(unresolved),
                        len(singular), clock.stopped is not None, reading)
    return arrivals, coverage


@dataclass(frozen=True)
class _Backward(Problem):
    """A start at rest (theta0, 0) run backwards in time: from the original's branch 0 target
    (base, 0) to the turning points (theta0 + 2 pi j, 0), branch j = -k for the original branch k.
    Time reversal, x~(t) = (theta(T - t) - 2 pi k, -omega(T - t)), u~(t) = u(T - t), maps the
    extremals of one onto the other's (see `_arrival`)."""

    angle: float = 0.0

    @property
    def base(self):
        return self.angle

    @classmethod
    def of(cls, problem):
        return cls(problem.kind, problem.kappa, (problem.base, 0.0),
                   None if problem.branch is None else -problem.branch, problem.x0[0])


def _backwards(problem):
    """Whether to scan `problem` backwards in time: a start at rest, in the upper half (where the
    forward family resolves an ever finer fan of extremals near the separatrix of the upright) while
    the target is in the lower (the reversed start then is)."""
    return problem.x0[1] == 0.0 and math.cos(problem.base) - math.cos(problem.x0[0]) > 1


def _center(problem):
    """The centre c of the symmetry theta -> 2c - theta, omega -> -omega, u -> -u, p -> -p that maps
    the problem onto itself, or None: a start at rest on a multiple of pi (sin(theta0) = 0 to
    rounding), on the circle (the reflected targets base - 2 pi k + 2c are targets)."""
    theta0, omega0 = problem.x0
    c = math.pi * round(theta0 / math.pi)
    if problem.branch is not None or omega0 != 0.0 or abs(theta0 - c) > 4 * EPS * max(1.0, abs(theta0)):
        return None
    return c


def _mirrored(problem, a):
    """The mirror image of the Extremal a under the symmetry about `_center(problem)`."""
    c = _center(problem)
    k = problem.nearest_branch(2 * c - problem.target(a.branch)[0])
    return Extremal(k, (a.phi + math.pi) % (2 * math.pi), a.T, tuple(-s for s in a.signs), a.switch_times,
                    tuple((2 * c - th, -om) for th, om in a.switch_states), (-a.p0[0], -a.p0[1]), a.T_error,
                    a.switch_time_error, a.solved)


def search(problem, horizon=None, margin=MARGIN, time_limit=None, progress=None, runner_up_budget=RUNNER_UP_BUDGET):
    """The complete Search of `problem`: scans with a horizon growing by GROWTH from the larger of
    GROWTH * problem.lower_bound and (on the circle, from a moving start or for kappa >= HEADROOM_KAPPA)
    HEADROOM * problem.time_estimate (or
    from `horizon`, e.g. a feasible time known, whose acceptance is then not lowered) until an arrival
    is found, then once more to the best time times (1 + margin) if the scan stopped short of it and
    (with margin <= MARGIN, whose purpose is the runner-up) found no runner-up, integrating at most
    `runner_up_budget` times the extremals before it, or RUNNER_UP_FLOOR (then the optimum is reported
    without a runner-up): a wider margin (the bench's references, the reference set) asks for every arrival
    before (1 + margin) times the best, whatever it costs. A start at rest in the upper half with the target below is scanned
    backwards in time (`_Backward`), a symmetric one (`_center`) over one half-circle and mirrored.

    time_limit: seconds; when they pass, the best arrival so far is returned, status "stopped" (not
    proven optimal; "optimal" still if only the runner-up's extension was cut). progress: called with
    a Progress every PROGRESS_EVERY seconds."""
    k = problem.at_target()
    if k is not None:
        on_target = Extremal(k, math.nan, 0.0, (), (), (), (math.nan, math.nan), 0.0, 0.0, "exact")
        return Search((on_target,), Coverage(0.0, (), 0, math.nan, (), (), 0.0), ("the start is on the target",))
    begun = time.perf_counter()
    edge = near.transfer(problem)
    if edge is not None:
        k, T, signs, times, states, p0, error = edge
        found = Extremal(k, math.atan2(p0[1], p0[0]), T, signs, times, states, p0, error, error, "near")
        coverage = Coverage(T, (), 0, math.nan, (), (), time.perf_counter() - begun, "near target")
        return Search((found,), coverage, (f"the start is within {near.NEAR_SCALE:g} rad of branch {k}: "
                                           "the transfer in closed form",))
    clock = _Clock(time_limit, progress)
    limit = max(MAX_HORIZON, REACH * problem.time_estimate)
    floor = 0.0 if horizon is None else horizon * (1 - HORIZON_BAND)     # a horizon given is scanned to
    scanned, original = (_Backward.of(problem), problem) if _backwards(problem) else (problem, None)
    halves = 1 if _center(problem) is not None else 2
    if horizon is None:
        estimated = problem.branch is None and (problem.kappa >= HEADROOM_KAPPA or problem.x0[1] != 0.0)
        guess = HEADROOM * problem.time_estimate if estimated else 0.0
        horizon = min(max(GROWTH * scanned.lower_bound, guess), limit)
    notes, done, family = [], None, _Family(scanned.x0, scanned.kappa)
    while True:
        arrivals, coverage = scan(scanned, horizon, original, clock, halves, family, margin, floor)
        if clock.stopped:
            if done is not None:        # the previous scan was complete: only the runner-up's extension was cut
                cut = f"its budget ({clock.budget:.0f} extremals in all)" if clock.stopped == "the budget" else "the time limit"
                return Search(*done, tuple(notes + [f"{cut} cut the scan for the runner-up: none reported"]))
            return Search(tuple(arrivals), coverage, tuple(notes + [f"stopped by the time limit ({time_limit:g} s)"]))
        if arrivals:
            clock.best = arrivals[0].T
            wanted = arrivals[0].T * (1 + margin) / (1 - HORIZON_BAND)
            runner_up = any(a.T > arrivals[0].T * (1 + TIE_WINDOW) + 10 * (a.T_error + arrivals[0].T_error)
                            for a in arrivals)
            if horizon >= wanted or (runner_up and margin <= MARGIN):  # a wider margin asks for every arrival
                return Search(tuple(arrivals), coverage, tuple(notes))
            notes.append(f"scanned to {horizon:.4g}, extended to {wanted:.4g} for the runner-up")
            done = (tuple(arrivals), coverage)
            if margin <= MARGIN:
                clock.budget = family.count + max(runner_up_budget * family.count, RUNNER_UP_FLOOR)
            horizon = wanted
            continue
        if horizon >= limit:
            found = "no extremal reaches the target" if coverage.complete else "no arrival found, intervals unresolved,"
            return Search((), coverage, tuple(notes + [f"{found} before {coverage.horizon:.4g}"]))
        notes.append(f"no arrival before {coverage.horizon:.4g}")
        horizon = min(GROWTH * horizon, limit)
