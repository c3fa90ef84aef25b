"""Work-precision of the suite's integrators on the free fall of the pendulum (u = 0), whose exact
time to the ground is known in closed form (ocp.scenes.falling.time_to_ground).

    python benchmarks/falling_integrators.py [--repeat 3]

First the falling times: the closed form, to the digits its accuracy defends (its distance from an
independent quadrature plus the quadrature's estimate, `falling_integral_checked`), and each
method's error at its tightest setting (signed, T_method - T_exact; the exact value is known far
better than these errors). The 1-degree case times sqrt(0.15/9.8) s is the paper's example,
0.6490 s. Then, for each method and setting (rtol = atol = tol for scipy's solve_ivp and CasADi's
cvodes/idas; number of finite elements per integrator call, a march step of 0.5 time units or a
Newton step, for CasADi's fixed-step rk and collocation): the largest relative error of the
falling time over the cases, the cold time of the first fall from 1 degree (every built object
forgotten first, `ocp.core.cache.clear()`: a CasADi integrator is built in it; scipy builds
nothing) and the warm time of the same fall (best of `--repeat`, the integrator already built). scipy
locates the ground by its event detection, CasADi by Newton on the integrator output
(fall_time_casadi). Ratios between rows are measured in this one run on this machine; nothing here
is asserted.
"""

import argparse
import math
import platform
import time

import casadi
import numpy as np
import scipy

from ocp.core import cache
from ocp.core.numbers import digits
from ocp.scenes.falling import fall_time_casadi, fall_time_scipy, falling_integral_checked, time_to_ground

#: suite-convention initial states (theta, omega): from rest 1, 10 and 45 degrees off the upright, and thrown
CASES = [(math.pi - math.radians(1), 0.0), (math.pi - math.radians(10), 0.0), (math.pi - math.radians(45), 0.0),
         (math.pi - 0.3, -1.5)]
TOLS = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
METHODS = (
    [(f"scipy {m}", f"tol {t:.0e}", lambda x0, m=m, t=t: fall_time_scipy(x0, m, rtol=t, atol=t))
     for m in ("RK45", "DOP853", "Radau", "LSODA") for t in TOLS]
    + [(f"casadi {p}", f"tol {t:.0e}", lambda x0, p=p, t=t: fall_time_casadi(x0, p, abstol=t, reltol=t))
       for p in ("cvodes", "idas") for t in TOLS]
    + [("casadi rk", f"N {n}", lambda x0, n=n: fall_time_casadi(x0, "rk", number_of_finite_elements=n))
       for n in (4, 16, 64, 256)]
    + [("casadi collocation", f"N {n}", lambda x0, n=n: fall_time_casadi(x0, "collocation", number_of_finite_elements=n))
       for n in (2, 4, 8, 16, 32)]
)


def exact(x0):
    """(time to the ground, its accuracy) from x0 in the suite's convention: I / sqrt(2)."""
    theta, omega = x0
    value, accuracy = falling_integral_checked(math.pi - theta, -omega / 2)
    return time_to_ground(x0), accuracy / math.sqrt(2)


def measure(fall, repeat):
    """(largest relative error over CASES, cold seconds of the first fall from CASES[0], warm
    seconds of the same fall, best of `repeat`)."""
    reference = [time_to_ground(x0) for x0 in CASES]
    cache.clear()
    start = time.perf_counter()
    first = fall(CASES[0])                                   # cold: builds a CasADi integrator
    cold = time.perf_counter() - start
    errors = [abs((first if i == 0 else fall(x0)) - e) / e for i, (x0, e) in enumerate(zip(CASES, reference))]
    warm = math.inf
    for _ in range(repeat):
        start = time.perf_counter()
        fall(CASES[0])
        warm = min(warm, time.perf_counter() - start)
    return max(errors), cold, warm


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"# {platform.processor() or platform.machine()}, Python {platform.python_version()}, numpy {np.__version__}, "
          f"scipy {scipy.__version__}, casadi {casadi.__version__}")
    tightest = {name: fall for name, _, fall in METHODS}  # the last setting of each method
    print("falling time (closed form) and each method's error at its tightest setting, T_method - T_exact:")
    print(f"{'x0 = (theta, omega)':<22} {'closed form':>18} " + " ".join(f"{n:>18}" for n in tightest))
    for x0 in CASES:
        T, accuracy = exact(x0)
        print(f"({x0[0]:.6f}, {x0[1]:4.1f})   {digits(T, accuracy):>18} "
              + " ".join(f"{fall(x0) - T:>18.1e}" for fall in tightest.values()))
    print()
    print(f"{'method':<20} {'setting':<10} {'max rel error':>14} {'cold ms':>8} {'warm ms':>8}")
    for name, setting, fall in METHODS:
        err, cold, warm = measure(fall, args.repeat)
        print(f"{name:<20} {setting:<10} {err:>14.1e} {1e3 * cold:>8.2g} {1e3 * warm:>8.2g}")


if __name__ == "__main__":
    main()
