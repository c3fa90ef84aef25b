"""Free fall of an inverted pendulum (u = 0): Batista and Peternelj (2006), and the suite's
check of its integrators against the closed-form falling time.

The paper's convention: angle theta_p from the upright, dimensional time s (seconds), length L and
g, point mass (J = m L^2), so that L theta_p'' = g sin(theta_p); the pendulum falls from theta_p0
with speed omega_0 = theta_p'(0) >= 0 (away from the upright) until it hits the ground at
theta_p = pi/2. The falling time is (7)

    T(theta_p0, omega_0) = sqrt(L/(2g)) I(theta_p0, a),    a = (omega_0/2) sqrt(L/g)    (9)

    I(theta0, a) = int_theta0^(pi/2) dtheta / sqrt(2a^2 + cos(theta0) - cos(theta))     (8)

Conversion at this module's edge to the suite's convention (ocp.core.model, theta = 0 hanging down):

    theta = pi - theta_p,   t = sqrt(g/L) s,   omega = dtheta/dt = -omega_p sqrt(L/g),

so theta'' + sin(theta) = 0, the ground is theta = pi/2, a = -omega/2 and the nondimensional
falling time is I / sqrt(2) (`time_to_ground`).

I in closed form. With c = cos(theta0/2), s = sin(theta0/2) and k^2 = a^2 + c^2 (13), the paper
gives three cases in Legendre's form, F(x, k) = int_0^x du / sqrt((1 - u^2)(1 - k^2 u^2)) (27),
i.e. argument x = sin(phi) and modulus k, where scipy's `ellipkinc(phi, m)` takes the amplitude
phi = arcsin(x) and the parameter m = k^2:

    k < 1:  I = sqrt(2) [F(c/k, k) - F(1/(sqrt(2) k), k)]                               (16)
    k = 1:  I = sqrt(2) [ln(sqrt(2) - 1) - ln tan(theta0/4)]                            (21)
    k > 1:  I = (sqrt(2)/k) [F(c, 1/k) - F(1/sqrt(2), 1/k)]                             (23)

All three are checked in tests/test_falling.py. In Carlson's form F(x, k) = x RF(1 - x^2,
1 - k^2 x^2, 1), and RF being homogeneous of degree -1/2, the three cases are one expression,

    I = sqrt(2) [c RF(a^2, k^2 s^2, k^2) - RF(2k^2 - 1, k^2, 2k^2)],

whose arguments carry no cancellation (the Legendre arguments 1 - x^2 and 1 - k^2 lose all
relative accuracy as theta0 -> 0 or k -> 1); that is what `falling_integral` evaluates, to a few
units in the last place (tests: 30-digit mpmath quadrature, all three cases).

Formula slips in the paper (no printed number depends on them): in (12) the factor 1/sqrt(2k)
should be 1/(sqrt(2) k); the upper limit in (15) reads cos(theta0/2)/p for cos(theta0/2)/k; the
bound before (26) prints sqrt(hbar/(2 m L^2)) sqrt(L/g) for sqrt(hbar/(2 m L^2) sqrt(L/g)), which
(26) then uses correctly; (7) holds only for omega_0 >= 0 (I depends on a^2 alone, but a pendulum
started towards the upright first rises). Printed numbers that are wrong are in
ocp/papers/data/batista2006.toml with the evidence (`ocp.papers.batista2006`): Table 1's "Maple numerical" value for
pi/48, and the difference of (18) and (19), which is sqrt(2) ln 2, not ln 2.

Table 1's "Relative Error" column compares the paper's two Maple computations with each other (at
15 digits, below the 9 printed decimals), a property of that software run rather than of I; it is
not reproduced. Here the closed form and the quadrature agree to ~1e-16 at every theta0.
"""

import math

import casadi as ca
import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import elliprf

from ..core import model
from ..core.cache import cached
from ..core.errors import InputError

G = 9.8  #: m/s^2, the paper's g
HBAR = 1.05457e-34  #: J s, the paper's hbar
GROUND = math.pi / 2  #: the ground, in both conventions


def falling_integral(theta0, a=0.0):
    """I(theta0, a) of (8), 0 <= theta0 <= pi/2 (from the upright), any a; inf at (0, 0).

    Evaluated as sqrt(2) [c RF(a^2, k^2 s^2, k^2) - RF(2k^2 - 1, k^2, 2k^2)] (module docstring),
    valid in all three cases k < 1, k = 1, k > 1. Accepts numpy arrays."""
    theta0, a = np.asarray(theta0, float), np.asarray(a, float)
    if np.any((theta0 < 0) | (theta0 > GROUND)):
        raise InputError(f"theta0 = {theta0} must lie in [0, pi/2] (radians from the upright)")
    c, s = np.cos(theta0 / 2), np.sin(theta0 / 2)
    k2 = a * a + c * c
    with np.errstate(divide="ignore", invalid="ignore"):
        # 2k^2 - 1 written as 2a^2 + cos(theta0): no cancellation as theta0 -> pi/2
        return math.sqrt(2) * (c * elliprf(a * a, k2 * s * s, k2) - elliprf(2 * a * a + np.cos(theta0), k2, 2 * k2))


def falling_integral_quadrature(theta0, a=0.0):
    """(I(theta0, a), error estimate) by adaptive Gauss-Kronrod quadrature (scipy.integrate.quad),
    independent of the closed form: theta = theta0 + v^2 removes the inverse-square-root end point
    at a = 0, cos(theta0) - cos(theta) = 2 sin(theta0 + v^2/2) sin(v^2/2) keeps the integrand
    free of cancellation, and the v-interval is cut at 40 log-spaced points from the scale of the
    end point (sqrt(theta0), or a) up, so that near-singular cases (theta0 -> 0) are resolved.
    The error estimate is the sum of quad's estimates over the pieces."""
    import warnings

    from scipy.integrate import IntegrationWarning, quad

    theta0, a = float(theta0), float(a)
    end = math.sqrt(GROUND - theta0)
    if end == 0:
        return 0.0, 0.0

    def integrand(v):
        return 2 * v / math.sqrt(2 * a * a + 2 * math.sin(theta0 + v * v / 2) * math.sin(v * v / 2))

    scale = min(math.sqrt(theta0), a) if a > 0 else math.sqrt(theta0)
    if scale == 0:
        raise InputError("I(0, 0) is infinite: the pendulum at rest upright never falls")
    cuts = [v for v in np.geomspace(scale / 8, end, 40) if 0 < v < end] if scale / 8 < end else []
    edges = [0.0, *cuts, end]
    value, error = 0.0, 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)   # the estimate is what is used
        for lo, hi in zip(edges, edges[1:]):
            v, e = quad(integrand, lo, hi, epsabs=1e-16, epsrel=1e-14, limit=200)
            value, error = value + v, error + e
    return value, error


def falling_integral_checked(theta0, a=0.0):
    """(I(theta0, a) in closed form, its accuracy): the accuracy is the closed form's distance from
    the independent quadrature plus the quadrature's own error estimate (a bound of the closed
    form's error as long as quad's estimate holds; about 1e-13 here, while the closed form agrees
    with 30-digit mpmath to ~1e-15, tests/test_falling.py)."""
    closed = float(falling_integral(theta0, a))
    value, error = falling_integral_quadrature(theta0, a)
    return closed, abs(closed - value) + error


def asymptotic18(theta0):
    """(18): I(theta0, 0) ~ sqrt(2) [ln(8 (sqrt(2) - 1)) - ln(theta0)] as theta0 -> 0."""
    return math.sqrt(2) * (np.log(8 * (math.sqrt(2) - 1)) - np.log(theta0))


def asymptotic19(theta0):
    """(19): the same with cos(theta0) set to 1 in (8), sqrt(2) [ln(4 (sqrt(2) - 1)) - ln(theta0)];
    it is the k = 1 case (21) with tan(theta0/4) ~ theta0/4, so it misses (18) by sqrt(2) ln 2."""
    return math.sqrt(2) * (np.log(4 * (math.sqrt(2) - 1)) - np.log(theta0))


def falling_time(theta0, omega0=0.0, L=0.15, g=G):
    """T of (7) in seconds: from theta0 (rad from the upright) with omega0 >= 0 (rad/s, towards
    the ground), length L (m), gravity g (m/s^2), to the ground theta_p = pi/2."""
    if np.any(np.asarray(omega0) < 0):
        raise InputError(f"omega0 = {omega0} must be >= 0 (towards the ground); (7) does not hold otherwise")
    return math.sqrt(L / (2 * g)) * falling_integral(theta0, omega0 / 2 * math.sqrt(L / g))


def time_to_ground(x0):
    """Nondimensional time for the suite's pendulum theta'' + sin(theta) = 0 to fall from
    x0 = (theta, omega), pi/2 <= theta <= pi, omega <= 0, to the ground theta = pi/2:
    I(pi - theta, -omega/2) / sqrt(2)."""
    theta, omega = x0
    if omega > 0:
        raise InputError(f"omega = {omega} must be <= 0 (towards the ground at theta = pi/2)")
    return falling_integral(math.pi - theta, -omega / 2) / math.sqrt(2)


def uncertainty_time(L=0.1, m=0.001, g=G, hbar=HBAR):
    """The falling time (s) of the paper's uncertainty-principle example: k = 1 (omega0 =
    2 sin(theta0/2) sqrt(g/L), (25)) and omega0 sin(theta0) = hbar / (2 m L^2), (24) with equality.
    theta0 ~ 1e-15, so theta0^2 = hbar/(2 m L^2) sqrt(L/g) to double precision; T from (7), (8)."""
    theta0 = math.sqrt(hbar / (2 * m * L**2) * math.sqrt(L / g))
    return falling_time(theta0, 2 * math.sin(theta0 / 2) * math.sqrt(g / L), L, g)


def figure1(n=200):
    """Data of the paper's Figure 1: theta0 in (0, pi/2], I(theta0, 0) and its asymptote (18)."""
    theta0 = np.linspace(GROUND / n, GROUND, n)
    return {"theta0": theta0, "I": falling_integral(theta0), "asymptotic18": asymptotic18(theta0)}


# --- the suite's integrators on the same fall (suite convention, nondimensional) ---------------

def _fall_rhs(t, x):
    return model.rhs(x, 0.0, 1.0)


def _ground(t, x):
    return x[0] - GROUND


_ground.terminal, _ground.direction = True, -1


def fall_time_scipy(x0, method="DOP853", rtol=1e-12, atol=1e-12, t_max=100.0):
    """Time to the ground by `scipy.integrate.solve_ivp` with a terminal event theta = pi/2
    (located by scipy's root finding on the method's dense output)."""
    sol = solve_ivp(_fall_rhs, (0.0, t_max), np.asarray(x0, float), method=method, rtol=rtol,
                    atol=atol, events=_ground)
    if not sol.t_events[0].size:
        raise RuntimeError(f"{method}: no ground crossing before t = {t_max} from x0 = {x0}")
    return float(sol.t_events[0][0])


@cached
def casadi_flow(plugin="cvodes", **opts):
    """CasADi integrator x(0) = x0 -> x(h) of the suite's pendulum with u = 0, the horizon h as the
    parameter p (time scaled to [0, 1]: x' = h f(x)); `opts` go to `casadi.integrator` untouched.
    Built once per arguments (`ocp.core.cache`: `clear()` forgets it, for cold timings)."""
    x, h = ca.SX.sym("x", 2), ca.SX.sym("h")
    return ca.integrator("fall", plugin, {"x": x, "p": h, "ode": h * model.rhs(x, 0.0, 1.0)}, 0.0, 1.0, opts)


def fall_time_casadi(x0, plugin="cvodes", step=0.5, t_max=100.0, **opts):
    """Time to the ground by a CasADi integrator (`casadi_flow`), which has no event detection:
    march in steps of `step` until theta <= pi/2, then solve theta(h) = pi/2 for the time h from
    the last state before the crossing by Newton's method, whose derivative d theta/dh = omega(h)
    is the integrator's own output, from the secant guess, until the step is below 1e-15 relative
    or stops shrinking (the integrator's own noise, e.g. collocation's inner rootfinder). Each Newton
    step re-integrates [0, h]."""
    F = casadi_flow(plugin, **opts)
    t, x = 0.0, np.asarray(x0, float)
    while True:
        xn = np.asarray(F(x0=x, p=step)["xf"]).ravel()
        if xn[0] <= GROUND:
            break
        t, x = t + step, xn
        if t > t_max:
            raise RuntimeError(f"{plugin}: no ground crossing before t = {t_max} from x0 = {x0}")
    h, last = step * (x[0] - GROUND) / (x[0] - xn[0]), math.inf
    for _ in range(50):
        xh = np.asarray(F(x0=x, p=h)["xf"]).ravel()
        dh = (xh[0] - GROUND) / xh[1]
        h -= dh
        if abs(dh) <= 1e-15 * (t + h) or abs(dh) > last / 2:
            return t + h
        last = abs(dh)
    raise RuntimeError(f"{plugin}: Newton on theta(h) = pi/2 did not converge from x0 = {x0}")


TABLE1 = (192, 48, 24, 6, 3)  #: Table 1: theta0 = pi/n
TABLE2 = (3072, 384, 96, 24, 6)  #: Table 2: theta0 = pi/n
