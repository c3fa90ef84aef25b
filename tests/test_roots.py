"""ocp.core.roots.minimum, the bounded minimisation of the Finch cross-check, is scipy's
minimize_scalar(method="bounded") operation for operation: the same x and f(x), bit for bit."""

import math

import numpy as np
from scipy.optimize import minimize_scalar

from ocp.core.roots import minimum
from ocp.exact import finch


def test_the_bounded_minimum_is_scipys_bit_for_bit():
    rng = np.random.default_rng(0)
    for _ in range(100):
        c, a = rng.normal(size=4), rng.uniform(-3, 0)
        b = a + rng.uniform(0.1, 5)
        f = lambda x: math.sin(c[0] * x + c[1]) + c[2] * x * x + c[3] * x
        for xtol in (1e-5, 1e-10, 1e-14):
            ref = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": xtol})
            assert minimum(f, a, b, xtol) == (ref.x, ref.fun)


def test_the_steepest_point_of_finchs_two_switch_family_is_scipys():
    low, high = finch.two_switch_range()
    for kappa in np.linspace(low, high, 12)[1:-1]:
        f = lambda r: -finch.stationarity(r, kappa)[0]
        ref = minimize_scalar(f, bounds=finch._feasible_rhos(kappa), method="bounded", options={"xatol": 1e-10})
        assert finch._steepest(kappa) == (ref.x, -ref.fun)


def test_a_minimum_asked_below_a_level_stops_at_the_first_point_evaluated_under_it():
    rng = np.random.default_rng(1)
    stopped = 0
    for _ in range(100):
        c, a = rng.normal(size=4), rng.uniform(-3, 0)
        b = a + rng.uniform(0.1, 5)
        evaluated = []
        f = lambda x: evaluated.append((x, math.sin(c[0] * x + c[1]) + c[2] * x * x + c[3] * x)) or evaluated[-1][1]
        x_min, f_min = minimum(f, a, b, 1e-10)
        level = f_min + abs(f_min) * rng.uniform(0, 0.5) + rng.uniform(0, 0.2)
        first = next(((x, v) for x, v in evaluated if v < level), (x_min, f_min))
        assert minimum(f, a, b, 1e-10, below=level) == first
        stopped += first[1] < level
        assert minimum(f, a, b, 1e-10, below=f_min) == (x_min, f_min)     # nothing below the minimum
    assert stopped > 50
