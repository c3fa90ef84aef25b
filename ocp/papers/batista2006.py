"""Batista and Peternelj 2006, "The falling time of an inverted plane pendulum": every printed
value of `data/batista2006.toml`, computed by `ocp.scenes.falling`.

Accuracies are computed: I(theta0, a) in closed form carries its distance from an independent
quadrature plus the quadrature's error estimate (`falling_integral_checked`); the elementary
formulas (18), (19), pi/n and sqrt(L/(2g)) carry a bound of their rounding, a few units of EPS per
operation times the size of the terms."""

import math
from dataclasses import replace

from ..core.numbers import digits, order
from ..scenes.falling import (G, TABLE1, TABLE2, asymptotic18, asymptotic19, falling_integral_checked,
                              falling_time, uncertainty_time)
from . import references
from .verify import Reproduction

EPS = 2.0 ** -52


def _rounding18(theta0):
    """Rounding bound of (18) = sqrt(2) [ln(8 (sqrt(2) - 1)) - ln(theta0)]: the two logarithms
    and the product, a few EPS each, on terms of size |ln(theta0)| + 2."""
    return 8 * EPS * math.sqrt(2) * (abs(math.log(theta0)) + 2)


def reproduce():
    """The paper's printed values, computed (keys of data/batista2006.toml)."""
    how = ("I(pi/n, 0) in closed form (Carlson RF, scipy); accuracy: its distance from adaptive quadrature "
           "plus the quadrature's estimate (also = 30-digit mpmath quadrature, tests)")
    out = {}
    for n in TABLE1:
        i = Reproduction(*falling_integral_checked(math.pi / n), how)
        out[f"t1_formula17_pi{n}"] = out[f"t1_maple_pi{n}"] = i
    i48 = out["t1_maple_pi48"]
    maple = references.value("batista2006", "t1_maple_pi48")
    out["t1_maple_pi48"] = replace(i48, evidence=(
        f"I(pi/48) = {digits(i48.value, i48.accuracy)} by the closed form and by adaptive quadrature "
        "(and by 30-digit mpmath quadrature, tests/test_falling.py): the 'Formula (17)' entry 5.55096041 is "
        f"right, the 'Maple numerical' entry 5.55096159 is {order(maple - i48.value)} too large"))
    for n in TABLE2:
        theta0 = math.pi / n
        i, ei = falling_integral_checked(theta0)
        i18, e18 = float(asymptotic18(theta0)), _rounding18(theta0)
        out[f"t2_formula17_pi{n}"] = Reproduction(i, ei, how)
        out[f"t2_formula18_pi{n}"] = Reproduction(i18, e18, f"(18) at theta0 = pi/{n}")
        rel = (i - i18) / i
        out[f"t2_relerr_pi{n}"] = Reproduction(rel, (ei + e18) / i + abs(rel) * ei / i + 4 * EPS * abs(rel),
                                               "(I - (18)) / I")
    for n in (3072, 384):
        out[f"t2_theta0_pi{n}"] = Reproduction(math.pi / n, 2 * EPS * math.pi / n, f"pi/{n}")
    diff, e_diff = float(asymptotic18(0.1) - asymptotic19(0.1)), 2 * _rounding18(0.1)
    out["diff_18_19"] = Reproduction(diff, e_diff, "(18) - (19), the same at every theta0", evidence=(
        f"(18) - (19) = sqrt(2) [ln(8(sqrt(2)-1)) - ln(4(sqrt(2)-1))] = sqrt(2) ln 2 = {digits(diff, e_diff)} "
        "(both formulas evaluated at theta0 = 0.1); ln 2 is the difference of the brackets"))
    out["sqrt_L_2g"] = Reproduction(math.sqrt(0.15 / (2 * G)), 4 * EPS * math.sqrt(0.15 / (2 * G)),
                                    "sqrt(L/(2g)), L = 0.15 m")
    scale = math.sqrt(0.15 / (2 * G))
    T, eT = falling_integral_checked(math.pi / 180)
    out["T_1deg"] = Reproduction(float(falling_time(math.pi / 180)), scale * eT + 4 * EPS * scale * T,
                                 "(7), I in closed form; theta0 = pi/180, omega0 = 0, L = 0.15 m")
    L, g = 0.1, G
    theta0, a = _uncertainty_start(L, g)
    T, eT = falling_integral_checked(theta0, a)
    out["T_uncertainty"] = Reproduction(float(uncertainty_time()), math.sqrt(L / (2 * g)) * (eT + 4 * EPS * T),
                                        "(7), k = 1, equality in (24); L = 0.1 m, m = 1 g")
    return out


def _uncertainty_start(L, g, m=0.001):
    """(theta0, a) of the paper's uncertainty example (as `ocp.scenes.falling.uncertainty_time`)."""
    from ..scenes.falling import HBAR

    theta0 = math.sqrt(HBAR / (2 * m * L**2) * math.sqrt(L / g))
    omega0 = 2 * math.sin(theta0 / 2) * math.sqrt(g / L)
    return theta0, omega0 / 2 * math.sqrt(L / g)
