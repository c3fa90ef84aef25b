"""The torque-limited pendulum, in the suite's one convention.

    theta'' + sin(theta) = kappa * u,    |u| <= 1,

nondimensional time t = sqrt(m g l / I) s, control u = tau / tau0, kappa = tau0 / (m g l);
theta = 0 hangs down, theta = pi is upright, theta counterclockwise. The state is
x = (theta, omega) with omega = theta'. Every function here takes either numpy values or CasADi
symbols (SX/MX) and returns the same kind.
"""

import casadi as ca
import numpy as np


def _symbolic(*values):
    return any(isinstance(v, (ca.SX, ca.MX)) for v in values)


def rhs(x, u, kappa):
    """x' = f(x, u; kappa) = (omega, kappa*u - sin(theta))."""
    theta, omega = x[0], x[1]
    if _symbolic(x, u, kappa):
        return ca.vertcat(omega, kappa * u - ca.sin(theta))
    return np.array([omega, kappa * u - np.sin(theta)])


def energy(x):
    """Mechanical energy E = omega^2/2 - cos(theta): -1 at rest hanging, +1 at rest upright."""
    theta, omega = x[0], x[1]
    cos = ca.cos if _symbolic(x) else np.cos
    return 0.5 * omega**2 - cos(theta)


def arc_invariant(x, u, kappa):
    """On an arc of constant u, omega^2/2 - cos(theta) - kappa*u*theta is conserved."""
    return energy(x) - kappa * u * x[0]


def hamiltonian(x, p, u, kappa):
    """Pontryagin's Hamiltonian of minimum time, maximum form: H = p1*omega + p2*(kappa*u - sin(theta)) - 1.
    An optimal control maximises it (u = sign(p2)) and keeps H = 0 (free final time)."""
    f = rhs(x, u, kappa)
    return p[0] * f[0] + p[1] * f[1] - 1


def costate_rhs(x, p):
    """Adjoint p' = -dH/dx: p1' = p2*cos(theta), p2' = -p1."""
    if _symbolic(x, p):
        return ca.vertcat(p[1] * ca.cos(x[0]), -p[0])
    return np.array([p[1] * np.cos(x[0]), -p[0]])


def state_costate_dae():
    """The state-costate system of one bang arc on scaled time s in [0, 1]: y = (theta, omega, p1, p2),
    parameters (u, d, kappa), y' = d * (f(x, u), -dH/dx); a CasADi integrator's dae dict."""
    y, u, d, kappa = ca.SX.sym("y", 4), ca.SX.sym("u"), ca.SX.sym("d"), ca.SX.sym("kappa")
    ode = d * ca.vertcat(rhs(y[:2], u, kappa), costate_rhs(y[:2], y[2:]))
    return {"x": y, "p": ca.vertcat(u, d, kappa), "ode": ode}
