"""Starts at the target's edge (issue 18, item 2): within 1e-15 .. 1e-6 of every branch, on the circle
and the plane, for kappa across the accepted range, the search's answer is the tiny transfer (or
T = 0 on the target), against an independent computation whose own error is estimated.

The reference: the offset x = theta - n pi from the branch (n pi in mpmath at 40 digits), the exact
dynamics x'' = kappa u - cos(n pi) sin x integrated by scipy's DOP853 in the scaled variables of the
double integrator (x = L xi, omega = V eta, t = tau s, V = max(|omega0|, sqrt(kappa |x0|)),
tau = V / kappa, L = V tau: xi'' = u - c tau^2 sin(L xi) / L), both orders of the arcs u = s then
-s shot by scipy.optimize.root from the double integrator's switch times, the least time kept
(every extremal faster than pi has at most one switch). Its error: ten times the change of T between
two tolerances of the integration (1e-13 and 1e-11). A start whose angle is the target's to rounding has x0 = 0
(`Problem.on_target_angle`, the convention of `Problem.at_target`).
"""

import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import solve_ivp

from ocp.core.problem import KAPPA_RANGE, make
from ocp.indirect import search


def offset(problem, k):
    """(x0, c): theta0 - n pi for the target n pi of branch k, and c = cos(n pi)."""
    n = round(problem.target(k)[0] / math.pi)
    if problem.on_target_angle(k):
        return 0.0, (-1) ** n
    with mpmath.workdps(40):
        return float(mpmath.mpf(problem.x0[0]) - n * mpmath.pi), (-1) ** n


def _end(c, eps, L, s, times, y0, rtol):
    """The scaled state after the arcs u = s for times[0], then -s for times[1]."""
    y = np.array(y0, float)
    for u, t in zip((s, -s), times):
        if t > 0:
            rhs = lambda _, z, u=u: [z[1], u - c * eps * z[0] * np.sinc(L * z[0] / np.pi)]
            y = solve_ivp(rhs, (0.0, t), y, method="DOP853", rtol=rtol, atol=rtol * 1e-3).y[:, -1]
    return y


def _shoot(c, eps, L, s, y0, guess, rtol):
    """The switch times (t1, t2) of the arcs u = s, then -s, from y0 to (0, 0): Newton's method with
    a forward-difference Jacobian, from `guess`."""
    t = np.array(guess, float)
    for _ in range(12):
        r = _end(c, eps, L, s, t, y0, rtol)
        h = 1e-7 * max(1.0, float(np.sum(np.abs(t))))
        J = np.column_stack([(_end(c, eps, L, s, t + h * e, y0, rtol) - r) / h for e in np.eye(2)])
        step = np.linalg.solve(J, r)
        t = t - step
        if np.sum(np.abs(step)) <= 1e-15 * np.sum(np.abs(t)):
            break
    return t


def reference(problem, k):
    """(T, its error): the least time of the transfer from the problem's start to branch k, shot
    at the tolerances 1e-13 and 1e-11 of the integration."""
    x0, c = offset(problem, k)
    omega0, kappa = problem.x0[1], problem.kappa
    V = max(abs(omega0), math.sqrt(kappa * abs(x0)))
    tau = V / kappa
    L, eps = V * tau, tau * tau
    y0 = ((x0 / V) * (kappa / V), omega0 / V)
    best = (math.inf, math.inf)
    for s in (1, -1):
        disc = 0.5 * y0[1] ** 2 - s * y0[0]
        if disc < 0 or -s * y0[1] + math.sqrt(disc) < 0:     # no transfer of this order (O(eps) from one)
            continue
        fine = _shoot(c, eps, L, s, y0, [-s * y0[1] + math.sqrt(disc), math.sqrt(disc)], 1e-13)
        coarse = _shoot(c, eps, L, s, y0, fine, 1e-11)
        if min(fine) >= -1e-9 and np.all(np.abs(_end(c, eps, L, s, fine, y0, 1e-13)) < 1e-11):
            T = tau * float(np.sum(np.maximum(fine, 0.0)))
            best = min(best, (T, 10 * tau * float(np.sum(np.abs(fine - coarse))) + 8 * 2.2e-16 * T))
    return best


def check(problem, k):
    found = search(problem)
    assert found.coverage.complete and found.best.branch == k
    fine, ref_error = reference(problem, k)
    assert ref_error <= 1e-10 * fine, "the reference is not accurate enough to test anything"
    assert abs(found.best.T - fine) <= found.best.T_error + ref_error, (found.best.T, fine, found.best.T_error)
    return found


@settings(max_examples=150, deadline=None, derandomize=True)
@given(kind=st.sampled_from(["damping", "swing-up"]), k=st.integers(-3, 3), plane=st.booleans(),
       log_kappa=st.floats(math.log10(KAPPA_RANGE[0]), math.log10(KAPPA_RANGE[1])),
       which=st.sampled_from(["theta", "omega", "both"]),
       dx=st.floats(-15, -6), dw=st.floats(-15, -6), sx=st.sampled_from([-1, 1]), sw=st.sampled_from([-1, 1]))
def test_a_start_at_the_edge_of_any_branch_gets_the_tiny_transfer(kind, k, plane, log_kappa, which, dx, dw, sx, sw):
    base = make(kind, 1.0)
    theta = base.target(k)[0] + (sx * 10 ** dx if which != "omega" else 0.0)
    omega = sw * 10 ** dw if which != "theta" else 0.0
    problem = make(kind, min(max(10 ** log_kappa, KAPPA_RANGE[0]), KAPPA_RANGE[1]), (theta, omega), k if plane else None)
    if problem.at_target() is not None:
        assert search(problem).best.T == 0.0
        return
    check(problem, k)


@pytest.mark.parametrize("args", [("damping", 1.0, (0.0, 1e-12), None), ("damping", 1e4, (0.0, 1e-10), None),
                                  ("damping", 1.0, (0.0, -1e-12), 0), ("swing-up", 1.0, (math.pi, 1e-12), None),
                                  ("damping", 1.0, (2 * math.pi, -1e-12), None)])
def test_the_probes_of_issue_18_get_the_tiny_transfer(args):
    """The starts that got T = 6.86, 0.0501, 12.23 and 'T = 0.000 (error 2e-3)': about
    (1 + sqrt 2) |omega0| / kappa (the double integrator's from (0, omega0))."""
    kind, kappa, x0, branch = args
    problem = make(kind, kappa, x0, branch)
    found = check(problem, problem.nearest_branch(x0[0]))
    assert found.best.T == pytest.approx((1 + math.sqrt(2)) * abs(x0[1]) / kappa, rel=1e-6)


@pytest.mark.parametrize("kind", ["damping", "swing-up"])
def test_a_start_on_the_target_to_rounding_is_there(kind):
    for k in range(-3, 4):
        theta = make(kind, 1.0).target(k)[0]
        for nudge in (0.0, math.nextafter(theta, math.inf) - theta, math.nextafter(theta, -math.inf) - theta):
            found = search(make(kind, 2.0, (theta + nudge, 0.0)))
            assert found.best.T == 0.0 and found.best.branch == k
