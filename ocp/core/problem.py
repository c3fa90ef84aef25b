"""The minimum-time problems of the pendulum, declared once.

    minimise T  subject to  x' = f(x, u; kappa) (`ocp.core.model.rhs`),  |u| <= 1,
                            x(0) = x0,  x(T) in the target set.

theta lives on a circle, so a target is a set of branches: the upright (pi + 2*pi*k, 0) for
swing-up, the hanging (2*pi*k, 0) for damping. A problem is read on the circle (`branch=None`:
any branch counts, the result says which was reached) or on the plane (`branch=k`: only that
target counts; the angle is a coordinate on the line). The two readings have different optima.
Every transcription and the peer take the dynamics, the control bounds and the terminal set from
here (`dynamics`, `CONTROL_BOUNDS`, `terminal_bounds`, `terminal_constraints`).
"""

import math
from dataclasses import dataclass, asdict
from functools import cached_property

from . import model
from .errors import InputError, finite, integer


@dataclass(frozen=True)
class Kind:
    """A problem kind: the target angle of branch 0 and the standard start."""

    target_base: float
    start: tuple
    about: str


#: the registry of problem kinds (a new kind: one line here)
KINDS = {
    "swing-up": Kind(math.pi, (0.0, 0.0), "from hanging at rest to the upright"),
    "damping": Kind(0.0, (math.pi, 0.0), "from the upright at rest to hanging"),
}
CONTROL_BOUNDS = (-1.0, 1.0)
#: accepted ranges, sized so that a solve ends in seconds to minutes on a laptop
KAPPA_RANGE = (0.05, 1e4)
THETA_LIMIT = 1e3
OMEGA_LIMIT = 50.0
READINGS = ("circle", "plane")


def terminal_bounds(reading, target):
    """The components of x(T) that the target set fixes: omega(T) = 0, and on the plane
    theta(T) = target (the pinned angle); None where free."""
    return {"theta": target if reading == "plane" else None, "omega": 0.0}


def terminal_constraints(reading, theta, omega, target):
    """[(expression, lower, upper)]: the rest of x(T) in the target set, symbolic (CasADi) in
    theta = theta(T): on the circle `target` is the base angle and any branch counts,
    sin(theta - target) = 0, cos(theta - target) >= 0; nothing more on the plane."""
    import casadi as ca

    if reading == "circle":
        return [(ca.sin(theta - target), 0.0, 0.0), (ca.cos(theta - target), 0.0, math.inf)]
    return []


dynamics = model.rhs


@dataclass(frozen=True)
class Problem:
    """One minimum-time transfer: `kind` in KINDS, torque bound `kappa`, start `x0`, and `branch`
    (None: the circle, any branch; an integer k: the plane, target branch k only)."""

    kind: str
    kappa: float
    x0: tuple[float, float]
    branch: int | None = None

    def __post_init__(self):
        if self.kind not in KINDS:
            raise InputError(f"unknown problem {self.kind!r}; accepted: {', '.join(KINDS)}")
        low, high = KAPPA_RANGE
        kappa = finite("kappa", self.kappa, f"a number from {low:g} to {high:g} (the torque bound tau0/(m g l))",
                       low, high)
        try:
            theta0, omega0 = self.x0
        except (TypeError, ValueError):
            raise InputError(f"x0 = {self.x0!r} is not a pair THETA OMEGA of finite numbers") from None
        x0 = (finite("theta0", theta0, f"a number with |theta0| <= {THETA_LIMIT:g} rad", -THETA_LIMIT, THETA_LIMIT),
              finite("omega0", omega0, f"a number with |omega0| <= {OMEGA_LIMIT:g}", -OMEGA_LIMIT, OMEGA_LIMIT))
        object.__setattr__(self, "kappa", kappa)
        object.__setattr__(self, "x0", x0)
        if self.branch is not None:
            k = integer("branch", self.branch, f"an integer k with a target within {THETA_LIMIT:g} rad of theta0",
                        -10**6, 10**6)
            if abs(self.base + 2 * math.pi * k - x0[0]) > THETA_LIMIT:
                raise InputError(f"branch = {self.branch!r}: its target is more than {THETA_LIMIT:g} rad from theta0; "
                                 f"branch accepts an integer k with a target within {THETA_LIMIT:g} rad of theta0")
            object.__setattr__(self, "branch", k)

    @property
    def reading(self):
        """"circle" (any branch of the target counts) or "plane" (the pinned branch only)."""
        return "circle" if self.branch is None else "plane"

    @property
    def base(self):
        """Target angle of branch 0: pi (swing-up) or 0 (damping)."""
        return KINDS[self.kind].target_base

    def target(self, k):
        """Target state of branch k: (base + 2*pi*k, 0)."""
        return (self.base + 2 * math.pi * k, 0.0)

    @property
    def nlp_target(self):
        """The `target` argument of terminal_constraints: the base angle on the circle, the pinned
        target angle on the plane."""
        return self.base if self.branch is None else self.target(self.branch)[0]

    def nearest_branch(self, theta):
        """The branch k whose target angle is nearest to theta (ties go to the smaller |k|)."""
        s = (theta - self.base) / (2 * math.pi)
        lo, hi = math.floor(s), math.ceil(s)
        if s - lo != hi - s:
            return lo if s - lo < hi - s else hi
        return min((lo, hi), key=abs)

    def allowed(self, k):
        """Whether reaching branch k solves this problem."""
        return self.branch is None or k == self.branch

    def on_target_angle(self, k):
        """Whether theta0 is the target angle of branch k to rounding (4 ulp of max(1, |theta0|))."""
        theta0 = self.x0[0]
        return abs(theta0 - self.target(k)[0]) <= 4 * 2.3e-16 * max(1.0, abs(theta0))

    def at_target(self):
        """The branch x0 is on (exactly, omega0 = 0 and theta0 on a target angle to rounding), or None."""
        theta0, omega0 = self.x0
        k = self.nearest_branch(theta0) if self.branch is None else self.branch
        return k if omega0 == 0.0 and self.on_target_angle(k) else None

    @property
    def stop_angle(self):
        """theta0 + omega0*|omega0|/(2*kappa): where full braking (u = -sign(omega), gravity
        neglected) brings the pendulum to rest."""
        theta0, omega0 = self.x0
        return theta0 + omega0 * abs(omega0) / (2 * self.kappa)

    @property
    def guess_branch(self):
        """The branch an initial guess aims at: the pinned one, else the nearest to `stop_angle`."""
        return self.branch if self.branch is not None else self.nearest_branch(self.stop_angle)

    @property
    def time_estimate(self):
        """A rough time to the target: braking to rest at `stop_angle` (|omega0|/kappa), then the
        larger of the two limits of the time from rest over the distance d to `guess_branch`,
        2*sqrt(d/kappa) (a double integrator, large kappa) and 1.2*d/kappa (energy pumped at a rate
        of about kappa*|omega|, small kappa; from (0, 0) the optimum is 1.20 pi/kappa at kappa = 0.3)."""
        d = abs(self.target(self.guess_branch)[0] - self.stop_angle)
        return abs(self.x0[1]) / self.kappa + max(2 * math.sqrt(d / self.kappa), 1.2 * d / self.kappa)

    @property
    def double_integrator_bound(self):
        """A lower bound of the minimum time: |theta''| <= kappa + 1, so no transfer is faster than the
        double integrator with that bound, T = (-s*v + 2 sqrt(s*a*d + v^2/2)) / a for a = kappa + 1,
        d = theta* - theta0, v = omega0, s = +1 when d > v|v|/(2a) (first accelerating), else -1. It
        grows with the distance of theta* from the stopping point theta0 + v|v|/(2a) on either side,
        so on the circle the least is at the branches nearest that point (not those nearest theta0: a
        fast start stops many turns away). The direct transcriptions bound T below by half of it."""
        a = self.kappa + 1
        theta0, omega0 = self.x0
        stop = theta0 + omega0 * abs(omega0) / (2 * a)
        k0 = self.nearest_branch(stop) if self.branch is None else self.branch
        best = math.inf
        for k in ([k0] if self.branch is not None else range(k0 - 1, k0 + 2)):
            d = self.target(k)[0] - theta0
            s = 1.0 if d > omega0 * abs(omega0) / (2 * a) else -1.0
            best = min(best, (-s * omega0 + 2 * math.sqrt(max(0.0, s * a * d + omega0**2 / 2))) / a)
        return best

    @cached_property
    def lower_bound(self):
        """A lower bound of the minimum time, the larger of `double_integrator_bound` and the energy's:
        `transit` from x0 (F = sqrt(omega^2 + 4 sin^2(theta/2)) changes at |dF/dt| <= kappa; a start
        moving away from the target turns first, and a target behind the turn is reached over the way
        back: `transit` states the argument). At small kappa the energy's is the larger: 2/kappa from
        rest to the upright, 480 from (0, 50) at kappa = 0.1 (the optimum 488.6); from (1.473, 22.78)
        to branch -2 at kappa = 0.41, 630 rad behind the turn: 120.7 (the optimum 128.1; 50.8 without
        the turn)."""
        theta0, omega0 = self.x0
        e0 = 0.5 * omega0 * omega0 - math.cos(theta0)
        return max(self.double_integrator_bound, self.transit(theta0, theta0, e0, e0, math.copysign(1.0, omega0)))

    def gap(self, lo, hi):
        """The distance from [lo, hi] to the nearest allowed target angle, 0 if one lies in it (or lo, hi
        are not finite)."""
        if not math.isfinite(lo + hi):
            return 0.0
        if self.branch is not None:
            target = self.target(self.branch)[0]
            return max(lo - target, target - hi, 0.0)
        below = self.base + 2 * math.pi * math.floor((hi - self.base) / (2 * math.pi))   # the last target <= hi
        return 0.0 if below >= lo else min(lo - below, below + 2 * math.pi - hi)

    def transit(self, lo, hi, e_lo, e_hi, sign=0.0):
        """A lower bound of the time from a state with theta in [lo, hi], e = omega^2/2 - cos(theta) in
        [e_lo, e_hi] and omega of sign `sign` (0: either) to an arrival (at rest on an allowed target,
        F* = 2 |sin(theta*/2)|) after it (run backwards in time, the same with -sign bounds the time
        from an arrival before it). e changes at de/dt = kappa u omega, so F = sqrt(2 (e + 1)) =
        sqrt(omega^2 + 4 sin^2(theta/2)) >= |omega| changes at |dF/dt| <= kappa.
        One way: `least_transit` over the gap to the nearest target. A state moving away (e > 1) turns
        first, where e = -cos(theta) <= 1, and e changes at |de/dtheta| = kappa |u| <= kappa on the way,
        so the turn is at least reach = (e_lo - 1) / kappa on, braking to F <= 2 (`least_transit` over
        the reach from F_lo, (F_lo - 2) / kappa: the least over [F_lo, F_hi]); the arrival, at rest, is
        the first turning point only on a target past it, so a target behind the turn is reached over
        the way back from it too. On the circle, the least over the branches, relaxed: min(one way to
        the first branch at or past the turn, max(one way to the nearest, way back from the last branch
        before the turn)) (the one way grows with the distance from the state, the way back with the
        distance from the turn)."""
        kappa, f_target = self.kappa, 2 * abs(math.sin(self.base / 2))
        if not math.isfinite(lo + hi + e_lo + e_hi):
            return least_transit(kappa, self.gap(lo, hi), 0.0, math.inf, f_target)
        f_lo, f_hi = math.sqrt(2 * max(e_lo + 1, 0.0)), math.sqrt(2 * max(e_hi + 1, 0.0))
        nearest = least_transit(kappa, self.gap(lo, hi), f_lo, f_hi, f_target)
        reach = max(0.0, (e_lo - 1) / kappa) if sign else 0.0
        if reach == 0.0:
            return nearest
        turn = (lo if sign > 0 else hi) + sign * reach        # the first turning point is at or past it
        first = least_transit(kappa, reach, 0.0, 2.0, f_lo)

        def back(target):                   # a target before the turn: the way to it and back
            return max(nearest, first + least_transit(kappa, sign * (turn - target), 0.0, 2.0, f_target))

        if self.branch is not None:
            target = self.target(self.branch)[0]
            return back(target) if sign * (target - turn) < 0 else nearest
        past = math.ceil if sign > 0 else math.floor
        beyond = past((turn - self.base) / (2 * math.pi))     # the first branch at or past the turn
        one_way = least_transit(kappa, max(0.0, sign * (self.target(beyond)[0] - (hi if sign > 0 else lo))),
                                f_lo, f_hi, f_target)
        return min(one_way, back(self.target(beyond - int(sign))[0]))

    def describe(self):
        """One line: kind, kappa, start, target set and reading."""
        target = (f"any branch of ({angle_text(self.base)} + 2 pi k, 0) (on the circle)" if self.branch is None
                  else f"({angle_text(self.target(self.branch)[0])}, 0) (on the plane, branch k = {self.branch} pinned)")
        return (f"{self.kind}, kappa = {self.kappa:g}, from (theta, omega) = ({self.x0[0]:.6g}, {self.x0[1]:.6g}) "
                f"to {target}")

    def to_dict(self):
        return asdict(self)


def transit_time(kappa, d, f_from, f_to):
    """A lower bound of the time to cover an angle d >= 0 while F = sqrt(omega^2 + 4 sin^2(theta/2)) goes from
    f_from to f_to, where |dF/dt| <= kappa and |omega| <= F: at least |f_to - f_from| / kappa, and the
    angle covered is at most the integral of min(f_from + kappa t, f_to + kappa (T - t)) =
    kappa T^2/4 + S T/2 - D^2/(4 kappa) (S = f_from + f_to, D = f_to - f_from), so
    T >= (sqrt(S^2 + D^2 + 4 kappa d) - S) / kappa. Symmetric in its ends."""
    total, change = f_from + f_to, f_to - f_from
    return max(abs(change), math.sqrt(total * total + change * change + 4 * kappa * max(d, 0.0)) - total) / kappa


def least_transit(kappa, d, f_lo, f_hi, f_to):
    """The least of `transit_time` over f_from in [f_lo, f_hi]: it falls with f_from up to
    sqrt(f_to^2 + 2 kappa d), where its two bounds meet, and rises after, so it is there, clamped."""
    f = min(max(math.sqrt(f_to * f_to + 2 * kappa * max(d, 0.0)), f_lo), f_hi)
    return transit_time(kappa, d, f, f_to)


def angle_text(theta):
    """theta as a multiple of pi where it is one (pi, -3*pi, 0), else 6 significant digits."""
    k = theta / math.pi
    if abs(k - round(k)) < 1e-12:
        return {0: "0", 1: "pi", -1: "-pi"}.get(round(k), f"{round(k)}*pi")
    return f"{theta:.6g}"


def make(kind, kappa, x0=None, branch=None):
    """The problem `kind` (a key of KINDS) from x0 (default: its standard start)."""
    if kind not in KINDS:
        raise InputError(f"unknown problem {kind!r}; accepted: {', '.join(KINDS)}")
    return Problem(kind, kappa, KINDS[kind].start if x0 is None else x0, branch)


def swing_up(kappa, x0=None, branch=None):
    """Minimum-time swing-up from x0 (default (0, 0), hanging at rest) to the upright (pi + 2*pi*k, 0)."""
    return make("swing-up", kappa, x0, branch)


def damping(kappa, x0=None, branch=None):
    """Minimum-time damping from x0 (default (pi, 0), upright at rest) to the hanging (2*pi*k, 0)."""
    return make("damping", kappa, x0, branch)
