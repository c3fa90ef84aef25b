"""Batista and Peternelj 2006, "The falling time of an inverted plane pendulum": every printed
value of `data/batista2006.toml`, computed by `ocp.scenes.falling`."""

import math
from dataclasses import replace

from ..scenes.falling import (ACCURACY_I, G, TABLE1, TABLE2, asymptotic18, asymptotic19, falling_integral,
                              falling_time, uncertainty_time)
from .verify import Reproduction


def reproduce():
    """The paper's printed values, computed (keys of data/batista2006.toml)."""
    how = "I(pi/n, 0) in closed form (Carlson RF, scipy); = 30-digit mpmath quadrature (tests)"
    out = {}
    for n in TABLE1:
        i = Reproduction(float(falling_integral(math.pi / n)), ACCURACY_I, how)
        out[f"t1_formula17_pi{n}"] = out[f"t1_maple_pi{n}"] = i
    out["t1_maple_pi48"] = replace(out["t1_maple_pi48"], evidence=(
        f"I(pi/48) = {out['t1_maple_pi48'].value!r} by 30-digit mpmath quadrature "
        "(tests/test_falling.py) and by the closed form: the 'Formula (17)' entry 5.55096041 is "
        "right, the 'Maple numerical' entry 5.55096159 is 1.2e-6 too large"))
    for n in TABLE2:
        i, i18 = float(falling_integral(math.pi / n)), float(asymptotic18(math.pi / n))
        out[f"t2_formula17_pi{n}"] = Reproduction(i, ACCURACY_I, how)
        out[f"t2_formula18_pi{n}"] = Reproduction(i18, 1e-14, f"(18) at theta0 = pi/{n}")
        out[f"t2_relerr_pi{n}"] = Reproduction((i - i18) / i, 1e-14, "(I - (18)) / I")
    for n in (3072, 384):
        out[f"t2_theta0_pi{n}"] = Reproduction(math.pi / n, 1e-16, f"pi/{n}")
    diff = float(asymptotic18(0.1) - asymptotic19(0.1))
    out["diff_18_19"] = Reproduction(diff, 1e-14, "(18) - (19), the same at every theta0", evidence=(
        f"(18) - (19) = sqrt(2) [ln(8(sqrt(2)-1)) - ln(4(sqrt(2)-1))] = sqrt(2) ln 2 = {diff:.6f} "
        "(both formulas evaluated at theta0 = 0.1); ln 2 is the difference of the brackets"))
    out["sqrt_L_2g"] = Reproduction(math.sqrt(0.15 / (2 * G)), 1e-16, "sqrt(L/(2g)), L = 0.15 m")
    out["T_1deg"] = Reproduction(float(falling_time(math.pi / 180)), 1e-14,
                                 "(7), I in closed form; theta0 = pi/180, omega0 = 0, L = 0.15 m")
    out["T_uncertainty"] = Reproduction(float(uncertainty_time()), 1e-13,
                                        "(7), k = 1, equality in (24); L = 0.1 m, m = 1 g")
    return out
