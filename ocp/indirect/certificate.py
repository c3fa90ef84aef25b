"""The certificate of an extremal found by the search, checked by means independent of it.

First order (maximum principle, H = p . f(x, u) - 1, p' = -dH/dx from `ocp.core.model`): the
state and costate are integrated again from (x0, p(0)) along the extremal's arcs by CasADi's CVODES
(rtol = atol = TOL, restarted at each switch), the costate equation by automatic differentiation
of the Hamiltonian (nothing shared with the Taylor integration of the search); the state it
reaches carries its own error estimate, its distance to the state the same integration reaches at
tolerance ROUGH (`final_state_error`: CVODES's error grows with the trajectory's length, 1e-13
over 4 time units, 2e-7 over 489 from (0, 50) at kappa = 0.1). On SAMPLES points of every arc, u = sign(p2) (s_i * p2 > 0 inside arc i), p2
vanishes at each switch (relative to max |p2|) and nowhere else, and H = 0 (relative to
max(1, P(t) |f|), P(t) the largest |p| up to t: the integration's error in p is relative to it, and
a costate that shrinks from hundreds to units, as after a start near the upright, keeps it). Strict bang-bang: the
switching function crosses zero transversally, p2'(t_j) = -p1(t_j) of the sign of s_{j+1} - s_j.

Second order: the switching-time problem min sum(d) s.t. x(T; d) = target has the Lagrangian
L = sum(d) + nu . (x(T; d) - target), nu = -p(T); its Hessian in the durations d, reduced to the
null space of dx(T)/dd (dimension n_arcs - 2), must be positive definite for a strict local minimum
(vacuous for one switch). With strict bang-bang this is the sufficient condition of Agrachev,
Stefani and Zezza (2002) and Osmolovskii and Maurer (2012): a strict strong local minimum. The
derivatives are central differences of x(T; d) (`ocp.indirect.taylor.bang`, PRECISE) at steps
STEP and 2 STEP; their difference is the eigenvalues' error estimate.

Global optimality is the search's claim, not the certificate's: every extremal reaching the target
before the horizon is compared (`ocp.indirect.searching`).
"""

from dataclasses import dataclass

import numpy as np

from ..core import model
from ..core.cache import cached
from . import taylor

SAMPLES = 200
TOL = 1e-14
ROUGH = 1e-13
#: first-order conditions accepted when their residuals are below this (integrator noise ~1e-11)
FIRST_ORDER_TOL = 1e-8
STEP = 1e-4


@dataclass(frozen=True)
class Certificate:
    """Residuals of the first-order conditions, strict bang-bang slopes, the reduced Hessian's
    eigenvalues with their error estimate, the verdicts, and the state reached by the independent
    integration (`final_state`: the control re-simulated) and its error estimate (`final_state_error`:
    its distance to the state reached at tolerance ROUGH)."""

    sign_violation: float
    switch_residual: float
    extra_zeros: int
    switch_slopes: tuple
    strict_bang_bang: bool
    hamiltonian_deviation: float
    reduced_hessian_eigenvalues: tuple
    eigenvalue_error: float
    first_order: bool
    second_order: bool
    final_state: tuple
    final_state_error: float

    @property
    def certified(self):
        return self.first_order and self.strict_bang_bang and self.second_order

    def to_dict(self):
        return {
            "certified": self.certified, "first_order": self.first_order,
            "strict_bang_bang": self.strict_bang_bang, "second_order": self.second_order,
            "sign_violation": self.sign_violation, "switch_residual": self.switch_residual,
            "extra_zeros_of_p2": self.extra_zeros, "switch_slopes": list(self.switch_slopes),
            "hamiltonian_deviation": self.hamiltonian_deviation,
            "reduced_hessian_eigenvalues": list(self.reduced_hessian_eigenvalues),
            "eigenvalue_error": self.eigenvalue_error, "final_state": list(self.final_state),
            "final_state_error": self.final_state_error,
        }


@cached
def _sampled_flow(tol=TOL):
    """CVODES (rtol = atol = tol) over an arc scaled to s in [0, 1]: y = (theta, omega, p1, p2),
    parameters (u, d, kappa), y' = d * (f(x, u), -dH/dx), sampled at s = k/SAMPLES."""
    import casadi as ca

    y, u, d, kappa = ca.SX.sym("y", 4), ca.SX.sym("u"), ca.SX.sym("d"), ca.SX.sym("kappa")
    ode = d * ca.vertcat(model.rhs(y[:2], u, kappa), model.costate_rhs(y[:2], y[2:], u, kappa))
    return ca.integrator("certificate", "cvodes", {"x": y, "p": ca.vertcat(u, d, kappa), "ode": ode}, 0,
                         np.linspace(0, 1, SAMPLES + 1)[1:], {"abstol": tol, "reltol": tol, "max_num_steps": 200000})


def _arc(y0, u, duration, kappa, tol=TOL):
    """State and costate along an arc of constant u at SAMPLES + 1 equal steps: array (4, SAMPLES + 1)."""
    samples = np.array(_sampled_flow(tol)(x0=y0, p=[u, duration, kappa])["xf"])
    return np.column_stack([y0, samples])


def _arcs(y0, signs, durations, kappa, tol=TOL):
    """State and costate along each arc (`_arc`) from y0 = (x0, p(0)), each from the end of the one before."""
    arcs = []
    for s, d in zip(signs, durations):
        arcs.append(_arc(y0 if not arcs else arcs[-1][:, -1], s, d, kappa, tol))
    return arcs


def certify(extremal, x0, kappa):
    """The Certificate of `extremal` (an `ocp.indirect.searching.Extremal`) from x0 for bound kappa."""
    signs, durations = extremal.signs, extremal.durations
    y0 = np.concatenate([np.asarray(x0, float), extremal.p0])
    arcs = _arcs(y0, signs, durations, kappa)
    at_switch, y = [a[:, -1] for a in arcs[:-1]], arcs[-1][:, -1]
    p2_scale = max(np.max(np.abs(a[3])) for a in arcs)
    sign_violation, extra_zeros, h_dev, p_seen = 0.0, 0, 0.0, 0.0
    for s, a in zip(signs, arcs):
        inner = s * a[3, 1:-1]
        sign_violation = max(sign_violation, float(np.max(-inner, initial=0.0)) / p2_scale)
        extra_zeros += int(np.sum(np.diff(np.sign(inner)) != 0))
        # |H| relative to the size of p . f, whose rounding and integration error it carries: the
        # error of p is relative to the largest |p| integrated up to that point
        p_size = np.maximum.accumulate(np.maximum(np.hypot(a[2], a[3]), p_seen))
        p_seen = float(p_size[-1])
        size = p_size * np.hypot(*model.rhs(a[:2], s, kappa))
        h_dev = max(h_dev, float(np.max(np.abs(model.hamiltonian(a[:2], a[2:], s, kappa)) / np.maximum(1.0, size))))
    switch_residual = max((abs(v[3]) for v in at_switch), default=0.0) / p2_scale
    slopes = tuple(float(-v[2]) for v in at_switch)
    strict = all(slope * (signs[j + 1] - signs[j]) > 0 for j, slope in enumerate(slopes))
    first_order = (sign_violation == 0.0 and extra_zeros == 0 and switch_residual < FIRST_ORDER_TOL
                   and h_dev < FIRST_ORDER_TOL)
    eigenvalues, error = reduced_hessian(x0, signs, durations, kappa, -y[2:])
    second = all(e > error for e in eigenvalues)
    rough = _arcs(y0, signs, durations, kappa, ROUGH)[-1][:, -1]
    return Certificate(sign_violation, float(switch_residual), extra_zeros, slopes, strict, h_dev,
                       eigenvalues, error, first_order, second, (float(y[0]), float(y[1])),
                       float(np.hypot(y[0] - rough[0], y[1] - rough[1])))


def _end(x0, signs, durations, kappa):
    tol, order = taylor.PRECISE
    return taylor.bang(np.asarray(x0, float), np.asarray(signs, float), np.asarray(durations, float), kappa, tol, order)


def _derivatives(x0, signs, d, kappa, nu, h):
    """(J = dx(T)/dd (2 x n), Hessian of nu . x(T; d) (n x n)) by central differences of step h."""
    n = len(d)
    J = np.empty((2, n))
    H = np.empty((n, n))
    f = lambda dd: _end(x0, signs, dd, kappa)
    base = nu @ f(d)
    for i in range(n):
        e = np.zeros(n)
        e[i] = h
        plus, minus = f(d + e), f(d - e)
        J[:, i] = (plus - minus) / (2 * h)
        H[i, i] = (nu @ plus - 2 * base + nu @ minus) / h**2
        for j in range(i):
            g = np.zeros(n)
            g[j] = h
            H[i, j] = H[j, i] = (nu @ (f(d + e + g) - f(d + e - g) - f(d - e + g) + f(d - e - g))) / (4 * h * h)
    return J, H


def reduced_hessian(x0, signs, durations, kappa, nu):
    """(eigenvalues of the Lagrangian's Hessian on the null space of dx(T)/dd, their error
    estimate): empty for at most two arcs."""
    n = len(signs)
    if n <= 2:
        return (), 0.0
    d = np.asarray(durations, float)
    results = []
    for h in (STEP, 2 * STEP):
        J, H = _derivatives(x0, signs, d, kappa, np.asarray(nu, float), h)
        Z = np.linalg.svd(J)[2][2:].T
        results.append(np.linalg.eigvalsh(Z.T @ H @ Z))
    error = float(np.max(np.abs(results[0] - results[1])))
    return tuple(float(v) for v in results[0]), error
