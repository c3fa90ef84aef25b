"""Falling time of the inverted pendulum (ocp.scenes.falling, Batista and Peternelj 2006)."""

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.special import ellipkinc

from ocp.papers import references, verify
from ocp.scenes import falling


def quadrature(theta0, a, dps=30):
    """I(theta0, a) of (8) by mpmath tanh-sinh quadrature at `dps` digits, independent of the
    closed form: theta = theta0 + u^2 removes the endpoint singularity at a = 0, and
    cos(theta0) - cos(theta) = 2 sin(theta0 + u^2/2) sin(u^2/2) keeps the integrand exact."""
    with mp.workdps(dps):
        t0, a = mp.mpf(theta0), mp.mpf(a)
        end = mp.sqrt(mp.pi / 2 - t0)
        cuts = [c for c in (mp.sqrt(t0) / 4, mp.sqrt(t0), 4 * mp.sqrt(t0)) if 0 < c < end]
        return mp.quad(lambda u: 2 * u / mp.sqrt(2 * a**2 + 2 * mp.sin(t0 + u**2 / 2) * mp.sin(u**2 / 2)),
                       [0, *cuts, end])


def paper_F(x, k):
    """The paper's F(x, k) of (27) (argument x = sin(phi), modulus k) in scipy's convention."""
    return ellipkinc(np.arcsin(x), k**2)


def paper_I(theta0, a):
    """I(theta0, a) by the paper's case formulas (16), (21), (23), as printed."""
    c = math.cos(theta0 / 2)
    k = math.sqrt(a**2 + c**2)
    if k < 1:
        return math.sqrt(2) * (paper_F(c / k, k) - paper_F(math.sqrt(2) / (2 * k), k))
    if k == 1:
        return math.sqrt(2) * (math.log(math.sqrt(2) - 1) - math.log(math.tan(theta0 / 4)))
    return math.sqrt(2) / k * (paper_F(c, 1 / k) - paper_F(math.sqrt(2) / 2, 1 / k))


# (theta0, a) in the three cases of (13): k < 1 (a < sin(theta0/2)), k = 1, k > 1, near k = 1 too
CASES = [(math.pi / 48, 0.0), (0.3, 0.05), (1.2, 0.1), (1e-3, 4e-4), (1.0, math.sin(0.5)), (0.3, math.sin(0.15)),
         (0.3, 0.5), (0.0, 0.3), (1e-3, 6e-4), (1.5, 2.0)]


@pytest.mark.parametrize("theta0, a", CASES)
def test_closed_form_against_30_digit_quadrature(theta0, a):
    exact = float(quadrature(theta0, a))
    assert abs(float(falling.falling_integral(theta0, a)) - exact) <= 2e-15 * max(1.0, exact)


@pytest.mark.parametrize("theta0, a", [c for c in CASES if c[0] > 0.01])
def test_paper_case_formulas_16_21_23(theta0, a):
    """The printed Legendre forms, with x = sin(phi) -> phi = arcsin(x) and k -> m = k^2 for scipy,
    agree with the closed form (away from theta0 -> 0, where arcsin loses the digits)."""
    assert paper_I(theta0, a) == pytest.approx(float(falling.falling_integral(theta0, a)), rel=1e-12)


def test_table1_pi48_which_print_is_right():
    """Table 1 prints 5.55096041 (Formula (17)) and 5.55096159 (Maple numerical) for pi/48
    (reference keys t1_formula17_pi48, t1_maple_pi48): 30-digit quadrature decides for the first."""
    exact = quadrature(mp.pi / 48, 0)
    assert mp.nstr(exact, 9) == "5.55096041"
    assert references.value("batista2006", "t1_formula17_pi48") == float(mp.nstr(exact, 9))
    assert abs(references.value("batista2006", "t1_maple_pi48") - float(exact)) > 1e-6


def test_verify_table():
    table = {r.key: r for r in verify.rows("batista2006")}
    assert all(r.verdict != "disagrees" for r in table.values())
    assert all(r.verdict != "not reproduced" for r in table.values())
    wrong = {k for k, r in table.items() if r.verdict == "the paper is wrong"}
    assert wrong == {"t1_maple_pi48", "diff_18_19"}


def test_asymptotics():
    """(18) is the limit of I(theta0, 0), with error O(theta0^2 ln(1/theta0)); (19) misses it by sqrt(2) ln 2."""
    for theta0 in (1e-2, 1e-3, 1e-4):
        err = float(falling.falling_integral(theta0)) - float(falling.asymptotic18(theta0))
        assert 0 < err < theta0**2 * math.log(1 / theta0) / 8
    assert float(falling.asymptotic18(0.2) - falling.asymptotic19(0.2)) == pytest.approx(math.sqrt(2) * math.log(2))


def test_falling_time_units_and_conventions():
    """T(theta0, omega0) with L, g in seconds is sqrt(L/g) times the suite's nondimensional time
    from theta = pi - theta0, omega = -omega0 sqrt(L/g)."""
    L, g, theta0, omega0 = 0.7, 9.81, 0.2, 1.3
    T = falling.falling_time(theta0, omega0, L, g)
    assert T == pytest.approx(math.sqrt(L / g) * falling.time_to_ground((math.pi - theta0, -omega0 * math.sqrt(L / g))), rel=1e-15)
    with pytest.raises(ValueError):
        falling.falling_time(theta0, -1.0)


def test_uncertainty_example_against_26():
    """(26), T = sqrt(L/g) [ln(4 (sqrt(2) - 1)) - ln sqrt(hbar/(2 m L^2) sqrt(L/g))] (key T_uncertainty)."""
    L, m, g, hbar = 0.1, 0.001, 9.8, falling.HBAR
    T26 = math.sqrt(L / g) * (math.log(4 * (math.sqrt(2) - 1)) - 0.5 * math.log(hbar / (2 * m * L**2) * math.sqrt(L / g)))
    assert falling.uncertainty_time() == pytest.approx(T26, rel=1e-14)


# x0 in the suite's convention: (theta, omega), from rest near the upright, and thrown (k > 1)
FALLS = [(math.pi - 0.1, 0.0), (math.pi - math.pi / 180, 0.0), (math.pi - 0.3, -1.5)]


@pytest.mark.parametrize("x0", FALLS)
@pytest.mark.parametrize("method", ["DOP853", "Radau", "LSODA"])
def test_scipy_integrators_against_closed_form(x0, method):
    exact = falling.time_to_ground(x0)
    assert falling.fall_time_scipy(x0, method, rtol=1e-12, atol=1e-12) == pytest.approx(exact, rel=1e-8)


@pytest.mark.parametrize("x0", FALLS)
@pytest.mark.parametrize("plugin, opts", [("cvodes", {"abstol": 1e-12, "reltol": 1e-12}),
                                          ("idas", {"abstol": 1e-12, "reltol": 1e-12}),
                                          ("collocation", {"number_of_finite_elements": 20, "interpolation_order": 4})])
def test_casadi_integrators_against_closed_form(x0, plugin, opts):
    exact = falling.time_to_ground(x0)
    assert falling.fall_time_casadi(x0, plugin, **opts) == pytest.approx(exact, rel=1e-8)


def test_no_cancellation_near_the_ground():
    """Near theta0 = pi/2, I is small and must keep its absolute accuracy. Reference: the same
    Carlson form evaluated in 60-digit arithmetic (mpmath.elliprf), an independent evaluation."""

    def high_precision(theta0):
        with mp.workdps(60):
            th = mp.mpf(theta0)
            c, s = mp.cos(th / 2), mp.sin(th / 2)
            k2 = c * c
            return float(mp.sqrt(2) * (c * mp.elliprf(0, k2 * s * s, k2) - mp.elliprf(2 * k2 - 1, k2, 2 * k2)))

    for theta0 in (math.pi / 2, math.pi / 2 - 1e-10, math.pi / 2 - 1e-6):
        assert abs(falling.falling_integral(theta0) - high_precision(theta0)) < 1e-15
