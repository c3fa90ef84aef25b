"""The torque-limited pendulum, in the suite's one convention.

    theta'' + sin(theta) = kappa * u,    |u| <= 1,

nondimensional time t = sqrt(m g l / I) s, control u = tau / tau0, kappa = tau0 / (m g l);
theta = 0 hangs down, theta = pi is upright, theta counterclockwise. The state is
x = (theta, omega) with omega = theta'. `rhs`, `energy`, `arc_invariant` and `hamiltonian` take
numpy values or CasADi symbols and return the same kind; the costate equation is derived from the
Hamiltonian by CasADi's automatic differentiation (`costate_rhs`).
"""

import numpy as np

from .cache import cached


def _casadi(*values):
    """The casadi module if any value is a CasADi symbol, else None (casadi is imported only then)."""
    if any(type(v).__module__.startswith("casadi") for v in values):
        import casadi
        return casadi
    return None


def rhs(x, u, kappa):
    """x' = f(x, u; kappa) = (omega, kappa*u - sin(theta))."""
    ca = _casadi(x, u, kappa)
    if ca:
        return ca.vertcat(x[1], kappa * u - ca.sin(x[0]))
    return np.array([x[1], kappa * u - np.sin(x[0])])


def energy(x):
    """Mechanical energy E = omega^2/2 - cos(theta): -1 at rest hanging, +1 at rest upright."""
    ca = _casadi(x)
    return 0.5 * x[1] ** 2 - (ca.cos if ca else np.cos)(x[0])


def arc_invariant(x, u, kappa):
    """On an arc of constant u, omega^2/2 - cos(theta) - kappa*u*theta is conserved."""
    return energy(x) - kappa * u * x[0]


def hamiltonian(x, p, u, kappa):
    """Pontryagin's Hamiltonian of minimum time, maximum form: H = p . f(x, u) - 1. An optimal
    control maximises it (u = sign(p2)) and keeps H = 0 (free final time)."""
    f = rhs(x, u, kappa)
    return p[0] * f[0] + p[1] * f[1] - 1


@cached
def costate_function():
    """The CasADi Function (x, p, u, kappa) -> p' = -dH/dx, by automatic differentiation of
    `hamiltonian`: p1' = p2*cos(theta), p2' = -p1."""
    import casadi as ca

    x, p, u, kappa = ca.SX.sym("x", 2), ca.SX.sym("p", 2), ca.SX.sym("u"), ca.SX.sym("kappa")
    return ca.Function("costate", [x, p, u, kappa], [-ca.gradient(hamiltonian(x, p, u, kappa), x)])


def costate_rhs(x, p, u, kappa):
    """p' = -dH/dx at (x, p, u), as numpy (or CasADi, for symbolic arguments)."""
    value = costate_function()(x, p, u, kappa)
    return value if _casadi(x, p, u, kappa) else np.array(value).ravel()
