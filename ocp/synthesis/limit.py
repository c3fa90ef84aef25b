"""The plane at high energy: the far turnaround, and why N_kappa >= 2 on the plane for every kappa.

On the plane (one pinned target (theta_T, 0), theta_T = pi for the swing-up, 0 for the damping)
take a state beyond the target moving away from it (theta0 > theta_T, omega0 > 0; the mirror
image theta -> 2 theta_T - theta, omega -> -omega is the same). Its only transfer with at most one
switch (at speeds above 2; for the damping at kappa > 1) is the *candidate*: u = -1 (braking, the
turnaround at (theta_s, 0), the return accelerating), then u = +1 braking into the target. On an arc of constant u,
E - kappa u theta is conserved (E = omega^2/2 - cos theta), so the switch lies where the arc
levels l = E + kappa theta (of the first arc, l = kappa theta_s - cos theta_s) and
l_T = -cos theta_T - kappa theta_T (of the last) meet:

    theta_sw = (l - l_T) / (2 kappa),    E_sw = (l + l_T) / 2,    omega_sw < 0.

Pontryagin's principle (H = 1 + p_theta omega + p_omega (kappa u - sin theta) = 0, u = -sign p_omega)
fixes the costate at the switch, p_omega = 0, p_theta = -1 / omega_sw, and the first arc needs
p_omega > 0 all along it. Backwards from the switch, p_omega' = -p_theta, p_theta' = p_omega cos theta:
p_omega grows linearly over the fast return (cos theta averages out), and at the turnaround, where
theta is slow, p_theta receives the kick -p_omega(stop) * integral of cos theta dt =
-p_omega(stop) sqrt(2 pi / a) cos(theta_s - pi/4) (stationary phase, a = kappa + sin theta_s). With
p_omega(stop) = p_theta * (the return's duration, about |omega_sw| / kappa), the kick reverses
p_theta, and p_omega comes back to zero on the outgoing arc, as soon as

    |omega_sw| sqrt(2 pi) cos(theta_s - pi/4) / kappa^(3/2) > 1:

every state of the first arc upstream of that zero violates the principle, so it needs two
switches or more. Such states exist at every kappa (at switch energies E_sw of about
kappa^3 / (4 pi) and above): N_kappa >= 2 on the plane for every kappa, and the plane's principal
values kappa_1 (swing-up and damping) do not exist. (For the damping below kappa = 1 the circle
has states of two switches already, kappa_1 = 1.039 there, and a state's optimal transfer on the
circle is optimal on the plane pinned to its branch.)

The limit problem (l -> infinity): near the turnaround p_omega is a constant P to first order and
mu = p_omega / P solves Jacobi's equation mu'' + cos(theta(t)) mu = 0 along the u = -1 arc through
(phi, 0), with mu -> 1, mu' -> 0 on the return far from the stop; its first zero on the outgoing
side is the lower edge of the tongue of two switches, at the speed omega_edge(phi). The least over
the phase phi, omega_min(kappa), is the least speed of a far state needing two switches (attained
at infinite distance); it tends to (kappa + sin(pi/4))^(3/2) / sqrt(2 pi) (the kick) as kappa grows.

Units: nondimensional time and angle of `ocp.core.model`; all speeds in rad per unit time.
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from ..core.errors import InputError
from ..core.problem import KINDS

#: the relative and absolute tolerance of the integrations (DOP853)
TOL = 1e-12
#: the least kappa of each kind for which the candidate is computed: the damping's braking curve
#: into (0, 0) reaches every switch for kappa > 1, the swing-up's for every kappa (computed from 0.5);
#: below, the circle has states of two switches already (kappa_1 = 1.039 and 0.800 there)
LOWEST = {"swing-up": 0.5, "damping": 1.0}


@dataclass(frozen=True)
class Candidate:
    """The one-switch candidate through the turnaround (theta_s, 0): the switch (theta, omega),
    the first zero of p_omega on the outgoing arc upstream of the turnaround (theta, omega), None
    if p_omega stays positive up to the speed cap, and the time from that zero to the turnaround."""

    kind: str
    kappa: float
    theta_s: float
    switch: tuple
    zero: tuple | None
    zero_to_stop: float | None


def _arc(t, y, kappa):
    """u = -1: (theta, omega, p_theta, p_omega)' = (omega, -kappa - sin theta, p_omega cos theta, -p_theta)."""
    theta, omega, p_theta, p_omega = y
    return (omega, -kappa - math.sin(theta), p_omega * math.cos(theta), -p_theta)


def _event(index, value=0.0, terminal=True, direction=0.0):
    def event(t, y, kappa):
        return y[index] - value
    event.terminal, event.direction = terminal, direction
    return event


def _cap(kappa):
    """The default speed cap of the outgoing arc: ten times the edge's scale kappa^(3/2) / sqrt(2 pi)."""
    return 10 * kappa ** 1.5 / math.sqrt(2 * math.pi) + 50.0


def _outgoing_zero(y_stop, kappa, omega_cap):
    """Backwards in time from the turnaround state y_stop (omega = 0) along the outgoing arc: the
    first zero of p_omega as (theta, omega, time before the stop), or None if omega reaches
    omega_cap first."""
    span = 4.0 * omega_cap / kappa + 20.0
    sol = solve_ivp(_arc, (0.0, -span), y_stop, "DOP853", args=(kappa,), rtol=TOL, atol=TOL,
                    events=(_event(3), _event(1, omega_cap)))
    if len(sol.t_events[0]):
        theta, omega = sol.y_events[0][0][:2]
        return float(theta), float(omega), float(-sol.t_events[0][0])
    return None


def candidate(kind, kappa, theta_s, omega_cap=None):
    """The Candidate of problem `kind` on the plane (target branch 0) whose first arc turns at
    (theta_s, 0): the costate from the switch (p_omega = 0, p_theta = -1/omega_sw) integrated
    backwards through the turnaround and along the outgoing arc until p_omega vanishes or the speed
    reaches omega_cap."""
    if kind not in KINDS:
        raise InputError(f"unknown problem {kind!r}; accepted: {', '.join(KINDS)}")
    low = LOWEST[kind]
    if not kappa > low:
        raise InputError(f"kappa = {kappa!r}: the far candidate of the {kind} is computed for kappa > {low:g} only; "
                         f"accepted: kappa > {low:g}")
    omega_cap = _cap(kappa) if omega_cap is None else omega_cap
    theta_t = KINDS[kind].target_base
    level, level_t = kappa * theta_s - math.cos(theta_s), -math.cos(theta_t) - kappa * theta_t
    theta_sw, e_sw = (level - level_t) / (2 * kappa), (level + level_t) / 2
    if not (theta_t < theta_sw < theta_s and e_sw + math.cos(theta_sw) > 0):
        raise InputError(f"theta_s = {theta_s!r}: the turnaround must lie beyond the target, far enough that the "
                         f"return meets the braking curve into it")
    omega_sw = -math.sqrt(2 * (e_sw + math.cos(theta_sw)))
    y_sw = np.array([theta_sw, omega_sw, -1.0 / omega_sw, 0.0])
    back = solve_ivp(_arc, (0.0, -4 * abs(omega_sw) / kappa - 20.0), y_sw, "DOP853", args=(kappa,), rtol=TOL,
                     atol=TOL, events=(_event(1, 0.0, True, 1.0), _event(3, 0.0, True, -1.0)))
    if len(back.t_events[1]) or not len(back.t_events[0]):
        zero = (float(back.y[0, -1]), float(back.y[1, -1]), None)       # p_omega vanished on the return
    else:
        zero = _outgoing_zero(back.y_events[0][0], kappa, omega_cap)
    return Candidate(kind, kappa, theta_s, (theta_sw, omega_sw), None if zero is None else zero[:2],
                     None if zero is None else zero[2])


def edge_speed(kappa, phi, omega_start=None, omega_cap=None):
    """The limit problem: the speed omega_edge(phi) at the first zero of Jacobi's mu'' + cos(theta) mu = 0
    on the outgoing side of the u = -1 arc through (phi, 0), started on the return at the speed
    omega_start (default 4 kappa^(3/2)) with mu = 1 and p_theta = sin(theta)/omega (mu. = 0 to O(omega^-2), the bounded
    solution to O(omega^-2), so the error is O(1 / (kappa omega_start))); inf if none below
    omega_cap."""
    if omega_start is None:
        omega_start = 4 * kappa ** 1.5
    omega_cap = _cap(kappa) if omega_cap is None else omega_cap
    # the return side: forward in time from the stop the pendulum falls back (omega < 0)
    ret = solve_ivp(_arc, (0.0, 4 * omega_start / kappa + 20.0), np.array([phi, 0.0, 0.0, 0.0]), "DOP853",
                    args=(kappa,), rtol=TOL, atol=TOL, events=(_event(1, -omega_start),))
    start = ret.y_events[0][0].copy()
    start[2:] = (math.sin(start[0]) / start[1], 1.0)      # p_theta = mu sin(theta)/omega + O(omega^-2)
    back = solve_ivp(_arc, (0.0, -2 * ret.t_events[0][0]), start, "DOP853", args=(kappa,), rtol=TOL, atol=TOL,
                     events=(_event(1, 0.0, True, 1.0),))
    zero = _outgoing_zero(back.y_events[0][0], kappa, omega_cap)
    return math.inf if zero is None else zero[1]


def sampled_minimum(f, lo, hi, samples, xatol):
    """(min f, its argument) over [lo, hi]: f at `samples` equispaced points, then bounded Brent
    minimisation between the neighbours of the least; (inf, nan) if f is infinite at every sample."""
    grid = np.linspace(lo, hi, samples)
    values = [f(x) for x in grid]
    i = int(np.argmin(values))
    if not math.isfinite(values[i]):
        return math.inf, math.nan
    step = grid[1] - grid[0]
    best = minimize_scalar(f, bounds=(grid[i] - step, grid[i] + step), method="bounded", options={"xatol": xatol})
    return float(best.fun), float(best.x)


def least_edge(kappa, omega_start=None, samples=24):
    """(omega_min, phi): the least edge speed of the limit problem over the turnaround's phase phi,
    sampled then refined by bounded Brent minimisation."""
    value, phi = sampled_minimum(lambda p: edge_speed(kappa, p, omega_start), 0.0, 2 * math.pi, samples, 1e-7)
    return value, float(math.remainder(phi, 2 * math.pi))


def kick_edge(kappa):
    """The stationary-phase estimate of omega_min: the kick sqrt(2 pi / a) cos(theta_s - pi/4) reverses
    p_theta, and p_omega vanishes after the time 1/(kick) on the outgoing arc, at the speed a / kick
    with a = kappa + sin(pi/4): omega_min ~ a^(3/2) / sqrt(2 pi)."""
    a = kappa + math.sin(math.pi / 4)
    return a ** 1.5 / math.sqrt(2 * math.pi)


def upstream(kappa, x, dt):
    """The state dt time units before x on the u = -1 arc through x (dt < 0: after)."""
    sol = solve_ivp(_arc, (0.0, -dt), np.array([x[0], x[1], 0.0, 0.0]), "DOP853", args=(kappa,), rtol=TOL, atol=TOL)
    return float(sol.y[0, -1]), float(sol.y[1, -1])


def confirm(kind, kappa, theta_s, offsets=(-0.2, 0.2)):
    """The complete search on the plane (branch 0) at states of the candidate's first arc, offset dt
    before (dt > 0: upstream, where the principle fails) or after (dt < 0) the zero of p_omega:
    [{"dt", "x0", "T", "switches", "arc_signs", "candidate_T"}]; N >= 2 upstream is the claim checked."""
    from ..core.problem import make
    from ..solving import solve

    c = candidate(kind, kappa, theta_s)
    if c.zero is None:
        raise InputError(f"theta_s = {theta_s!r}: p_omega keeps its sign up to the speed cap; no tongue on this arc")
    rows = []
    for dt in offsets:
        x0 = upstream(kappa, c.zero, dt)
        s = solve(make(kind, kappa, x0, branch=0))
        rows.append({"dt": dt, "x0": list(x0), "T": s.T, "switches": s.n_switches, "arc_signs": list(s.arc_signs)})
    return c, rows


@dataclass(frozen=True)
class Edge:
    """The least speed omega_min of a far state needing two switches on the plane at kappa (the
    lower edge of the tongues, at the turnaround phase phi), with its error bar: the spread of the
    routes (the limit problem at two starting speeds, and the finite candidates extrapolated), and
    the stationary-phase estimate `kick` beside it."""

    kappa: float
    omega_min: float
    error: float
    phi: float
    kick: float
    routes: dict

    def to_dict(self):
        return {"kappa": self.kappa, "omega_min": self.omega_min, "error": self.error, "phi": self.phi,
                "kick": self.kick, "routes": self.routes}


def extrapolated_edge(kind, kappa, phi, turns=(160, 320, 640)):
    """(omega at infinite distance, its fit error): the speed at the zero of p_omega of the finite
    candidates turning at phi + 2 pi m (m in turns, times (kappa/5)^2 above kappa = 5, which keeps the
    expansion's variable kappa^(3/2) / |omega_sw| of the same size), 1/omega_zero fitted by a parabola in
    1/|omega_sw| (the kick's model: 1/omega_zero = sqrt(2 pi) kappa^(-3/2) - 1/|omega_sw| + ...) and
    read at 1/|omega_sw| = 0; the error is its distance from the line through the two farthest."""
    scale = max(1.0, (kappa / 5) ** 2)
    points = [candidate(kind, kappa, phi + 2 * math.pi * round(m * scale)) for m in turns]
    x = np.array([1 / abs(c.switch[1]) for c in points])
    y = np.array([1 / c.zero[1] for c in points])
    quadratic, line = np.polyfit(x, y, 2)[-1], np.polyfit(x[1:], y[1:], 1)[-1]
    return float(1 / quadratic), float(abs(1 / quadratic - 1 / line))


def edge(kappa, kind="swing-up"):
    """The Edge at kappa: the limit problem minimised over phi (omega_start 4 kappa^(3/2)), checked
    at omega_start 8 kappa^(3/2) and by the finite candidates of `kind` extrapolated to infinite
    distance at the same phase; error = the spread of the three plus the fit error."""
    omega, phi = least_edge(kappa)
    far, fit = extrapolated_edge(kind, kappa, phi)
    routes = {"limit problem, omega_start 4 kappa^1.5": omega,
              "limit problem, omega_start 8 kappa^1.5": edge_speed(kappa, phi, 8 * kappa ** 1.5),
              "finite candidates, extrapolated to infinite distance": far}
    values = list(routes.values())
    return Edge(kappa, omega, max(values) - min(values) + fit, phi, kick_edge(kappa), routes)


def least_time_to_go(kind, kappa, n, psi_lo, psi_hi, s_max=400.0, samples=60):
    """(s, psi): the least time-to-go s_n(psi) of the n-th switch (counted back from the target) of
    the field's extremals over final costate angles psi in [psi_lo, psi_hi] (sampled, then bounded
    Brent minimisation); (inf, nan) if none switches n times within s_max."""
    from .bifurcation import switch_point

    def s(psi):
        point = switch_point(kind, kappa, psi, n, s_max=s_max)
        return math.inf if point is None else point.s

    return sampled_minimum(s, psi_lo, psi_hi, samples, 1e-9)


def runaway(kind, n, kappas, psi_lo, psi_hi, samples=60):
    """(kappa_inf, error, [(kappa, s, psi)]): where the least time-to-go of the n-th switch runs off to
    infinity (its switch point to infinite energy): 1/s at the kappas, fitted by a parabola and by
    the line through the last two, each extrapolated to 1/s = 0; the error is their distance."""
    rows = [(k, *least_time_to_go(kind, k, n, psi_lo, psi_hi, samples=samples)) for k in kappas]
    k, inv = np.array([r[0] for r in rows]), np.array([1 / r[1] for r in rows])
    quadratic = np.polynomial.polynomial.Polynomial.fit(k, inv, 2)
    roots = [r.real for r in quadratic.roots() if abs(r.imag) < 1e-12 and r.real > k[-1]]
    line = k[-1] - inv[-1] * (k[-1] - k[-2]) / (inv[-1] - inv[-2])
    best = min(roots) if roots else line
    return float(best), float(abs(best - line)), rows
