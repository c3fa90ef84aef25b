"""Certificate of a refined bang-bang extremal (`ocp.refine.Refined`).

First order (maximum principle, H = p1*omega + p2*(kappa*u - sin(theta)) - 1, p' = -dH/dx):
on SAMPLES points of every arc, u = sign(p2) (s_i * p2 > 0 inside arc i), p2 vanishes at each
switch and nowhere else, H = 0 throughout. Strict bang-bang: the switching function crosses zero
transversally, p2'(t_j) = -p1(t_j) with the sign of s_{j+1} - s_j.

Second order: the switching-time problem min sum(d) s.t. x(T; d) = target has the Lagrangian
L = sum(d) + nu . (x(T; d) - target) with nu = -p(T); its Hessian in d, reduced to the null space
of the constraint Jacobian dx(T)/dd (dimension n_arcs - 2), must be positive definite for a strict
local minimum of that problem (vacuous for one switch: the end constraint then fixes the
durations locally). With the strict bang-bang property this is the second-order sufficient
condition for bang-bang controls (Agrachev, Stefani and Zezza 2002; Osmolovskii and Maurer 2012):
a strict strong local minimum. Nothing here proves global optimality.
"""

from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from . import model
from .refine import MAX_STEPS, TOL

SAMPLES = 200
#: first-order conditions accepted when their residuals are below this (integrator noise ~1e-12)
FIRST_ORDER_TOL = 1e-8


@dataclass(frozen=True)
class Certificate:
    sign_violation: float
    switch_residual: float
    extra_zeros: int
    switch_slopes: tuple
    strict_bang_bang: bool
    hamiltonian_deviation: float
    reduced_hessian_eigenvalues: tuple
    first_order: bool
    second_order: bool

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
        }


@lru_cache(maxsize=2)
def _sampled_flow(samples):
    """State and costate at s = k/samples (k = 1..samples) of an arc scaled to [0, 1] (CVODES, TOL)."""
    return ca.integrator("sampled", "cvodes", model.state_costate_dae(), 0, np.linspace(0, 1, samples + 1)[1:],
                         {"abstol": TOL, "reltol": TOL, "max_num_steps": MAX_STEPS})


@lru_cache(maxsize=32)
def _end_state(n):
    """x(T; d) for n arcs, params (theta0, omega0, kappa, s_1..s_n), by CVODES at TOL."""
    x, u, h, kappa = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("h"), ca.SX.sym("kappa")
    integ = ca.integrator("arc", "cvodes", {"x": x, "p": ca.vertcat(u, h, kappa),
                                            "ode": h * model.rhs(x, u, kappa)}, 0, 1,
                          {"abstol": TOL, "reltol": TOL, "max_num_steps": MAX_STEPS})
    d, par = ca.MX.sym("d", n), ca.MX.sym("par", 3 + n)
    xe = par[0:2]
    for i in range(n):
        xe = integ(x0=xe, p=ca.vertcat(par[3 + i], d[i], par[2]))["xf"]
    nu = ca.MX.sym("nu", 2)
    lagrangian = ca.sum1(d) + ca.dot(nu, xe)
    return ca.Function("end", [d, par, nu], [xe, ca.jacobian(xe, d), ca.hessian(lagrangian, d)[0]])


def certify(refined, x0, kappa):
    """The Certificate of `refined` (an ocp.refine.Refined) for the pendulum with bound kappa."""
    signs, durations = refined.signs, refined.durations
    flow = _sampled_flow(SAMPLES)
    y = np.concatenate([x0, refined.p0])
    arcs, at_switch = [], []
    for i, (s, d) in enumerate(zip(signs, durations)):
        samples = np.array(flow(x0=y, p=[s, d, kappa])["xf"])          # 4 x SAMPLES
        arcs.append((s, np.column_stack([y, samples])))
        y = samples[:, -1]
        if i < len(signs) - 1:
            at_switch.append(y)
    p2_scale = max(np.max(np.abs(a[3])) for _, a in arcs)
    sign_violation, extra_zeros, h_dev = 0.0, 0, 0.0
    for s, a in arcs:
        inner = s * a[3, 1:-1]
        sign_violation = max(sign_violation, float(np.max(-inner, initial=0.0)) / p2_scale)
        extra_zeros += int(np.sum(np.diff(np.sign(inner)) != 0))
        H = model.hamiltonian(a[:2], a[2:], s, kappa)
        h_dev = max(h_dev, float(np.max(np.abs(H))))
    switch_residual = max((abs(y[3]) for y in at_switch), default=0.0) / p2_scale
    slopes = tuple(float(-y[2]) for y in at_switch)
    strict = all(slope * (signs[j + 1] - signs[j]) > 0 for j, slope in enumerate(slopes))
    first_order = sign_violation == 0.0 and extra_zeros == 0 and switch_residual < FIRST_ORDER_TOL \
        and h_dev < FIRST_ORDER_TOL
    eig = _reduced_hessian_eigenvalues(refined, x0, kappa, p_T=y[2:])      # y: the state-costate at T
    return Certificate(sign_violation, float(switch_residual), extra_zeros, slopes, strict, h_dev,
                       eig, first_order, bool(np.all(np.array(eig) > 0)))


def _reduced_hessian_eigenvalues(refined, x0, kappa, p_T):
    n = len(refined.signs)
    if n <= 2:
        return ()
    _, J, H = _end_state(n)(refined.durations, np.concatenate([x0, [kappa], refined.signs]), -p_T)
    J, H = np.array(J), np.array(H)
    Z = np.linalg.svd(J)[2][2:].T                  # orthonormal basis of the null space of J
    return tuple(float(v) for v in np.linalg.eigvalsh(Z.T @ H @ Z))
