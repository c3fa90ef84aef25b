"""The exact side of the torque-limited pendulum (Finch 2015, "Swing-up control of a pendulum").

Convention of `ocp.model`: theta'' + sin(theta) = kappa*u, |u| <= 1, x = (theta, omega), theta = 0
hanging, theta = pi upright. On an arc of constant u the invariant omega^2/2 - cos(theta) -
kappa*u*theta gives

    omega(theta)^2 = W(theta) = omega_a^2 + 2*[cos(theta) - cos(a) + kappa*u*(theta - a)]
                              = omega_a^2 + 2*(theta - a)*q_a(theta),
    q_a(theta) = kappa*u - sin((theta + a)/2) * sinc((theta - a)/2),     sinc(z) = sin(z)/z,

for any point (a, omega_a) of the arc; the product form has no cancellation as theta -> a.
Every arc time is a quadrature of dt = |dtheta|/sqrt(W); where the pendulum is at rest (W = 0 at an
end) the integrand has an inverse-square-root singularity, removed analytically by the substitution
theta = a + L*sin^2(phi/2) (L the arc length), under which the integrand is analytic and
Gauss-Legendre converges exponentially. Accuracy: relative error of every time below 1e-15 against
mpmath at 30 digits (tests/test_analytic.py).

The motion is reversible (t -> -t, omega -> -omega, same u) and mirror-symmetric (theta -> 2*pi*k -
theta, omega -> -omega, u -> -u): damping from (pi, 0) to (0, 0) is swing-up run backwards, and the
transfers to -pi (or from -pi) are mirror images.
"""

import math
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipk, sici

from .verify import Reproduction

EPS = np.finfo(float).eps
_KINDS = {"swing-up": ((0.0, 0.0), (math.pi, 0.0)), "damping": ((math.pi, 0.0), (0.0, 0.0))}


# --- quadrature ---------------------------------------------------------------------------------

@lru_cache(maxsize=None)
def _legendre(n):
    return np.polynomial.legendre.leggauss(n)


def _gauss(f, a, b, n_max=1 << 15):
    """(integral of the analytic, vectorised f over [a, b], error estimate): Gauss-Legendre with
    n = 16, 32, ... nodes until two successive values agree to 4 eps; the estimate is their
    difference plus the rounding of the sum (16 eps |value|)."""
    previous = None
    n = 16
    while n <= n_max:
        x, w = _legendre(n)
        value = 0.5 * (b - a) * np.dot(w, f(0.5 * (b - a) * x + 0.5 * (a + b)))
        if previous is not None and abs(value - previous) <= 4 * EPS * abs(value):
            return float(value), abs(value - previous) + 16 * EPS * abs(value)
        previous, n = value, 2 * n
    raise ArithmeticError("quadrature did not converge: the arc passes too close to a rest point")


def _q(a, d, u, kappa):
    """q_a(a + d) = (W(a + d) - W(a)) / (2d) = kappa*u - sin(a + d/2) * sinc(d/2)."""
    return kappa * u - np.sin(a + 0.5 * d) * np.sinc(d / (2 * np.pi))


def _half(a, w2, length, u, kappa):
    """Time from a (where omega^2 = w2) to the midpoint a + length/2 of an arc of constant u:
    with theta = a + length*s^2, s = sin(phi/2), phi in [0, pi/2],
        t = int_0^{pi/2} |length| cos(phi/2) / sqrt(w2/s^2 + 2*length*q_a(theta)) dphi."""
    def integrand(phi):
        s, c = np.sin(0.5 * phi), np.cos(0.5 * phi)
        r = w2 / s**2 + 2 * length * _q(a, length * s**2, u, kappa)
        if np.any(r <= 0):
            raise ValueError("the arc comes to rest before it reaches theta")
        return abs(length) * c / np.sqrt(r)
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
    k = math.sin(theta0 / 2)
    t = float(ellipk(k * k))
    return Arrival(t, -2 * k, 4 * EPS * t)


# --- the one-switch transfer --------------------------------------------------------------------

def one_switch_bound():
    """kappa_1 = 0.7246113537...: the root of 1 - pi*kappa + sqrt(1 - kappa^2) + kappa*arcsin(kappa)
    = 0, i.e. of min_{0 < phi < pi} [cos(phi) - 1 + kappa*phi] = 0 (the minimum is at
    phi = pi - arcsin(kappa)): for kappa <= kappa_1 the u = +1 arc from (0, 0) comes to rest
    before pi/2 + 1/kappa. g'(kappa) = arcsin(kappa) - pi, so the root is well conditioned."""
    return brentq(lambda k: 1 - math.pi * k + math.sqrt(1 - k * k) + k * math.asin(k), 0.5, 1.0,
                  xtol=1e-17, rtol=4 * EPS)


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
    if kind not in _KINDS:
        raise ValueError(f"unknown kind {kind!r}; accepted: {', '.join(_KINDS)}")


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
    bb = BangBang("swing-up", kappa, _KINDS["swing-up"][0], _KINDS["swing-up"][1], +1, (up.t,),
                  ((theta1, omega1),), up.t + down.t, error=up.error + down.error + 8 * EPS * omega1)
    return bb if kind == "swing-up" else _reversed(bb)
