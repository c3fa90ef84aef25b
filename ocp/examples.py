"""The swing-up paper's claims that only a solve can check: the optimal switch counts N_kappa(x0)
it states for the standard transfers, and Reshmin's damping example from (-100, 14.16), kappa = 1
(two switches, 0.27 % faster than one). Each count is that of the best certified extremal of
`ocp.solve` among its competing structures: evidence, not a proof of global optimality."""

import math

from . import damping, solve, swing_up
from .verify import Reproduction

HOW = "switch count of ocp.solve's best certified extremal among its candidate structures (not a global proof)"


def _count(problem):
    sol = solve(problem)
    if not sol.certified:
        return Reproduction(sol.n_switches, math.inf, f"{HOW}; NOT certified here: {sol.verdict}")
    return Reproduction(sol.n_switches, 0.0, f"{HOW}: T = {sol.T:.10f}")


def reproduce():
    out = {key: _count(problem) for key, problem in (
        ("n_one", swing_up(1.0)), ("n_half", swing_up(0.5)), ("n_three_quarters", swing_up(0.75)),
        ("n_damping_one", damping(1.0)))}
    sol = solve(damping(1.0, x0=(-100.0, 14.16), branch=0))
    out["reshmin_damping_switches"] = Reproduction(
        sol.n_switches, 0.0 if sol.certified else math.inf, f"{HOW}: T = {sol.T:.10f}, arcs {sol.arc_signs}")
    one = [c for c in sol.candidates if c.valid and len(c.signs) == 2]
    if sol.certified and sol.n_switches == 2 and one:
        T1, T2 = one[0].T, sol.T
        error = 100 * (one[0].refined.residual + 1e-10) / T2        # both T to ~1e-10 (refinement)
        out["reshmin_damping_gain"] = Reproduction(
            100 * (T1 - T2) / T2, error,
            f"100 (T1 - T2)/T2 with T2 = {T2:.10f} (two switches, certified) and T1 = {T1:.10f} (the one-switch "
            f"extremal {one[0].signs} among the candidates)")
    return out
