"""Finch 2015, "Swing-up control of a pendulum": every printed value of `data/finch2015.toml`,
computed. The formulas by `ocp.exact.finch` (quadrature with error bounds); the claims that need a
solve (the switch counts N_kappa(x0) of the standard transfers, Reshmin's damping example) by
`ocp.solve`, whose complete search of extremals proves the optimum (a count is exact when the
search's verdict is "globally optimal", of unknown accuracy otherwise); the misprinted t_inf,2 by
an independent DOP853 shooting."""

import math
from typing import NamedTuple

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from ..core.numbers import digits, order, plus_minus
from ..core.problem import damping, swing_up
from ..exact.finch import (EPS, F, stationarity_term, arc, free_swing, gibbs_constant, one_switch,
                           one_switch_bound, two_switch)
from ..solving import solve
from .verify import Reproduction


class Shot(NamedTuple):
    """The least time of the shooting (`shooting_time`): T, t1 and the landing state x, each with
    its error estimate."""

    T: float
    T_error: float
    t1: float
    t1_error: float
    x: tuple
    x_error: float


def shooting_time(kappa, t1_bounds, xatol=1e-6, rtol=1e-13):
    """Independent of every quadrature here: the least time of u = -1, +1, -1 from (0, 0) to
    (pi, 0), by DOP853 (rtol = atol = `rtol`) with event detection: u = -1 for t1, u = +1 until
    omega^2 = 2[cos(theta) + 1 + kappa*(pi - theta)] (the arc into (pi, 0)), u = -1 until omega = 0;
    T minimised over t1 in t1_bounds by bounded Brent to `xatol` in t1.

    Error estimates (computed, not assumed): t1 to `xatol` (Brent's stopping bracket); T: the change
    of T across t1 +- xatol (T is stationary, so this is second order) plus the change of T and of
    the landing state when the integration runs at 100 rtol instead (the second tolerance)."""
    def flow(u, t0, x0, event, tol):
        event.terminal = True
        sol = solve_ivp(lambda t, x: (x[1], kappa * u - math.sin(x[0])), (t0, t0 + 100.0), x0,
                        method="DOP853", rtol=tol, atol=tol, events=event)
        return sol.t_events[0][0], sol.y_events[0][0]

    def land(t1, tol=rtol):
        t, x = flow(-1, 0.0, (0.0, 0.0), lambda t, x: t - t1, tol)
        meet = lambda t, x: x[1] ** 2 - 2 * (math.cos(x[0]) + 1 + kappa * (math.pi - x[0])) if x[1] > 0 else -1.0
        t, x = flow(+1, t, x, meet, tol)
        return flow(-1, t, x, lambda t, x: x[1], tol)

    best = minimize_scalar(lambda t1: land(t1)[0], bounds=t1_bounds, method="bounded", options={"xatol": xatol})
    T, x = land(best.x)
    T_loose, x_loose = land(best.x, 100 * rtol)
    flat = max(abs(land(best.x + d)[0] - T) for d in (-xatol, xatol))
    return Shot(float(T), float(flat + abs(T_loose - T)), float(best.x), xatol, tuple(map(float, x)),
                float(np.max(np.abs(x_loose - x))))


def reproduce():
    """Every value of data/finch2015.toml the suite computes: key -> Reproduction."""
    out = dict(solved_claims(), **bifurcation_values())

    def put(key, value, accuracy, how, evidence="", erratum=""):
        out[key] = Reproduction(float(value), float(accuracy), how, evidence, erratum)

    swing = free_swing(math.pi / 2)
    put("free_swing_time", swing.t, swing.error, "K(m = 1/2) = Gamma(1/4)^2/(4 sqrt(pi)), scipy.special.ellipk")
    put("free_swing_velocity", swing.omega, 4 * EPS, "-2 sin(pi/4) = -sqrt(2)")
    down, up = arc(-1, math.pi / 2, 0.0, 0.0, 1.0, 0.0), arc(+1, 0.0, 0.0, 0.0, 1.0, math.pi / 2)
    put("t_minus_half_pi_to_0", down.t, down.error, "arc(-1, pi/2, 0, 0, 1, 0): quadrature, rest end removed")
    put("t_plus_0_to_half_pi", up.t, up.error, "arc(+1, 0, 0, 0, 1, pi/2): quadrature, rest end removed")
    put("omega_minus", down.omega, 8 * EPS, "energy integral: -sqrt(2 + pi) (no ODE solver needed)")
    put("omega_plus", up.omega, 8 * EPS, "energy integral: sqrt(pi - 2) (no ODE solver needed)")

    k1 = one_switch_bound()
    g = 1 - math.pi * k1 + math.sqrt(1 - k1 * k1) + k1 * math.asin(k1)
    # the root's error: the residual (and its rounding, on terms of size 3 + pi k) over the slope
    # g'(k) = arcsin(k) - pi, plus the rounding of k itself
    e_k1 = (abs(g) + 8 * EPS * (3 + math.pi * k1)) / abs(math.asin(k1) - math.pi) + 2 * EPS * k1
    put("one_switch_kappa_min", k1, e_k1, "brentq root of g = 1 - pi k + sqrt(1 - k^2) + k arcsin k; accuracy "
        "|g|/|g'| at the root plus rounding")
    put("one_switch_phi_min", math.pi - math.asin(k1), e_k1 / math.sqrt(1 - k1 * k1) + 4 * EPS * math.pi,
        "pi - arcsin(kappa_1), kappa_1's error carried through arcsin")
    swing_up, damping = one_switch("swing-up", 1.0), one_switch("damping", 1.0)
    how = "one_switch('{}', {}): switch at (pi/2 + 1/kappa, +-sqrt(kappa pi - 2 sin(1/kappa))), arc quadratures"
    put("figure1_switch_theta", swing_up.switch_states[0][0], 4 * EPS, "pi/2 + 1/kappa at kappa = 1")
    put("figure1_switch_omega", swing_up.switch_states[0][1], 8 * EPS, "sqrt(pi - 2 sin 1)")
    put("t1_swing_up_kappa_1", swing_up.switch_times[0], swing_up.error, how.format("swing-up", 1))
    put("t_inf_swing_up_kappa_1", swing_up.T, swing_up.error, how.format("swing-up", 1))
    put("t1_damping_kappa_1", damping.switch_times[0], damping.error, how.format("damping", 1))
    put("t_inf_damping_kappa_1", damping.T, damping.error, how.format("damping", 1))
    one = one_switch("swing-up", 0.75)
    put("t_inf_one_switch_kappa_3_4", one.T, one.error, how.format("swing-up", 0.75))

    half, three_quarters = two_switch("swing-up", 0.5), two_switch("swing-up", 0.75)
    rho, (x1, w1), (x2, w2) = half.rho, *half.switch_states
    # the printed numerator with the real F: 1/F(x) + int_rho^x (sin u - sin rho)/F^3 du at x = xi, eta
    flipped = [stationarity_term(rho, x, 0.5)[0] + 2 / F(x, rho, 0.5) for x in (x1, x2)]
    e = half.error
    e_flipped = sum(stationarity_term(rho, x, 0.5)[1] for x in (x1, x2)) + sum(
        (2 / F(x, rho, 0.5) ** 3) * (abs(math.sin(x)) + 0.5 + 1) * e + 8 * EPS / F(x, rho, 0.5) for x in (x1, x2))
    erratum = (f"the printed F(u, rho) = sqrt(-2 kappa (u - rho) - 2[cos u - cos rho]) is imaginary on the middle arc: "
               f"at kappa = 1/2, rho = {digits(rho, e)} its radicand is {digits(-w1 ** 2, 2 * abs(w1) * e)} = "
               f"-omega1^2 at u = xi and {digits(-w2 ** 2, 2 * abs(w2) * e)} = -omega2^2 at u = eta. With the real "
               f"F = |omega| = sqrt(+2 kappa (u - rho) + 2[cos u - cos rho]) the numerator must be sin u - sin rho "
               f"(stationarity, checked against finite differences of the three-arc time); with the printed "
               f"numerator the left side is {plus_minus(sum(flipped), e_flipped)}, not 0, at this rho. Read with "
               f"complex F = i|omega| the printed equation is -i times the right one, so the printed rho values stand")
    how2 = "two_switch('swing-up', {}): root of dT/drho (corrected equation), arc quadratures"
    put("two_switch_half_rho", rho, half.error, how2.format(0.5), erratum=erratum)
    put("two_switch_3_4_rho", three_quarters.rho, three_quarters.error, how2.format(0.75))
    for key, bb in (("half", half), ("3_4", three_quarters)):
        put(f"two_switch_{key}_theta1", bb.switch_states[0][0], bb.error, "xi(rho) = rho/2 + (cos rho - 1)/(2 kappa)")
        put(f"two_switch_{key}_theta2", bb.switch_states[1][0], bb.error, "eta(rho) = xi(rho) + pi/2 + 1/kappa")
    for i, name in ((0, "switch1"), (1, "switch2")):
        put(f"figure2_{name}_theta", half.switch_states[i][0], half.error, how2.format(0.5))
        put(f"figure2_{name}_omega", half.switch_states[i][1], half.error, how2.format(0.5) + ": -+F(xi or eta, rho)")
    shot = shooting_time(0.75, (0.9, 1.1))
    miss = math.hypot(shot.x[0] - math.pi, shot.x[1])
    put("t_inf_two_switch_kappa_3_4", three_quarters.T, three_quarters.error, how2.format(0.75),
        f"independently, DOP853 shooting (u = -1 for t1, u = +1 to the arc into (pi, 0), u = -1 to rest) "
        f"minimised over t1 gives T = {digits(shot.T, shot.T_error)} at t1 = {plus_minus(shot.t1, shot.t1_error)}, "
        f"landing {order(miss)} from (pi, 0) (integration error {order(shot.x_error)}); no two-switch transfer "
        f"arrives by 5.8397 (likely a misprint of 5.8399)")
    T1, T2 = one.T, three_quarters.T
    gain = 100 * (T1 - T2) / T2
    put("two_switch_gain_kappa_3_4", gain, 100 * (one.error + three_quarters.error) / T2
        + abs(gain) * three_quarters.error / T2 + 4 * EPS * abs(gain),
        "100 (t_inf,1 - t_inf,2)/t_inf,2 from the two transfers, in %; accuracy from their error bounds")
    G = gibbs_constant()
    # independently: the alternating series of the paper, summed exactly rounded (math.fsum); its
    # terms fall below EPS * G after j = 12, and the tail of an alternating series is below its first term
    series = math.fsum((-1) ** j * math.pi ** (2 * j + 1) / ((2 * j + 1) * math.factorial(2 * j + 1)) for j in range(30))
    e_G = abs(G - series) + 4 * EPS * G
    put("gibbs_G", G, e_G, "Si(pi), scipy.special.sici; accuracy: its distance from the series, plus rounding")
    put("gibbs_G_half", G / 2, e_G / 2, "Si(pi)/2")
    return out


def _count(problem):
    """The optimal switch count from a solve, exact when the search proves the optimum."""
    sol = solve(problem)
    how = f"switch count of ocp.solve from {problem.x0} to branch {problem.branch}: {sol.verdict}"
    return Reproduction(sol.n_switches, 0.0 if sol.optimal else math.inf, how), sol


def solved_claims():
    """N_kappa(x0) of the standard transfers (Finch pins the target (pi, 0) or (0, 0): the plane,
    branch 0) and Reshmin's damping example from (-100, 14.16), kappa = 1, on the plane (theta = 0
    pinned): two switches, 0.27 % faster than one."""
    out = {}
    for key, problem in (("n_one", swing_up(1.0, branch=0)), ("n_half", swing_up(0.5, branch=0)),
                         ("n_three_quarters", swing_up(0.75, branch=0)), ("n_damping_one", damping(1.0, branch=0))):
        out[key] = _count(problem)[0]
    out["reshmin_damping_switches"], sol = _count(damping(1.0, x0=(-100.0, 14.16), branch=0))
    one = next((e for e in sol.extremals if e.n_switches == 1), None)
    if sol.optimal and sol.n_switches == 2 and one is not None:
        T1, T2, e1, e2 = one.T, sol.T, one.T_error, sol.T_error
        gain = 100 * (T1 - T2) / T2
        out["reshmin_damping_gain"] = Reproduction(
            gain, 100 * (e1 + e2) / T2 + abs(gain) * e2 / T2,
            f"100 (T1 - T2)/T2 with T2 = {plus_minus(T2, e2)} (the optimum, two switches) and T1 = {plus_minus(T1, e1)} "
            f"(the fastest one-switch extremal, {one.signs}), both from the complete search")
    return out


def bifurcation_values():
    """The bifurcation values Finch prints (quoting Reshmin), from the results `ocp bifurcation`
    stored with the package (`ocp.synthesis.results.stored`): each with its error bar and reading.
    Reshmin's values agree with the circle reading (any branch of the target)."""
    from ..synthesis.results import PUBLISHED, stored

    rows = stored()
    out = {}
    for case, (key, _) in PUBLISHED.items():
        row = rows.get(case)
        if row is None:
            continue
        theta, omega = row["state"]
        out[key] = Reproduction(row["kappa"], row["error"], (
            f"ocp bifurcation, case {case} (the {row['reading']}), at commit {row['commit']}: {row['mechanism']}; "
            f"attained at (theta, omega) = ({math.remainder(theta, 2 * math.pi):.6f}, {omega:.6f}) modulo 2 pi"))
    return out
