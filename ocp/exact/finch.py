"""The exact side of the torque-limited pendulum (Finch 2015, "Swing-up control of a pendulum").

Convention of `ocp.core.model`: theta'' + sin(theta) = kappa*u, |u| <= 1, x = (theta, omega), theta = 0
hanging, theta = pi upright. On an arc of constant u the invariant omega^2/2 - cos(theta) -
kappa*u*theta gives

    omega(theta)^2 = W(theta) = omega_a^2 + 2*[cos(theta) - cos(a) + kappa*u*(theta - a)]
                              = omega_a^2 + 2*(theta - a)*q_a(theta),
    q_a(theta) = kappa*u - sin((theta + a)/2) * sinc((theta - a)/2),     sinc(z) = sin(z)/z,

for any point (a, omega_a) of the arc; the product form has no cancellation as theta -> a.
Every arc time is a quadrature of dt = |dtheta|/sqrt(W); where the pendulum is at rest (W = 0 at an
end) the integrand has an inverse-square-root singularity, removed analytically by the substitution
theta = a + L*sin^2(phi/2) (L the arc length), under which the integrand is analytic and
Gauss-Legendre converges exponentially. Accuracy: relative error of the times below 1e-15 against
mpmath at 30 digits (tests/test_analytic.py; observed <= 2e-16); every time comes with an error
bound, which grows where an arc nearly comes to rest inside (kappa -> 0.7246... for one switch),
because W itself then suffers cancellation.

The motion is reversible (t -> -t, omega -> -omega, same u) and mirror-symmetric (theta -> 2*pi*k -
theta, omega -> -omega, u -> -u): damping from (pi, 0) to (0, 0) is swing-up run backwards, and the
transfers to -pi (or from -pi) are mirror images.
"""

import math
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from ..core.cache import cached
from ..core.problem import KINDS
from ..core.roots import brent, minimum

EPS = np.finfo(float).eps


def _ends(kind):
    """(start, target) of the standard transfer of `kind` (`ocp.core.problem.KINDS`)."""
    return KINDS[kind].start, (KINDS[kind].target_base, 0.0)


# --- quadrature ---------------------------------------------------------------------------------

#: Gauss-Legendre nodes and weights with 32 and 64 nodes on [-1, 1], the nodes side by side (one call of
#: the integrand evaluates both rules)
_WEIGHTS = [np.polynomial.legendre.leggauss(n)[1] for n in (32, 64)]
_NODES = np.concatenate([np.polynomial.legendre.leggauss(n)[0] for n in (32, 64)])


def _gauss(f, a, b, depth=0):
    """(integral over [a, b], error bound) of an analytic integrand; f(x) returns the values and a
    bound on their rounding errors. Gauss-Legendre with 32 and 64 nodes, accepted when they agree
    to 1e-11 of int |f| (the 64-node truncation error is then of the order of the square of that,
    far below rounding) or to twice the rounding bound, else the interval is halved; the error
    bound is the 32-64 difference squared over int |f|, plus the integrated rounding bound, plus
    4 eps int |f| for the sum."""
    y, dy = f(0.5 * (b - a) * _NODES + 0.5 * (a + b))
    h = 0.5 * abs(b - a)
    (w32, w64), n = _WEIGHTS, len(_WEIGHTS[0])
    coarse = math.copysign(h, b - a) * np.dot(w32, y[:n])
    value, size, rounding = math.copysign(h, b - a) * np.dot(w64, y[n:]), h * np.dot(w64, np.abs(y[n:])), \
        h * np.dot(w64, dy[n:])
    if abs(value - coarse) <= max(1e-11 * size, 2 * rounding):
        return float(value), float((value - coarse) ** 2 / size + rounding + 4 * EPS * size)
    if depth == 40:
        raise ArithmeticError("quadrature did not converge: the arc passes too close to a rest point")
    m = 0.5 * (a + b)
    (v1, e1), (v2, e2) = _gauss(f, a, m, depth + 1), _gauss(f, m, b, depth + 1)
    return v1 + v2, e1 + e2


def _q(a, d, u, kappa):
    """q_a(a + d) = (W(a + d) - W(a)) / (2d) = kappa*u - sin(a + d/2) * sinc(d/2)."""
    return kappa * u - np.sin(a + 0.5 * d) * np.sinc(d / (2 * np.pi))


def _half(a, w2, length, u, kappa):
    """Time from a (where omega^2 = w2) to the midpoint a + length/2 of an arc of constant u:
    with theta = a + length*s^2, s = sin(phi/2), phi in [0, pi/2],
        t = int_0^{pi/2} |length| cos(phi/2) / sqrt(w2/s^2 + 2*length*q_a(theta)) dphi.
    Returns (t, error bound); the rounding of the integrand is bounded by 4 eps times the size of
    the radicand's terms, w2/s^2 + 2|length|(kappa|u| + 1), over the radicand."""
    def integrand(phi):
        s, c = np.sin(0.5 * phi), np.cos(0.5 * phi)
        r = w2 / s**2 + 2 * length * _q(a, length * s**2, u, kappa)
        if np.any(r <= 0):
            raise ValueError("the arc comes to rest before it reaches theta")
        y = abs(length) * c / np.sqrt(r)
        return y, 4 * EPS * y * (w2 / s**2 + 2 * abs(length) * (kappa * abs(u) + 1)) / r
    return _gauss(integrand, 0.0, 0.5 * math.pi)


class Arrival(NamedTuple):
    """Time t and velocity omega on arrival at theta, and a bound on the error of t."""

    t: float
    omega: float
    error: float


def arc(u, theta0, omega0, t0, kappa, theta):
    """Finch's T_u(theta0, omega0, t0, kappa; theta), u in {+1, -1} (T+, T-) or 0 (free swing):

        T_u = t0 + | int_{theta0}^{theta} dphi / sqrt(W(phi)) |,
        W(phi) = omega0^2 + 2*[cos(phi) - cos(theta0) + kappa*u*(phi - theta0)],

    and the velocity on arrival omega = sign(theta - theta0)*sqrt(W(theta)). The arc must move
    monotonically from theta0 to theta (omega0 of the sign of theta - theta0, or omega0 = 0 with
    the acceleration pointing to theta); else ValueError. An end with |W| within rounding of 0
    (32 eps times the size of the terms of W) is a rest point and is treated as exactly at rest,
    e.g. T_-(pi/2 + 1/kappa, sqrt(kappa*pi - 2 sin(1/kappa)), t1, kappa; pi) arrives at rest.
    Both halves of the arc are integrated from their own end (theta = end + L sin^2(phi/2)),
    which removes the singularity 1/sqrt(W) at a rest point analytically."""
    length = theta - theta0
    if length == 0:
        return Arrival(float(t0), float(omega0), 0.0)
    if omega0 * length < 0:
        raise ValueError(f"omega0 = {omega0} moves away from theta = {theta}")
    w2 = omega0**2 + 2 * length * _q(theta0, length, u, kappa)
    if abs(w2) <= 32 * EPS * (omega0**2 + 2 + 2 * kappa * abs(u) * (abs(theta0) + abs(theta))):
        w2 = 0.0
    if w2 < 0:
        raise ValueError(f"the arc comes to rest before it reaches theta = {theta}")
    first, e1 = _half(theta0, omega0**2, length, u, kappa)
    second, e2 = _half(theta, w2, -length, u, kappa)
    return Arrival(t0 + first + second, math.copysign(math.sqrt(w2), length), float(e1 + e2))


def free_swing(theta0):
    """Swing u = 0 from rest at theta0 in (0, pi) to the bottom: t = K(k) (quarter period, the
    complete elliptic integral with modulus k = sin(theta0/2), scipy's parameter m = k^2) and
    omega = -2 sin(theta0/2). theta0 = pi/2: K(1/sqrt 2) = Gamma(1/4)^2/(4 sqrt(pi)), -sqrt(2)."""
    from scipy.special import ellipk

    k = math.sin(theta0 / 2)
    t = float(ellipk(k * k))
    return Arrival(t, -2 * k, 4 * EPS * t)


# --- the one-switch transfer --------------------------------------------------------------------

def one_switch_bound():
    """kappa_1 = 0.7246113537...: the root of 1 - pi*kappa + sqrt(1 - kappa^2) + kappa*arcsin(kappa)
    = 0, i.e. of min_{0 < phi < pi} [cos(phi) - 1 + kappa*phi] = 0 (the minimum is at
    phi = pi - arcsin(kappa)): for kappa <= kappa_1 the u = +1 arc from (0, 0) comes to rest
    before pi/2 + 1/kappa. g'(kappa) = arcsin(kappa) - pi, so the root is well conditioned."""
    return brent(lambda k: 1 - math.pi * k + math.sqrt(1 - k * k) + k * math.asin(k), 0.5, 1.0, 1e-17)


@dataclass(frozen=True)
class BangBang:
    """A bang-bang transfer from x0 to target: u = first_u, then alternating at the switch_times
    t_1 < t_2 < ... in the switch_states (theta_i, omega_i), arriving at time T. rho is the turning
    point (rho, 0) of the middle arc of a two-switch transfer (None otherwise); error bounds the
    absolute error of every time and state."""

    kind: str
    kappa: float
    x0: tuple
    target: tuple
    first_u: int
    switch_times: tuple
    switch_states: tuple
    T: float
    rho: float | None = None
    error: float = 0.0

    @property
    def n_switches(self):
        return len(self.switch_times)


def _check_kind(kind):
    if kind not in KINDS:
        raise ValueError(f"unknown kind {kind!r}; accepted: {', '.join(KINDS)}")


def _reversed(bb):
    """The same motion backwards in time: t -> T - t, omega -> -omega, u(t) -> u(T - t)."""
    kind = "damping" if bb.kind == "swing-up" else "swing-up"
    return replace(bb, kind=kind, x0=bb.target, target=bb.x0, first_u=bb.first_u * (-1) ** bb.n_switches,
                   switch_times=tuple(bb.T - t for t in reversed(bb.switch_times)),
                   switch_states=tuple((th, -om) for th, om in reversed(bb.switch_states)))


def one_switch(kind, kappa):
    """The one-switch transfer (Finch 2015, Figure 1). Swing-up (0, 0) -> (pi, 0): u = +1 on
    omega^2 = 2[cos(theta) - 1 + kappa*theta] until it meets the u = -1 arc into (pi, 0),
    omega^2 = 2[cos(theta) + 1 + kappa*(pi - theta)], at

        (theta1, omega1) = (pi/2 + 1/kappa, sqrt(kappa*pi - 2 sin(1/kappa))),
        t1 = T_+(0, 0, 0, kappa; theta1),    T = t1 + T_-(pi, 0, 0, kappa; theta1).

    Damping (pi, 0) -> (0, 0) is its time reversal: u = -1 until (theta1, -omega1) at T - t1, then
    u = +1. Exists iff kappa > one_switch_bound() = 0.7246...; else ValueError."""
    _check_kind(kind)
    bound = one_switch_bound()
    if not kappa > bound:
        raise ValueError(f"no one-switch {kind} for kappa = {kappa}: it needs kappa > {bound!r} "
                         f"(the u = +1 arc from (0, 0) comes to rest at pi - arcsin(kappa))")
    theta1 = math.pi / 2 + 1 / kappa
    omega1 = math.sqrt(kappa * math.pi - 2 * math.sin(1 / kappa))
    up, down = arc(+1, 0.0, 0.0, 0.0, kappa, theta1), arc(-1, math.pi, 0.0, 0.0, kappa, theta1)
    bb = BangBang("swing-up", kappa, *_ends("swing-up"), +1, (up.t,),
                  ((theta1, omega1),), up.t + down.t, error=float(up.error + down.error + 8 * EPS * omega1))
    return bb if kind == "swing-up" else _reversed(bb)


# --- the two-switch swing-up (Finch 2015, Addendum; Reshmin and Chernousko 2014) -----------------

def xi(rho, kappa):
    """xi(rho) = rho/2 + (cos(rho) - 1)/(2 kappa): where the u = -1 arc from (0, 0),
    omega^2 = 2[cos(theta) - 1 - kappa*theta], meets the u = +1 arc through (rho, 0)."""
    return rho / 2 + (math.cos(rho) - 1) / (2 * kappa)


def eta(rho, kappa):
    """eta(rho) = xi(rho) + pi/2 + 1/kappa: where the u = +1 arc through (rho, 0) meets the u = -1
    arc into (pi, 0), omega^2 = 2[cos(theta) + 1 + kappa*(pi - theta)]."""
    return xi(rho, kappa) + math.pi / 2 + 1 / kappa


def F(u, rho, kappa):
    """F(u, rho) = sqrt(2 kappa (u - rho) + 2[cos(u) - cos(rho)]) = |omega| on the u = +1 arc through
    (rho, 0). The paper prints sqrt(-2 kappa (u - rho) - 2[cos(u) - cos(rho)]), whose radicand is
    -omega^2 < 0 on the arc (see reproduce(), key two_switch_half_rho)."""
    d = u - rho
    return math.sqrt(2 * d * _q(rho, d, +1, kappa))


def three_arc_time(rho, kappa):
    """Total time of u = -1, +1, -1 from (0, 0) to (pi, 0) whose middle arc turns at (rho, 0):
    T(rho) = T_-(0, 0, 0, kappa; xi) + T_+(rho, 0, 0, kappa; xi) + T_+(rho, 0, 0, kappa; eta)
             + T_-(pi, 0, 0, kappa; eta)   (the last by reversibility: the arc into (pi, 0))."""
    x, e = xi(rho, kappa), eta(rho, kappa)
    return (arc(-1, 0.0, 0.0, 0.0, kappa, x).t + arc(+1, rho, 0.0, 0.0, kappa, x).t
            + arc(+1, rho, 0.0, 0.0, kappa, e).t + arc(-1, math.pi, 0.0, 0.0, kappa, e).t)


def stationarity_term(rho, x, kappa):
    """d/drho of T_+(rho, 0, 0, kappa; x) at fixed x > rho, with F = F(., rho):
        -1/F(x) + int_rho^x (sin(u) - sin(rho)) / F(u)^3 du;
    with u = rho + L sigma^2, L = x - rho, d = u - rho, F^2 = 2 d q_rho(u), the integral is
        int_0^1 sqrt(L/2) cos(rho + d/2) sinc(d/2) / q_rho(u)^(3/2) dsigma   (no singularity)."""
    length = x - rho

    def integrand(sigma):
        d = length * sigma**2
        q = _q(rho, d, +1, kappa)
        if np.any(q <= 0):
            raise ValueError("the middle arc comes to rest before it reaches x")
        y = math.sqrt(length / 2) * np.cos(rho + d / 2) * np.sinc(d / (2 * np.pi)) / q**1.5
        return y, 8 * EPS * np.abs(y) * (kappa + 1) / q
    integral, error = _gauss(integrand, 0.0, 1.0)
    return integral - 1 / F(x, rho, kappa), error + 4 * EPS / F(x, rho, kappa)


def stationarity(rho, kappa):
    """dT/drho of three_arc_time (the terms in d xi/d rho and d eta/d rho cancel, since the arcs
    meeting at xi and at eta have equal |omega| there):
        dT/drho = -1/F(xi) - 1/F(eta) + int_rho^xi (sin u - sin rho)/F^3 du
                  + int_rho^eta (sin v - sin rho)/F^3 dv.
    The paper prints 1/F(xi) + 1/F(eta) + int_xi^rho (sin rho - sin u)/F^3 du + (same at eta) = 0
    with its imaginary F = i|omega|: that is -i times this one, so both have the same root rho.
    Returns (value, error bound)."""
    (a, ea), (b, eb) = (stationarity_term(rho, x, kappa) for x in (xi(rho, kappa), eta(rho, kappa)))
    return a + b, ea + eb


def _feasible_rhos(kappa):
    """The open interval of turning points rho < 0 for which u = -1, +1, -1 joins (0, 0) to (pi, 0):
    the first arc has not come to rest before rho (cos(rho) - 1 - kappa*rho > 0, so xi > rho),
    and the middle arc from (rho, 0) passes the minimum of cos(theta) + kappa*theta at
    pi - arcsin(kappa) (cos(rho) + kappa*rho < kappa*(pi - arcsin(kappa)) - sqrt(1 - kappa^2)).
    For kappa > one_switch_bound() the first arc never rests in (-pi, 0) and the interval is
    (arcsin(kappa) - pi, 0). None if empty."""
    rho_min = math.asin(kappa) - math.pi
    if kappa > one_switch_bound():
        return rho_min, 0.0
    lo = brent(lambda r: math.cos(r) - 1 - kappa * r, rho_min, -kappa, 1e-17)
    hump = kappa * (math.pi - math.asin(kappa)) - math.sqrt(1 - kappa * kappa)
    if math.cos(lo) + kappa * lo >= hump:
        return None
    return lo, brent(lambda r: math.cos(r) + kappa * r - hump, lo, 0.0, 1e-17)


def _steepest(kappa, rising=False):
    """(rho, dT/drho) at the maximum of dT/drho over _feasible_rhos (None if empty); dT/drho -> -inf
    at the left end, and rises to +inf at the right end for kappa < one_switch_bound(), or falls
    back to -inf at rho = 0 above it. Located by bounded Brent to 1e-10 in rho. `rising`: the first
    point of that search where dT/drho > 0, if there is one (dT/drho > 0 only between the local
    minimum of T and its maximum or the right end: the right end of a bracket of that minimum)."""
    interval = _feasible_rhos(kappa)
    if interval is None:
        return None
    x, value = minimum(lambda r: -stationarity(r, kappa)[0], *interval, 1e-10, 0.0 if rising else None)
    return x, -value


def _two_switch_at(rho, kappa):
    """The u = -1, +1, -1 swing-up whose middle arc turns at (rho, 0): switches at
    (xi, -F(xi, rho)) at t1 = T_-(0, 0, 0, kappa; xi) and (eta, F(eta, rho)) at
    t2 = t1 + T_+(rho, 0, 0, kappa; xi) + T_+(rho, 0, 0, kappa; eta), arrival T = t2 + T_-(pi, 0, 0, kappa; eta)."""
    x, e = xi(rho, kappa), eta(rho, kappa)
    arcs = (arc(-1, 0.0, 0.0, 0.0, kappa, x), arc(+1, rho, 0.0, 0.0, kappa, x),
            arc(+1, rho, 0.0, 0.0, kappa, e), arc(-1, math.pi, 0.0, 0.0, kappa, e))
    t1 = arcs[0].t
    t2 = t1 + arcs[1].t + arcs[2].t
    return BangBang("swing-up", kappa, *_ends("swing-up"), -1, (t1, t2),
                    ((x, -F(x, rho, kappa)), (e, F(e, rho, kappa))), t2 + arcs[3].t, rho,
                    sum(a.error for a in arcs))


def two_switch(kind, kappa):
    """The two-switch transfer (Finch 2015, Figure 2 and Addendum). Swing-up (0, 0) -> (pi, 0):
    u = -1 to (xi, -F(xi, rho)), u = +1 through its turning point (rho, 0) to (eta, F(eta, rho)),
    u = -1 into (pi, 0), where rho is the local minimum of three_arc_time, the root of
    stationarity(rho) = dT/drho = 0 between the left end of _feasible_rhos (where dT/drho -> -inf
    as xi -> rho) and a point where dT/drho > 0 (`_steepest`).
    Damping (pi, 0) -> (0, 0) is its time reversal (same u sequence). Exists for
    two_switch_range()[0] < kappa < two_switch_range()[1] (0.42227... < kappa < 0.81534...); else ValueError.
    error bounds the quadratures and the propagated error of rho (|dT/drho error| / T'')."""
    _check_kind(kind)
    peak = _steepest(kappa, rising=True)
    if peak is None or peak[1] <= 0:
        low, high = two_switch_range()
        raise ValueError(f"no two-switch {kind} for kappa = {kappa}: three_arc_time has no local minimum "
                         f"(it has one for {low!r} < kappa < {high!r})")
    lo, rising = _feasible_rhos(kappa)[0], peak[0]
    a = next(a for a in lo + (rising - lo) * 0.1 ** np.arange(1, 17) if stationarity(a, kappa)[0] < 0)
    rho = brent(lambda r: stationarity(r, kappa)[0], a, rising, 1e-17)
    slope_error = stationarity(rho, kappa)[1]
    h = 0.5 * min(1e-4, rho - lo, rising - rho)
    curvature = (stationarity(rho + h, kappa)[0] - stationarity(rho - h, kappa)[0]) / (2 * h)
    drho = 2 * slope_error / curvature + 8 * EPS * abs(rho)
    bb, moved = _two_switch_at(rho, kappa), _two_switch_at(rho + drho, kappa)
    shift = max(abs(a - b) for a, b in zip(_flat(bb), _flat(moved)))
    bb = replace(bb, error=bb.error + shift)
    return bb if kind == "swing-up" else _reversed(bb)


def _flat(bb):
    """Switch times, switch states and T of bb, as one flat tuple."""
    return (*bb.switch_times, *(v for state in bb.switch_states for v in state), bb.T)


@cached
def two_switch_range():
    """(kappa_lo, kappa_hi) = (0.4222730599..., 0.8153495018...), the kappa for which three_arc_time has a
    local minimum. Below kappa_lo the feasible interval of rho is empty: the middle arc started at
    rest where the first arc comes to rest, cos(rho) - 1 = kappa*rho, no longer passes
    pi - arcsin(kappa) (one more swing is needed). At kappa_hi the minimum merges with a local
    maximum (a fold): max over rho of dT/drho = 0; above it only the one-switch transfer (rho = 0)
    remains. Both are roots found by Brent's method; kappa_hi's inner maximum is located to 1e-10 in rho,
    so its value is exact to rounding and kappa_hi to ~1e-13."""
    def gap(kappa):
        lo = brent(lambda r: math.cos(r) - 1 - kappa * r, math.asin(kappa) - math.pi, -kappa, 1e-17)
        return math.cos(lo) + kappa * lo - kappa * (math.pi - math.asin(kappa)) + math.sqrt(1 - kappa * kappa)

    return (brent(gap, 0.3, 0.6, 1e-16),
            brent(lambda k: _steepest(k)[1], 0.78, 0.9, 1e-14))


# --- solved results against the formulas ---------------------------------------------------------

def formula_for(problem, branch, n_switches, first_u):
    """The analytic transfer of `problem` (an ocp.core.problem.Problem) to target branch `branch` with
    the given structure, in the problem's own frame, or None where no formula applies. Formulas:
    one_switch and two_switch, from (0, 0) to (pi, 0) and from (pi, 0) to (0, 0), carried to
    x0 = (theta0, 0) and target theta_T by the symmetry theta = c + sigma*theta', omega =
    sigma*omega', u = sigma*u' with sigma = +-1 and c a multiple of 2*pi (so |theta_T - theta0| = pi,
    theta0 = 0 mod 2*pi for swing-up and pi mod 2*pi for damping, e.g. swing-up to -pi, damping from
    -pi); one switch needs kappa > one_switch_bound(), two switches (u' = -1, +1, -1)
    two_switch_range()."""
    start, end = (v[0] for v in _ends(problem.kind))
    theta0, omega0 = problem.x0
    sigma = (problem.target(branch)[0] - theta0) / (end - start)
    c = theta0 - sigma * start
    if abs(omega0) > 1e-12 or abs(abs(sigma) - 1) > 1e-12 or abs(c - 2 * math.pi * round(c / (2 * math.pi))) > 1e-9:
        return None
    sigma, c = round(sigma), 2 * math.pi * round(c / (2 * math.pi))
    canonical_u = sigma * first_u
    try:
        if n_switches == 1 and canonical_u == (1 if problem.kind == "swing-up" else -1):
            bb = one_switch(problem.kind, problem.kappa)
        elif n_switches == 2 and canonical_u == -1:
            bb = two_switch(problem.kind, problem.kappa)
        else:
            return None
    except ValueError:
        return None
    move = lambda state: (c + sigma * state[0] + 0.0, sigma * state[1] + 0.0)  # + 0.0: no -0.0
    return replace(bb, x0=move(bb.x0), target=move(bb.target), first_u=sigma * bb.first_u,
                   switch_states=tuple(move(x) for x in bb.switch_states),
                   rho=None if bb.rho is None else c + sigma * bb.rho)


@dataclass(frozen=True)
class Crosscheck:
    """A solved result against the formula for its structure: which formula, the analytic transfer
    (in the result's frame), the deviations result - analytic of the switch times, the switch
    states (theta, omega) and T, and the largest of them in absolute value."""

    formula: str
    analytic: BangBang
    switch_times: tuple
    switch_states: tuple
    T: float
    max_deviation: float


def crosscheck(problem, extremal):
    """Crosscheck of a solved extremal of `problem` (attributes branch, signs, switch_times,
    switch_states, T) against formula_for its problem, branch and structure; None where none
    applies."""
    bb = formula_for(problem, extremal.branch, len(extremal.signs) - 1, extremal.signs[0])
    if bb is None:
        return None
    times = tuple(t - a for t, a in zip(extremal.switch_times, bb.switch_times))
    states = tuple((x[0] - a[0], x[1] - a[1]) for x, a in zip(extremal.switch_states, bb.switch_states))
    T = extremal.T - bb.T
    name = f"{'one' if bb.n_switches == 1 else 'two'}-switch {bb.kind} (Finch 2015), kappa = {bb.kappa}"
    deviation = max(abs(v) for v in (*times, *(v for x in states for v in x), T))
    return Crosscheck(name, bb, times, states, T, deviation)


# --- constants ---------------------------------------------------------------------------------

def gibbs_constant():
    """G = int_0^pi sin(z)/z dz = Si(pi) = sum_j (-1)^j pi^(2j+1) / ((2j+1)(2j+1)!) = 1.8519370519...
    (scipy.special.sici); the damping bifurcation values behave like G/(2n) (Ovseevich 2014)."""
    from scipy.special import sici

    return float(sici(math.pi)[0])
