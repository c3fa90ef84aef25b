"""The vibrating-pivot inverted pendulum (ocp.scenes.kapitza, Weinstein; Tam)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import mathieu_a, mathieu_b

from ocp.papers import verify
from ocp.scenes import kapitza


def test_verify_table():
    table = {r.key: r for r in verify.rows("weinstein_tam")}
    assert all(r.verdict not in ("disagrees", "not reproduced") for r in table.values())
    wrong = {k for k, r in table.items() if r.verdict == "the paper is wrong"}
    assert wrong == {"cos_average", "fig4_stable_rad_s", "fig4_stable_2pi"}


@pytest.mark.parametrize("q", [0.013, 0.3, 0.9, 2.0])
def test_boundaries_against_scipy_mathieu(q):
    """a_0(q) and b_1(q) against scipy's characteristic values (Zhang and Jin's algorithm)."""
    a0, b1 = kapitza.boundaries(q)
    assert a0 == pytest.approx(mathieu_a(0, q), abs=1e-13)
    assert b1 == pytest.approx(mathieu_b(1, q), abs=1e-13)


def test_boundaries_against_series():
    """DLMF 28.6.1 and 28.6.4 (a_0 to q^8, b_1 to q^6: the next terms are < 1e-15 here), to the 1e-14 claimed."""
    q = 0.05
    a0, b1 = kapitza.boundaries(q)
    assert a0 == pytest.approx(-q**2 / 2 + 7 * q**4 / 128 - 29 * q**6 / 2304 + 68687 * q**8 / 18874368, abs=1e-14)
    assert b1 == pytest.approx(1 - q - q**2 / 8 + q**3 / 64 - q**4 / 1536 - 11 * q**5 / 36864 + 49 * q**6 / 589824, abs=1e-14)


@pytest.mark.parametrize("a, q", [(-0.3, 0.7), (0.2, 0.4), (-1.0, 1.5)])
def test_monodromy_from_half_period_against_full_period(a, q):
    """M from the half-period formula = the fundamental matrix integrated over the whole period."""
    def rhs(z, Y):
        p = a - 2 * q * math.cos(2 * z)
        return [Y[2], Y[3], -p * Y[0], -p * Y[1]]

    full = solve_ivp(rhs, (0, math.pi), [1, 0, 0, 1], method="DOP853", rtol=1e-13, atol=1e-16).y[:, -1].reshape(2, 2)
    M = kapitza.monodromy(a, q)
    assert np.allclose(M, full, rtol=0, atol=1e-11)
    assert np.linalg.det(M) == pytest.approx(1, abs=1e-12)


def strobe_trace(omega, periods, theta0=1e-6):
    """tr M estimated from a long nonlinear simulation of Tam (20) at small amplitude: samples
    theta_n one drive period apart obey theta_(n+1) - tr M theta_n + theta_(n-1) = 0 (Cayley-Hamilton,
    whatever the phase), solved for tr M by least squares."""
    T = 2 * math.pi / omega
    _, th = kapitza.simulate(kapitza.A, omega, theta0=theta0, t_end=periods * T,
                             t_eval=T * np.arange(periods + 1), rtol=1e-12)
    return np.dot(th[1:-1], th[2:] + th[:-2]) / np.dot(th[1:-1], th[1:-1])


@pytest.mark.parametrize("omega, periods, tol", [(2000.0, 200, 1e-7), (200.0, 30, 1e-5), (20.0, 3, 1e-4)])
def test_multipliers_against_long_nonlinear_simulation(omega, periods, tol):
    """Stable (2 - tr M = 3.5e-4, 200 periods) and unstable (max |mu| = 1.24 and 9.0) cases; the
    tolerance allows for the cubic terms at the amplitude reached (1e-6 max |mu|^periods)."""
    a, q = kapitza.mathieu_parameters(kapitza.A, omega)
    mu = kapitza.multipliers(a, q)
    trace = np.trace(kapitza.monodromy(a, q))
    assert np.real(mu.sum()) == pytest.approx(trace, abs=1e-12)
    assert strobe_trace(omega, periods) == pytest.approx(trace, abs=tol)
    assert (np.max(np.abs(mu)) > 1 + 1e-3) == (kapitza.stability(kapitza.A, omega) < 0)


@pytest.mark.parametrize("ratio", [1e-3, 1e-2])
def test_kapitza_limit(ratio):
    """For small A/l the exact lower boundary tends to Kapitza's A^2 w^2 = 2 g l, with relative
    correction 7 (A/l)^2 / 32 (from the series of a_0)."""
    A = ratio * kapitza.L
    lower, upper = kapitza.critical_frequencies(A)
    assert upper == math.inf
    assert lower / kapitza.kapitza_frequency(A) - 1 == pytest.approx(7 * ratio**2 / 32, rel=0.02)


def test_upper_boundary_appears_at_b1_zero():
    """w_upper is finite iff b_1(2A/l) < 0, i.e. A/l > 0.4540 (b_1(0.90805) = 0, scipy's mathieu_b)."""
    assert mathieu_b(1, 0.9080) > 0 > mathieu_b(1, 0.9081)
    assert kapitza.critical_frequencies(0.4539 * kapitza.L)[1] == math.inf
    lower, upper = kapitza.critical_frequencies(0.4541 * kapitza.L)
    assert lower < upper < math.inf


def test_the_devices_floquet_threshold_against_the_series():
    """The exact lower boundary of the papers' device (l = 0.20 m, A = 1.3 mm, g = 9.8) is
    w = 2 sqrt(g / (-a_0(q) l)) at q = 2A/l = 0.013. Reference: the power series of a_0(q), DLMF
    28.6.1 (NIST Digital Library of Mathematical Functions, eq. 28.6.1; McLachlan, Theory and
    Application of Mathieu Functions, 1947, sec. 2.151), to q^8: the next term is below 1e-18 at this
    q, far below the 1e-10 relative (1e-14 in a_0 over |a_0| = 8.4e-5) the module doc claims for w.
    The series shares nothing with the code's Brent-on-the-half-period computation."""
    q = 2 * kapitza.A / kapitza.L
    a0 = -q**2 / 2 + 7 * q**4 / 128 - 29 * q**6 / 2304 + 68687 * q**8 / 18874368
    exact = 2 * math.sqrt(kapitza.G / (-a0 * kapitza.L))          # 1523.01329650919 rad/s
    assert kapitza.critical_frequencies(kapitza.A)[0] == pytest.approx(exact, rel=1e-10)
    # Kapitza's A^2 w^2 = 2 g l keeps only -q^2/2 of a_0: it is low by 7 q^2 / 128 relative (the q^4 term)
    assert exact / kapitza.kapitza_frequency(kapitza.A) - 1 == pytest.approx(7 * q**2 / 128, rel=1e-3)


def test_examples_and_criteria():
    """Tam's criterion for the device, sqrt(sqrt(2) g / A) = 103.3 rad/s (his (31)); all four
    readings of Weinstein's Figures 4 and 5 are unstable, Tam's criterion calls three stable."""
    assert kapitza.tam_frequency(kapitza.A) == pytest.approx(math.sqrt(math.sqrt(2) * 9.8 / 0.0013))
    rows = kapitza.examples_table()
    assert [r["floquet"] for r in rows] == [-1, -1, -1, -1]
    assert [r["tam"] for r in rows] == [1, 1, -1, 1]


def test_figures():
    """Tam Figure 3 (assumed w = 2000 rad/s) stays up; Weinstein Figure 4 falls in both readings."""
    figs = kapitza.figures()
    assert figs["tam_fig3"]["stable"] == 1 and np.max(np.abs(figs["tam_fig3"]["theta"])) < 0.2
    for name in ("weinstein_fig4_rad_s", "weinstein_fig4_2pi", "weinstein_fig5_rad_s", "weinstein_fig5_2pi"):
        assert figs[name]["stable"] == -1 and np.max(np.abs(figs[name]["theta"])) > math.pi / 2
