"""ocp.analytic against the printed values of Finch 2015 (reference/finch2015.toml) and against
computations that share nothing with it: mpmath quadrature at 30 digits, DOP853 integration of the
ODE with event detection, finite differences of the three-arc time."""

import math
from types import SimpleNamespace

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from ocp.core import problem as problems
from ocp.exact import finch as analytic
from ocp.papers import finch2015, references, verify

mp.mp.dps = 30
ODE = dict(method="DOP853", rtol=1e-13, atol=1e-13)


def printed(key):
    return references.value("finch2015", key)


def flow(x0, u, duration, kappa):
    sol = solve_ivp(lambda t, x: (x[1], kappa * u - math.sin(x[0])), (0.0, duration), x0, **ODE)
    return sol.y[:, -1]


def fly(bb):
    """The state reached from bb.x0 under bb's control, by DOP853."""
    x, u, t = bb.x0, bb.first_u, 0.0
    for ts in (*bb.switch_times, bb.T):
        x, u, t = flow(x, u, ts - t, bb.kappa), -u, ts
    return x


def mp_arc_time(u, theta0, omega0_squared, kappa, theta):
    """|int dphi / sqrt(omega0^2 + 2[cos phi - cos theta0 + kappa u (phi - theta0)])| at 30 digits
    (tanh-sinh handles the inverse-square-root end points)."""
    theta0, theta, kappa = mp.mpf(theta0), mp.mpf(theta), mp.mpf(kappa)
    w = lambda p: omega0_squared + 2 * (mp.cos(p) - mp.cos(theta0) + kappa * u * (p - theta0))
    return abs(mp.quad(lambda p: 1 / mp.sqrt(w(p)), mp.linspace(theta0, theta, 9)))


# --- the printed values ----------------------------------------------------------------------------

def test_every_printed_value_is_reproduced_or_explained():
    table = verify.rows("finch2015")
    assert not [r.key for r in table if r.verdict == "disagrees"]
    wrong = {r.key for r in table if r.verdict == "the paper is wrong"}
    assert wrong == {"t_inf_two_switch_kappa_3_4"}  # 5.8397 printed, 5.83992946706 computed
    solved_keys = {"n_one", "n_half", "n_three_quarters", "n_damping_one", "reshmin_damping_switches",
                   "reshmin_damping_gain"}                # by ocp.solve; the rest by the formulas
    for r in table:
        if r.computed is not None and r.key not in solved_keys:
            assert r.accuracy < 1e-12 * max(1.0, abs(r.computed))
    solved = {r.key: r for r in table if r.key in solved_keys}
    assert all(r.verdict == "agrees" and r.accuracy < 1e-6 for r in solved.values())


# --- arc times: independent quadrature and integration ---------------------------------------------

K1 = 1.0
THETA1 = math.pi / 2 + 1 / K1
ARCS = [  # (u, theta0, omega0, kappa, theta): rest at the start, rest at the end, no rest, u = 0
    (-1, math.pi / 2, 0.0, 1.0, 0.0),
    (+1, 0.0, 0.0, 1.0, math.pi / 2),
    (+1, 0.0, 0.0, 0.75, math.pi / 2 + 1 / 0.75),
    (-1, THETA1, math.sqrt(K1 * math.pi - 2 * math.sin(1 / K1)), K1, math.pi),
    (+1, 0.5, 1.3, 0.6, 2.0),
    (-1, 2.0, -0.3, 0.5, -1.0),
    (0, math.pi / 2, 0.0, 1.0, 0.0),
]


@pytest.mark.parametrize("u, theta0, omega0, kappa, theta", ARCS)
def test_arc_time_against_mpmath(u, theta0, omega0, kappa, theta):
    got = analytic.arc(u, theta0, omega0, 0.0, kappa, theta)
    w2 = mp.mpf(omega0) ** 2
    if (u, theta) == (-1, math.pi):  # the paper's T_-(pi/2 + 1/kappa, sqrt(kappa pi - 2 sin(1/kappa)), t1, kappa; pi):
        theta0, theta = mp.pi / 2 + 1 / mp.mpf(K1), mp.pi  # exactly at rest at pi (in floats, within rounding)
        w2 = K1 * mp.pi - 2 * mp.sin(1 / mp.mpf(K1))
    exact = mp_arc_time(u, theta0, w2, kappa, theta)
    assert abs(got.t - exact) <= got.error                  # the stated bound covers the true error
    assert got.error <= 1e-13 * exact                        # and is not vacuous
    assert abs(got.t - exact) <= 1e-15 * exact               # the accuracy the module doc claims


def test_arc_time_and_velocity_against_the_ode():
    """T_+(0, 0, 0, 1; pi/2) and T_-(pi/2, 0, 0, 1; 0): the time DOP853 takes to reach theta."""
    for u, theta0, theta in ((+1, 0.0, math.pi / 2), (-1, math.pi / 2, 0.0)):
        got = analytic.arc(u, theta0, 0.0, 0.0, 1.0, theta)
        hit = lambda t, x: x[0] - theta
        hit.terminal = True
        sol = solve_ivp(lambda t, x: (x[1], u - math.sin(x[0])), (0, 10), (theta0, 0.0), events=hit, **ODE)
        assert got.t == pytest.approx(sol.t_events[0][0], abs=1e-11)
        assert got.omega == pytest.approx(sol.y_events[0][0][1], abs=1e-11)


def test_arrival_velocities_are_elementary():
    """omega_- = -sqrt(2 + pi), omega_+ = sqrt(pi - 2) from the energy integral."""
    assert analytic.arc(-1, math.pi / 2, 0, 0, 1, 0).omega == pytest.approx(-math.sqrt(2 + math.pi), rel=1e-15)
    assert analytic.arc(+1, 0, 0, 0, 1, math.pi / 2).omega == pytest.approx(math.sqrt(math.pi - 2), rel=1e-15)


def test_arc_that_cannot_reach_is_refused():
    with pytest.raises(ValueError):
        analytic.arc(+1, 0.0, 0.0, 0.0, 0.5, math.pi)  # comes to rest first
    with pytest.raises(ValueError):
        analytic.arc(+1, 0.0, -1.0, 0.0, 1.0, 1.0)  # moves away


def test_free_swing_is_the_lemniscate_quarter_period():
    swing = analytic.free_swing(math.pi / 2)
    exact = mp.gamma(mp.mpf(1) / 4) ** 2 / (4 * mp.sqrt(mp.pi))
    assert abs(swing.t - exact) <= 1e-15 * exact
    assert abs(swing.t - mp.ellipk(mp.mpf(1) / 2)) <= 1e-15 * exact  # mpmath's ellipk takes m = k^2 too
    assert analytic.arc(0, math.pi / 2, 0, 0, 1, 0).t == pytest.approx(swing.t, rel=1e-15)
    assert swing.omega == pytest.approx(-math.sqrt(2), rel=1e-16)


# --- one switch --------------------------------------------------------------------------------------

def test_one_switch_bound_against_mpmath():
    g = lambda k: 1 - mp.pi * k + mp.sqrt(1 - k**2) + k * mp.asin(k)
    exact = mp.findroot(g, 0.72)
    assert abs(analytic.one_switch_bound() - exact) <= 4 * analytic.EPS
    with pytest.raises(ValueError, match="kappa >"):
        analytic.one_switch("swing-up", 0.72)


@pytest.mark.parametrize("kind, kappa", [("swing-up", 1.0), ("swing-up", 0.75), ("damping", 1.0), ("damping", 2.0)])
def test_one_switch_lands_on_target(kind, kappa):
    bb = analytic.one_switch(kind, kappa)
    assert np.allclose(fly(bb), bb.target, atol=1e-9)


@pytest.mark.parametrize("kappa", [1.0, 2.0])
def test_damping_against_mpmath(kappa):
    """Damping from (pi, 0): u = -1 from rest at pi down to theta1 = pi/2 + 1/kappa, then u = +1 from
    there (omega^2 = kappa pi - 2 sin(1/kappa), the energy integral) to rest at 0. Both arcs by
    30-digit quadrature, written out here for the damping direction: the code gets damping by
    reversing its swing-up, this test does not."""
    down = analytic.one_switch("damping", kappa)
    k = mp.mpf(kappa)
    theta1 = mp.pi / 2 + 1 / k
    t1 = mp_arc_time(-1, mp.pi, mp.mpf(0), k, theta1)
    T = t1 + mp_arc_time(+1, theta1, k * mp.pi - 2 * mp.sin(1 / k), k, 0)
    assert down.first_u == -1 and down.n_switches == 1
    assert abs(down.T - T) <= down.error and abs(down.switch_times[0] - t1) <= down.error
    omega1 = mp.sqrt(k * mp.pi - 2 * mp.sin(1 / k))
    assert down.switch_states[0] == pytest.approx((float(theta1), -float(omega1)), abs=down.error)


# --- two switches ------------------------------------------------------------------------------------

def test_printed_F_is_imaginary_and_the_corrected_one_is_omega():
    """On the u = -1 arc from (0, 0), omega^2 = 2[cos(theta) - 1 - kappa*theta]: at xi it equals the
    corrected F^2 (the arcs meet there), and the printed radicand is its negative."""
    kappa, rho = 0.5, printed("two_switch_half_rho")
    x = analytic.xi(rho, kappa)
    omega2 = 2 * (math.cos(x) - 1 - kappa * x)
    assert analytic.F(x, rho, kappa) ** 2 == pytest.approx(omega2, rel=1e-4)  # rho printed to 6 digits
    assert -2 * kappa * (x - rho) - 2 * (math.cos(x) - math.cos(rho)) < 0


@pytest.mark.parametrize("kappa", [0.5, 0.75])
def test_two_switch_lands_and_is_stationary(kappa):
    bb = analytic.two_switch("swing-up", kappa)
    assert np.allclose(fly(bb), (math.pi, 0.0), atol=1e-9)
    h = 1e-5
    slope = (analytic.three_arc_time(bb.rho + h, kappa) - analytic.three_arc_time(bb.rho - h, kappa)) / (2 * h)
    assert abs(slope) < 1e-8
    assert bb.T < min(analytic.three_arc_time(bb.rho + d, kappa) for d in (-1e-2, 1e-2))


@pytest.mark.parametrize("rho", [-0.9, -0.7])
def test_stationarity_is_the_derivative_of_the_three_arc_time(rho):
    h = 1e-5
    fd = (analytic.three_arc_time(rho + h, 0.6) - analytic.three_arc_time(rho - h, 0.6)) / (2 * h)
    assert analytic.stationarity(rho, 0.6)[0] == pytest.approx(fd, abs=1e-8)


def test_two_switch_time_against_shooting():
    """Printed t_inf,2 (5.8397...) against DOP853 shooting minimised over t1 (no quadrature): the
    formula and the shooting agree within their error estimates together, which are small."""
    shot = finch2015.shooting_time(0.75, (0.9, 1.1))
    two = analytic.two_switch("swing-up", 0.75)
    assert np.allclose(shot.x, (math.pi, 0.0), atol=1e-9) and shot.x_error < 1e-9
    assert abs(two.T - shot.T) <= shot.T_error + two.error and shot.T_error < 1e-9
    assert abs(two.switch_times[0] - shot.t1) <= shot.t1_error
    assert shot.T - printed("t_inf_two_switch_kappa_3_4") > 2e-4


def test_two_switch_claims_of_the_text():
    """At kappa = 3/4 two switches beat one (printed gain ~12.5 %); at kappa = 1/2 the middle arc
    pushes omega above 1.3 (its maximum, at theta = arcsin(kappa), is F(arcsin(kappa), rho))."""
    one, two = analytic.one_switch("swing-up", 0.75), analytic.two_switch("swing-up", 0.75)
    assert 100 * (one.T - two.T) / two.T == pytest.approx(printed("two_switch_gain_kappa_3_4"), abs=0.05)
    half = analytic.two_switch("swing-up", 0.5)
    assert analytic.F(math.asin(0.5), half.rho, 0.5) > 1.3


def test_two_switch_range():
    lo, hi = analytic.two_switch_range()
    for kappa in (lo + 1e-3, hi - 1e-3):
        bb = analytic.two_switch("damping", kappa)
        assert np.allclose(fly(bb), (0.0, 0.0), atol=1e-9)
    for kappa in (lo - 1e-3, hi + 1e-3, 1.0):
        with pytest.raises(ValueError, match="no two-switch"):
            analytic.two_switch("swing-up", kappa)


# --- constants ---------------------------------------------------------------------------------------

def test_gibbs_constant():
    exact = mp.quad(lambda z: mp.sin(z) / z, [0, mp.pi])
    series = mp.nsum(lambda j: (-1) ** j * mp.pi ** (2 * j + 1) / ((2 * j + 1) * mp.factorial(2 * j + 1)), [0, mp.inf])
    assert abs(exact - series) < 1e-25
    assert abs(analytic.gibbs_constant() - exact) <= 4e-16 * exact


# --- crosscheck --------------------------------------------------------------------------------------

def extremal_of(bb, branch, nudge=0.0):
    signs = tuple(bb.first_u * (-1) ** i for i in range(bb.n_switches + 1))
    return SimpleNamespace(branch=branch, signs=signs, switch_times=[t + nudge for t in bb.switch_times],
                           switch_states=list(bb.switch_states), T=bb.T)


def test_crosscheck_of_the_formula_itself_and_a_nudge():
    p = problems.swing_up(1.0)
    bb = analytic.one_switch("swing-up", 1.0)
    assert analytic.crosscheck(p, extremal_of(bb, 0)).max_deviation == 0
    check = analytic.crosscheck(p, extremal_of(bb, 0, nudge=1e-6))
    assert check.max_deviation == pytest.approx(1e-6) and check.formula.startswith("one-switch swing-up")


def test_crosscheck_mirror_images():
    """Swing-up to -pi (branch -1) and damping from -pi are theta -> -theta images."""
    up = analytic.one_switch("swing-up", 1.0)
    mirrored = SimpleNamespace(branch=-1, signs=(-1, 1), switch_times=list(up.switch_times),
                               switch_states=[(-up.switch_states[0][0], -up.switch_states[0][1])], T=up.T)
    assert analytic.crosscheck(problems.swing_up(1.0), mirrored).max_deviation == 0
    two = analytic.formula_for(problems.damping(0.5, (-math.pi, 0.0)), 0, 2, +1)
    assert np.allclose(fly(two), (0.0, 0.0), atol=1e-9)


def test_crosscheck_where_no_formula_applies():
    bb = analytic.one_switch("swing-up", 1.0)
    for problem, branch in ((problems.swing_up(1.0, (0.1, 0.0)), 0),  # other start
                            (problems.swing_up(1.0), 1)):  # target 3 pi
        assert analytic.crosscheck(problem, extremal_of(bb, branch)) is None
    assert analytic.crosscheck(problems.swing_up(0.5), extremal_of(bb, 0)) is None  # kappa below 0.7246
    three = SimpleNamespace(branch=0, signs=(1, -1, 1, -1), switch_times=[1, 2, 3], switch_states=[(0, 0)] * 3, T=4)
    assert analytic.crosscheck(problems.swing_up(0.5), three) is None
