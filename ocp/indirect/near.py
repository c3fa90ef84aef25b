"""The transfer from a start at the edge of the target, in closed form: the offset from a branch
theta* = n pi (n = 2k for damping, 2k + 1 for swing-up) of at most NEAR_SCALE in length.

There the scan of the costate angle cannot work: an extremal that arrives in a tiny time T has its
costate angle within about T of an end of its admissible interval, below the resolution of an
angle near pi, and the float target angle differs from n pi by rounding. The transfer is solved
in the offset x = theta - theta* instead (x0 computed with pi in two parts, so that it is exact to
rounding where theta* is not a float; x0 = 0 when theta0 is the target angle to rounding,
`Problem.on_target_angle`, as for a start on the target). Exactly,

    x'' = kappa u - c sin x,   c = cos(theta*) = +1 (hanging) or -1 (upright).

Scaled by V = max(|omega0|, sqrt(kappa |x0|)), tau = V / kappa, L = V tau (x = L xi, omega = V eta,
t = tau s), its linear part is xi'' = u - c eps xi, eps = tau^2, whose flow over s under u is

    xi = C xi0 + S eta0 + F u,   eta = -c eps S xi0 + C eta0 + S u,

C = cos(w s), S = sin(w s) / w, F = (1 - C) / eps, w = sqrt(eps) (cosh and sinh for c = -1); the
rest, c (x - sin x), at most X^3 / 6 for X = max |x| on the transfer, is a force perturbation of
relative size delta = X^3 / (6 kappa).

Why it is the global answer: zeros of p2 on an extremal are at least pi apart (p2'' = -cos(theta)
p2, Sturm comparison with cos(theta) <= 1), so an extremal with T < pi has at most one switch:
u = s for t1 >= 0, then -s for t2 >= 0. For each order s the two equations x(T) = (0, 0) of the
linear field are solved by Newton from the double integrator's solution (t1 = -s eta0 + r, t2 = r,
r = sqrt(eta0^2 / 2 - s xi0), its only one with r >= 0), O(eps) away; the least T of the two orders
is the answer. Residual assumption: no other solution of either order with t1 + t2 <= T (the
double integrator has none, and the field differs from it by O(eps + delta) on that time). The
other branches are excluded by the least time over 2 pi - |x0| with |theta''| <= kappa + 1 (the
circle). The closed form applies when L <= NEAR_SCALE and T is below pi / 2 and half that bound.

Its error estimate: ROUNDING eps T for the rounding of the closed form, Newton's last step, and
2 delta T for the perturbation (the least time of a double integrator changes by less than the
relative change of its bound: T ~ a^(-1/2) to a^(-1)), and the least subnormal (T may underflow).
Below the speed scale MIN_SPEED the answer is T = 0, its error the bound 3.5 tau of the double
integrator's time (T = tau (-s eta0 + 2 sqrt(eta0^2 / 2 - s xi0)), |xi0|, |eta0| <= 1).
"""

import math
from fractions import Fraction

EPS = 2.220446049250313e-16
#: the closed form applies when the transfer's length scale V^2 / kappa is at most this (rad)
NEAR_SCALE = 1e-5
#: pi - float(pi)
PI_LO = 1.2246467991473532e-16
#: rounding of the closed form, in units of eps T
ROUNDING = 32
TINY = 5e-324
#: below this speed scale V the answer is T = 0 with an error bound (p(0) ~ 1/V would overflow)
MIN_SPEED = 1e-300


def _flow(c, eps, u, s, xi, eta):
    """(xi, eta, C, S) after the scaled time s under u from (xi, eta): xi'' = u - c eps xi."""
    h = math.sqrt(eps) * s
    if c > 0:
        C, sinc, half = math.cos(h), math.sin(h) / h if h else 1.0, math.sin(h / 2) / (h / 2) if h else 1.0
    else:
        C, sinc, half = math.cosh(h), math.sinh(h) / h if h else 1.0, math.sinh(h / 2) / (h / 2) if h else 1.0
    S, F = s * sinc, 0.5 * s * s * half * half
    return C * xi + S * eta + F * u, -c * eps * S * xi + C * eta + S * u, C, S


def _order(c, eps, s, xi0, eta0):
    """(t1, t2, last Newton step) of the arcs u = s, then -s, from (xi0, eta0) to (0, 0) in the
    linear field (scaled), from the double integrator's solution; None if it has none."""
    disc = 0.5 * eta0 * eta0 - s * xi0
    if disc < 0:
        return None
    r = math.sqrt(disc)
    t1, t2, step = -s * eta0 + r, r, 0.0
    for _ in range(40):
        xs, es, _, _ = _flow(c, eps, s, t1, xi0, eta0)
        xe, ee, C2, S2 = _flow(c, eps, -s, t2, xs, es)
        # columns: d(end)/dt1 = the flow's derivative applied to the field at the switch,
        # d(end)/dt2 = the field at the end
        fx, fe = es, s - c * eps * xs
        a, b = C2 * fx + S2 * fe, ee
        d, e = -c * eps * S2 * fx + C2 * fe, -s - c * eps * xe
        det = a * e - b * d
        if det == 0:
            return None
        d1, d2 = (xe * e - b * ee) / det, (a * ee - d * xe) / det
        t1, t2, step = t1 - d1, t2 - d2, abs(d1) + abs(d2)
        if step <= 4 * EPS * (abs(t1) + abs(t2)):
            break
    return t1, t2, step


def transfer(problem):
    """(branch, T, signs, switch_times, switch_states, p0, error) of the least-time transfer from a
    start at the target's edge (error: of T and of the switch time), or None where the closed form
    does not apply."""
    theta0, omega0 = problem.x0
    kappa = problem.kappa
    k = problem.nearest_branch(theta0) if problem.branch is None else problem.branch
    n = round(problem.target(k)[0] / math.pi)
    c = 1 if n % 2 == 0 else -1
    x0 = 0.0 if problem.on_target_angle(k) else float(Fraction(theta0) - n * Fraction(math.pi)) - n * PI_LO
    V = max(abs(omega0), math.sqrt(kappa * abs(x0)))
    tau = V / kappa
    if V == 0 or V * tau > NEAR_SCALE:
        return None
    if V < MIN_SPEED:           # the costate normalised by H = 0 would overflow; T <= 3.5 tau
        return k, 0.0, (), (), (), (math.nan, math.nan), 3.5 * tau + TINY
    xi0, eta0, eps = (x0 / V) * (kappa / V) if x0 else 0.0, omega0 / V, tau * tau
    best = None
    for s in (1, -1):
        solved = _order(c, eps, s, xi0, eta0)
        if solved is None:
            continue
        t1, t2, step = solved
        slack = ROUNDING * EPS * (abs(t1) + abs(t2))
        if min(t1, t2) < -slack:
            continue
        clamp = max(0.0, -t1) + max(0.0, -t2)
        t1, t2 = max(t1, 0.0), max(t2, 0.0)
        if best is None or t1 + t2 < best[1] + best[2]:
            best = (s, t1, t2, step + clamp)
    if best is None:
        return None
    s, t1, t2, step = best
    T = tau * (t1 + t2)
    bound = math.inf
    if problem.branch is None:
        a, D = kappa + 1, 2 * math.pi - abs(x0)
        bound = (math.sqrt(omega0 * omega0 + 2 * a * D) - abs(omega0)) / a
    if not T < min(math.pi, bound) / 2:
        return None
    X = V * tau * (abs(xi0) + abs(eta0) * (t1 + t2) + (t1 + t2) ** 2)
    delta = X ** 3 / (6 * kappa)
    T_error = ROUNDING * EPS * T + tau * step + 2 * delta * T + TINY
    target = problem.target(k)[0]
    if t1 > 0 and t2 > 0:
        xs, es, _, _ = _flow(c, eps, s, t1, xi0, eta0)
        signs, times, states = (s, -s), (tau * t1,), ((target + V * xs * tau, V * es),)
    else:
        signs, times, states = ((s,) if t2 == 0 else (-s,)), (), ()
    # the costate: p2'' = -c p2 (cos(theta) = c to O(X^2)), p2(t1) = 0, scaled by H = 0 at t = 0
    t = tau * t1 if len(signs) == 2 else 0.0
    ratio = math.tan(t) if c > 0 else math.tanh(t)
    p1 = 1.0 / (omega0 + ratio * (kappa * signs[0] - c * math.sin(x0)))
    return k, T, signs, times, states, (p1, ratio * p1), T_error
