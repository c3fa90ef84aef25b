"""Independent re-simulation of a control: scipy's DOP853 at tight tolerances, restarted at every
discontinuity of u. It shares nothing with the transcription but the model's right-hand side.
scipy is imported at the first re-simulation: a solve without a direct answer never loads it."""

import numpy as np

from . import model

RTOL = ATOL = 1e-12


def flow(x0, u, duration, kappa, rtol=RTOL, atol=ATOL):
    """State after `duration` under constant u from x0 (duration >= 0)."""
    from scipy.integrate import solve_ivp         # here: importing scipy.integrate costs more than a search

    x0 = np.asarray(x0, dtype=float)
    if duration <= 0:
        return x0.copy()
    sol = solve_ivp(lambda t, x: model.rhs(x, u, kappa), (0.0, duration), x0,
                    method="DOP853", rtol=rtol, atol=atol)
    return sol.y[:, -1]


def piecewise(x0, t, u, kappa):
    """States at the nodes t[0..N] under u[k] constant on [t[k], t[k+1]]: array (N+1, 2)."""
    x = np.empty((len(t), 2))
    x[0] = x0
    for k in range(len(u)):
        x[k + 1] = flow(x[k], u[k], t[k + 1] - t[k], kappa)
    return x


def arcs(x0, signs, durations, kappa):
    """States at the ends of consecutive bang arcs u = signs[i] for durations[i]: array (n+1, 2)."""
    x = np.empty((len(signs) + 1, 2))
    x[0] = x0
    for i, (u, d) in enumerate(zip(signs, durations)):
        x[i + 1] = flow(x[i], u, d, kappa)
    return x
