"""The inverted pendulum on a vertically vibrating pivot (Kapitza): Weinstein, "The Inverted
Pendulum", and Tam, "Two-Dimensional Inverted Pendulum" (CSULB, Physics 560A).

The papers' convention, kept here (SI units, theta from the upright, pivot height A cos(w t), point
mass on a massless rod of length l):

    l theta'' + (A w^2 cos(w t) - g) sin(theta) = 0                      (Tam (20))

`simulate` integrates it as it stands. Linearised about the upright (sin(theta) -> theta) and with
z = (w t + pi)/2 (z = 0 at the pivot's lowest point) it is Mathieu's equation

    y'' + (a - 2 q cos 2z) y = 0,    a = -4 g / (l w^2),    q = 2 A / l,

one drive period being z in [0, pi]. Floquet: the monodromy matrix M = Y(pi) (Y the fundamental
matrix, Y(0) = I) has det M = 1, multipliers mu, 1/mu, and the upright is linearly stable iff
|tr M| < 2. The coefficient is even in z, so M follows from half a period: with
Y(pi/2) = [[y1, y2], [y1', y2']],

    M = [[2 y1 y2' - 1, 2 y2 y2'], [2 y1 y1', 2 y1 y2' - 1]],   tr M - 2 = 4 y1' y2,   tr M + 2 = 4 y1 y2',

which gives |tr M| - 2 without cancellation. The stable band is a_0(q) < a < b_1(q): the lower
boundary a_0 (tr M = 2, the even pi-periodic solution, y1'(pi/2) = 0) and the upper one b_1
(tr M = -2, the odd 2pi-periodic solution, y2'(pi/2) = 0), found by Brent's method on y1'(pi/2)
and y2'(pi/2) with the half period integrated at rtol 1e-13: a to ~1e-14 absolute (tests: against
scipy's mathieu_a/mathieu_b and the series a_0 = -q^2/2 + 7q^4/128 - ...), so a critical w to
~1e-14/|a| relative (1e-10 for the papers' device, where a = -8.4e-5). In the (A, w) plane the
upright is stable for w_lower(A) < w < w_upper(A), w = 2 sqrt(g / (-a l)); w_upper is finite only
where b_1(2A/l) < 0, i.e. A/l > 0.4540 (b_1(0.9081) = 0).

Criteria compared (`criteria_table`, `examples_table`, `chart`):
    Kapitza (a_0 ~ -q^2/2):                           A^2 w^2 > 2 g l
    Tam (31), cos(tau) replaced by "its average" 1/sqrt(2) in the linearised (24):  w^2 > sqrt(2) g / A
    exact: the Floquet boundaries above.
Tam's step is wrong: the average of cos over a period is 0 (1/sqrt(2) is its root mean square), and
the stabilisation is an effect of second order in A/l; for the papers' device (l = 0.20 m,
A = 1.3 mm) Tam's criterion gives 103 rad/s against the true 1523 rad/s.

Formula errors in the papers (verdicts on printed numbers are in ocp/papers/data/weinstein_tam.toml):
- Weinstein (22) has l^2 theta'' for l theta'' (dimension error); (23) defines omega_0 = g/l for
  sqrt(g/l), and keeps a factor w_s^2 on the forcing term that the change tau = w_s t removes:
  it should read theta_tautau + ((A/l) cos(tau) - (omega_0/w_s)^2) sin(theta) = 0 (Tam's (23)).
- Weinstein (12) and (13) list l^2 sin^2(theta) theta'^2 twice, so (16) keeps a spurious
  l^2 sin^2(theta) theta'^2 in the kinetic energy (it is dropped again on the way to (22)); (17)
  has L (the connecting rod) where (18) has l.
- Tam's Lagrangian (16) puts -mg[...] inside (1/2) m [...] (a misplaced bracket; (18)-(20) are right).
- Tam (25) "[cos(tau)]_avg = 1/sqrt(2)" and so (26)-(31), as above.
- The figure captions give w in "Hz * rad"; both readings (w rad/s, and 2 pi w rad/s) are checked.

Assumptions for the figures (`figures`): Weinstein's Figures 4 and 5 state l, g, A and w only; the
initial state is taken as theta = 0.1 rad, theta' = 0 at t = 0 (pivot at its top), over 2 s. Tam's
Figure 3 states nothing: taken as the same device (l = 0.20 m, A = 1.3 mm, g = 9.8) at
w = 2000 rad/s, about 1.3 times the true critical frequency, so that the solution is stable as
its caption says. The simulations have no ground: a pendulum that falls swings on below the table.
"""

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..core.errors import InputError

L, A, G = 0.20, 0.0013, 9.8  #: the papers' device: rod length (m), pivot amplitude (m), g (m/s^2)
EXAMPLES = {"fig4": 200.0, "fig5": 20.0}  #: Weinstein's Figures 4 and 5: w in "Hz * rad"
READINGS = {"rad_s": 1.0, "2pi": 2 * math.pi}  #: "Hz * rad" read as rad/s, or as Hz times 2 pi
FIG3_OMEGA = 2000.0  #: rad/s, assumed for Tam's Figure 3
RTOL = 1e-13  #: relative tolerance of the Floquet integrations


def mathieu_parameters(A, omega, l=L, g=G):
    """(a, q) = (-4 g / (l w^2), 2 A / l) of the linearisation about the upright."""
    return -4 * g / (l * omega**2), 2 * A / l


def half_period(a, q, rtol=RTOL):
    """Fundamental matrix Y(pi/2) = [[y1, y2], [y1', y2']] of y'' + (a - 2q cos 2z) y = 0."""
    def rhs(z, Y):
        p = a - 2 * q * math.cos(2 * z)
        return [Y[2], Y[3], -p * Y[0], -p * Y[1]]

    sol = solve_ivp(rhs, (0.0, math.pi / 2), [1.0, 0.0, 0.0, 1.0], method="DOP853", rtol=rtol, atol=rtol * 1e-3)
    return sol.y[:, -1].reshape(2, 2)


def monodromy(a, q):
    """Monodromy matrix M = Y(pi) over one drive period, from the half period (module docstring)."""
    (y1, y2), (d1, d2) = half_period(a, q)
    return np.array([[2 * y1 * d2 - 1, 2 * y2 * d2], [2 * y1 * d1, 2 * y1 * d2 - 1]])


def multipliers(a, q):
    """Floquet multipliers: the eigenvalues of M (mu and 1/mu; on the unit circle iff stable)."""
    return np.linalg.eigvals(monodromy(a, q))


def margins(a, q):
    """(2 - tr M, tr M + 2) = (-4 y1' y2, 4 y1 y2'): the upright is stable iff both are > 0."""
    (y1, y2), (d1, d2) = half_period(a, q)
    return -4 * d1 * y2, 4 * y1 * d2


def stability(A, omega, l=L, g=G):
    """+1 if the upright is linearly stable (|tr M| < 2), -1 if not."""
    return 1 if min(margins(*mathieu_parameters(A, omega, l, g))) > 0 else -1


def boundaries(q):
    """(a_0(q), b_1(q)) for 0 <= q <= 2: the stable band of the upright is a_0 < a < b_1. Brent's
    method on y1'(pi/2) (a_0 in [-2q, 0]) and y2'(pi/2) (b_1 in [-2q, 1]); for q <= 2 these
    brackets hold no other characteristic value."""
    if q == 0:
        return 0.0, 1.0
    if not 0 < q <= 2:
        raise InputError(f"q = {q} is outside [0, 2], where each bracket holds one characteristic value")
    root = dict(xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=200)
    a0 = brentq(lambda a: half_period(a, q)[1, 0], -2 * q, 0.0, **root)
    b1 = brentq(lambda a: half_period(a, q)[1, 1], -2 * q, 1.0, **root)
    return a0, b1


def critical_frequencies(A, l=L, g=G):
    """(w_lower, w_upper) in rad/s: the upright is stable iff w_lower < w < w_upper (exact,
    Floquet); w_upper = inf where b_1(2A/l) >= 0 (A/l < 0.454)."""
    return tuple(2 * math.sqrt(g / (-a * l)) if a < 0 else math.inf for a in boundaries(2 * A / l))


def kapitza_frequency(A, l=L, g=G):
    """Kapitza's criterion A^2 w^2 > 2 g l: w_c = sqrt(2 g l) / A (rad/s)."""
    return math.sqrt(2 * g * l) / A


def tam_frequency(A, g=G):
    """Tam's (31) w_c^2 = sqrt(2) g / A (rad/s)."""
    return math.sqrt(math.sqrt(2) * g / A)


def criteria_table(amplitudes=(1e-3, 1.3e-3, 1e-2, 2e-2, 5e-2, 0.1, 0.15), l=L, g=G):
    """Critical frequencies (rad/s) by each criterion, a row per pivot amplitude A (m)."""
    rows = []
    for amp in amplitudes:
        lower, upper = critical_frequencies(amp, l, g)
        rows.append({"A": amp, "A/l": amp / l, "tam": tam_frequency(amp, g), "kapitza": kapitza_frequency(amp, l, g),
                     "floquet_lower": lower, "floquet_upper": upper})
    return rows


def examples_table(A=A, l=L, g=G):
    """The papers' examples, a row per figure and reading of "Hz * rad": w (rad/s), the verdicts
    by Tam's criterion, Kapitza's and Floquet's (+1 stable, -1 unstable), the Floquet
    multipliers' largest modulus and 2 - |tr M|."""
    rows = []
    for fig, value in EXAMPLES.items():
        for reading, factor in READINGS.items():
            omega = factor * value
            m = margins(*mathieu_parameters(A, omega, l, g))
            rows.append({"figure": fig, "reading": reading, "omega": omega,
                         "tam": 1 if omega > tam_frequency(A, g) else -1,
                         "kapitza": 1 if omega > kapitza_frequency(A, l, g) else -1,
                         "floquet": 1 if min(m) > 0 else -1,
                         "max_abs_mu": max(abs(multipliers(*mathieu_parameters(A, omega, l, g)))),
                         "margin": min(m)})
    return rows


def chart(n=60, l=L, g=G, ratio_max=0.8):
    """Data for the stability chart in the (A, w) plane: A (m), log-spaced up to ratio_max * l, and
    the critical frequencies (rad/s) Floquet lower and upper (inf where none), Kapitza, Tam."""
    amps = l * np.geomspace(1e-3, ratio_max, n)
    lower, upper = np.array([critical_frequencies(amp, l, g) for amp in amps]).T
    return {"A": amps, "floquet_lower": lower, "floquet_upper": upper,
            "kapitza": np.sqrt(2 * g * l) / amps, "tam": np.sqrt(math.sqrt(2) * g / amps)}


def simulate(A, omega, l=L, g=G, theta0=0.1, dtheta0=0.0, t_end=2.0, t_eval=None, rtol=1e-10):
    """Time history (t, theta) in s and rad of l theta'' + (A w^2 cos(w t) - g) sin(theta) = 0
    from (theta0, dtheta0) at t = 0; `t_eval` defaults to 40 samples a drive period."""
    def rhs(t, x):
        return [x[1], (g - A * omega**2 * math.cos(omega * t)) * math.sin(x[0]) / l]

    if t_eval is None:
        t_eval = np.linspace(0.0, t_end, int(40 * omega * t_end / (2 * math.pi)) + 1)
    sol = solve_ivp(rhs, (0.0, t_end), [theta0, dtheta0], method="DOP853", t_eval=t_eval,
                    rtol=rtol, atol=rtol * 1e-3, max_step=math.pi / omega)
    return sol.t, sol.y[0]


def figures():
    """Time histories of Tam's Figure 3 and Weinstein's Figures 4 and 5 (both readings of
    "Hz * rad"), as they really are: name -> dict(omega, stable, t, theta, caption)."""
    cases = {"tam_fig3": (FIG3_OMEGA, "Tam Figure 3 (assumed: device parameters, w = 2000 rad/s)")}
    for fig, value in EXAMPLES.items():
        for reading, factor in READINGS.items():
            cases[f"weinstein_{fig}_{reading}"] = (factor * value, f"Weinstein {fig}, w = {value:g} Hz*rad read as {reading}")
    out = {}
    for name, (omega, caption) in cases.items():
        t, theta = simulate(A, omega)
        out[name] = {"omega": omega, "stable": stability(A, omega), "t": t, "theta": theta, "caption": caption}
    return out
