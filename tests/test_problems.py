"""Problems as plain data: validation, branches, and the model in both numpy and CasADi."""

import math

import casadi as ca
import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from ocp import MultipleShooting, damping, swing_up
from ocp.core import model
from ocp.core.errors import InputError
from ocp.core.problem import Problem, make


@pytest.mark.parametrize("kappa", [0, -1, float("nan"), float("inf"), "abc", None])
def test_bad_kappa_is_rejected_with_what_is_accepted(kappa):
    with pytest.raises(InputError, match="kappa"):
        swing_up(kappa)


@pytest.mark.parametrize("x0", [(1.0,), (1.0, 2.0, 3.0), ("a", 0.0), (float("nan"), 0.0), 5.0])
def test_bad_x0_is_rejected(x0):
    with pytest.raises(InputError):
        damping(1.0, x0=x0)


def test_unknown_problem_and_bad_branch():
    with pytest.raises(InputError, match="swing-up, damping"):
        make("pendulum", 1.0)
    with pytest.raises(InputError, match="branch"):
        swing_up(1.0, branch=0.5)


@pytest.mark.parametrize("kwargs, match", [({"N": 1}, "N"), ({"N": 2.5}, "N"), ({"integrator": "euler"}, "rk4, collocation, cvodes"),
                                           ({"M": 0}, "M"), ({"tol": 0.0}, "tol")])
def test_bad_method_settings(kwargs, match):
    with pytest.raises(InputError, match=match):
        MultipleShooting(**kwargs)


def test_targets_are_branches_of_the_circle():
    p = swing_up(1.0)
    assert p.target(0) == (math.pi, 0.0) and p.target(-1) == (-math.pi, 0.0)
    assert damping(1.0).target(1) == (2 * math.pi, 0.0)
    # ties between two branches go to the smaller |k|
    assert p.nearest_branch(0.0) == 0
    assert damping(1.0).nearest_branch(math.pi) == 0
    assert p.nearest_branch(-3.0) == -1 and damping(1.0).nearest_branch(7.0) == 1
    assert swing_up(1.0, branch=-2).guess_branch == -2


def test_problem_is_plain_serialisable_data():
    p = swing_up(0.5, x0=(0.1, -0.2), branch=1)
    assert Problem(**p.to_dict()) == p


def test_model_numpy_and_casadi_agree():
    x, u, kappa = np.array([0.7, -1.3]), 0.4, 0.8
    xs, us = ca.SX.sym("x", 2), ca.SX.sym("u")
    f = ca.Function("f", [xs, us], [model.rhs(xs, us, kappa)])
    assert np.allclose(np.array(f(x, u)).ravel(), model.rhs(x, u, kappa), rtol=0, atol=1e-15)
    assert model.rhs(x, u, kappa)[1] == pytest.approx(kappa * u - math.sin(0.7), abs=1e-15)
    # the arc invariant is conserved along the flow: d/dt = omega*(omega' + sin(theta) - kappa*u) = 0
    xdot = model.rhs(x, u, kappa)
    grad = np.array([math.sin(x[0]) - kappa * u, x[1]])
    assert grad @ xdot == pytest.approx(0.0, abs=1e-15)
    assert model.energy(np.array([0.0, 0.0])) == -1 and model.energy(np.array([math.pi, 0.0])) == 1


def tent_time(f0, f1, d, kappa):
    """The transit bound from its definition: the least T >= |f1 - f0| / kappa whose tent integral of
    min(f0 + kappa t, f1 + kappa (T - t)) over [0, T] (trapezoids on 20001 points, exact for the two
    linear pieces up to the kink) covers the angle d, by bisection."""
    covered = lambda T: np.trapezoid(np.minimum(f0 + kappa * (t := np.linspace(0, T, 20001)), f1 + kappa * (T - t)), t)
    lo, hi = abs(f1 - f0) / kappa, abs(f1 - f0) / kappa + 10 * math.sqrt(d / kappa) + 10 * d + 1
    if covered(lo) >= d:
        return lo
    for _ in range(50):
        lo, hi = (lo, (lo + hi) / 2) if covered((lo + hi) / 2) >= d else ((lo + hi) / 2, hi)
    return hi


def energy_bound(problem, k):
    """The energy bound to branch k from its definition: `tent_time` from F0 to the target's F* over
    |theta*_k - theta0|; for a start moving away from a target behind its first turning point, which is
    at least reach = (E0 - 1) / kappa on (where E = omega^2 / 2 - cos(theta) <= 1), also the way there
    (to F = 2) and back (from the best F in [0, 2], by scipy's bounded minimisation: the time is
    unimodal in it; its ends too)."""
    (theta0, omega0), kappa = problem.x0, problem.kappa
    f0, f1 = math.sqrt(omega0**2 + 2 * (1 - math.cos(theta0))), math.sqrt(2 * (1 - math.cos(problem.base)))
    one_way = tent_time(f0, f1, abs(problem.target(k)[0] - theta0), kappa)
    reach = (omega0**2 / 2 - math.cos(theta0) - 1) / kappa
    back = math.copysign(1, omega0) * (theta0 - problem.target(k)[0]) + reach
    if reach <= 0 or back <= 0:
        return one_way
    time = lambda f: tent_time(f, f1, back, kappa)
    least = minimize_scalar(time, bounds=(0.0, 2.0), method="bounded", options={"xatol": 1e-10})
    return max(one_way, tent_time(f0, 2.0, reach, kappa) + min(least.fun, time(0.0), time(2.0)))


@pytest.mark.parametrize("branch", [None, 2, -1])
def test_the_gap_to_the_targets_is_the_least_distance_to_a_target_angle_outside_an_interval(branch):
    """`Problem.gap` against the distances to the target angles listed one by one (branches -5 to 5)."""
    problem = make("swing-up", 1.0, branch=branch)
    rng = np.random.default_rng(5)
    for lo in rng.uniform(-30, 30, 200):
        hi = lo + float(rng.exponential(2.0))
        angles = [problem.target(k)[0] for k in range(-5, 6) if branch is None or k == branch]
        expected = 0.0 if any(lo <= x <= hi for x in angles) else min(min(abs(x - lo), abs(x - hi)) for x in angles)
        assert problem.gap(lo, hi) == pytest.approx(expected, abs=1e-12)


def test_lower_bound_is_the_least_over_every_branch():
    """On the plane, the larger of the double-integrator bound and of the energy bound against their
    definitions (`energy_bound`); on the circle, below the least of those over 4001 branches (a fast
    start (0, 20) at kappa = 1 stops about 100 rad away, far from the branches near theta0: there the
    old double-integrator bound gave 22.98 against the optimum 19.552 of the complete search), and not
    below the one-way energy bound at the branch nearest theta0 (the bound before the turn was counted)."""
    rng = np.random.default_rng(7)
    for _ in range(40):
        kind = ("swing-up", "damping")[rng.integers(2)]
        kappa = float(rng.uniform(0.05, 10))
        x0 = (float(rng.uniform(-1000, 1000)), float(rng.uniform(-50, 50)))
        p = make(kind, kappa, x0)
        a, (theta0, omega0) = kappa + 1, x0
        k0 = p.nearest_branch(theta0)

        def bound(k):
            d = p.target(k)[0] - theta0
            s = 1.0 if d > omega0 * abs(omega0) / (2 * a) else -1.0
            return (-s * omega0 + 2 * math.sqrt(max(0.0, s * a * d + omega0**2 / 2))) / a

        stop = p.nearest_branch(p.stop_angle)        # where the energy bound's turn is (gravity neglected)
        branches = [*range(k0 - 2000, k0 + 2001), *range(stop - 3, stop + 4)]
        pinned = {k: make(kind, kappa, x0, k).lower_bound for k in branches if abs(p.target(k)[0] - theta0) <= 1000}
        assert p.lower_bound <= min(pinned.values()) * (1 + 1e-12)
        f0, f1 = math.hypot(omega0, 2 * math.sin(theta0 / 2)), 2 * abs(math.sin(p.base / 2))
        one_way = tent_time(f0, f1, abs(p.target(k0)[0] - theta0), kappa)
        assert p.lower_bound >= max(min(bound(k) for k in range(k0 - 2000, k0 + 2001)), one_way) * (1 - 1e-7)
        for k in (k0 + int(rng.integers(-150, 151)), stop - 1 + 2 * (_ % 2)):    # the plane: that branch only
            if k in pinned:
                assert pinned[k] == pytest.approx(max(bound(k), energy_bound(p, k)), rel=1e-7)
    assert make("swing-up", 1.0, (0.0, 20.0)).lower_bound < 19.552


def test_the_transit_over_a_box_of_states_is_below_the_transit_from_each():
    """`Problem.transit` over theta in [lo, hi], e in [e_lo, e_hi] with omega's sign known is below its
    value at every state of the box (the states on a 9 x 9 grid, each the energy bound of a start there,
    `lower_bound`, checked against its definition above), on both readings; with the sign unknown,
    below both signs'. 300 boxes: theta from -300 rad, e_lo from -1 (rest at the bottom) to 200, widths
    exponential (mean 10 rad, 10 in e); both kinds, kappa 0.05 to 10, the circle or a branch within 50."""
    rng = np.random.default_rng(11)
    for _ in range(300):
        kind, kappa = ("swing-up", "damping")[rng.integers(2)], float(np.exp(rng.uniform(np.log(0.05), np.log(10))))
        lo = float(rng.uniform(-300, 300))
        hi, e_lo = lo + float(rng.exponential(10)), float(rng.uniform(-1, 200))
        e_hi = e_lo + float(rng.exponential(10))
        branch = None if rng.random() < 0.5 else int(rng.integers(-50, 51))
        problem = make(kind, kappa, (0.0, 0.0), branch)
        for sign in (-1.0, 1.0):
            box = problem.transit(lo, hi, e_lo, e_hi, sign)
            assert problem.transit(lo, hi, e_lo, e_hi) <= box * (1 + 1e-12)
            for theta in np.linspace(lo, hi, 9):
                for e in np.linspace(e_lo, e_hi, 9):
                    if e + math.cos(theta) <= 0:
                        continue                # no state moving there
                    at = problem.transit(theta, theta, e, e, sign)
                    assert box <= at * (1 + 1e-12)
                    start = make(kind, kappa, (float(theta), sign * math.sqrt(2 * (e + math.cos(theta)))), branch)
                    if start.lower_bound > start.double_integrator_bound:
                        assert start.lower_bound == pytest.approx(at, rel=1e-9)


@pytest.mark.parametrize("kind, kappa, x0, branch, optimum", [
    # optima of the complete search (ocp solve KIND --kappa K --x0 ... [--branch B], optimal)
    ("swing-up", 0.05, (0.0, 0.0), None, 68.78111013494),
    ("swing-up", 0.1, (0.0, 50.0), None, 488.63699369),
    ("swing-up", 0.05, (0.0, 50.0), None, 976.1287163),
    ("damping", 1.0, (0.0, 50.0), None, 51.43057237465),
    ("damping", 0.1, (2.5, -0.3), None, 31.0615957088),
    ("swing-up", 0.5, (0.0, 0.0), 20, 34.1239373819),
    # a target behind a fast start's first turning point (about 630 and 360 rad on): braking, then back
    ("swing-up", 0.41, (1.473, 22.78), -2, 128.137471544204),
    ("damping", 0.63, (-0.36, 28.28), -2, 108.528887597339),
])
def test_the_energy_bound_is_below_the_optimum_and_tight_for_fast_starts(kind, kappa, x0, branch, optimum):
    """The energy bound holds against optima of the complete search, and is within 3 % of them from
    a fast start, where braking is the whole problem (the double integrator's bound: 51 % of the
    optimum from (0, 50) at kappa = 1, 10 % at kappa = 0.1)."""
    p = make(kind, kappa, x0, branch)
    assert p.lower_bound <= optimum
    if abs(x0[1]) >= 50:
        assert p.lower_bound >= 0.97 * optimum


def test_the_lower_bound_is_below_every_optimum_the_residual_runs_found():
    """Against an independent computation: every optimum of the search that the brute force of
    benchmarks/search_residual.py confirmed (random states and kappa, both readings, in the committed
    records; the brute force found nothing earlier) is at least Problem.lower_bound."""
    import json
    from pathlib import Path

    checked = 0
    for path in sorted((Path(__file__).resolve().parent.parent / "benchmarks").glob("search_residual-*.jsonl")):
        for line in path.read_text().splitlines():
            record = json.loads(line)
            if record["status"] != "optimal" or record["missing"] or record["brute_best"] is None:
                continue
            problem, T = record["problem"], min(record["best"], record["brute_best"])
            bound = make(problem["kind"], problem["kappa"], tuple(problem["x0"]), problem["branch"]).lower_bound
            assert bound <= T * (1 + 1e-12), (problem, bound, T)
            checked += 1
    assert checked > 10000
