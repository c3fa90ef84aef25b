"""Work-precision of the suite's integrators on the free fall of the pendulum (u = 0), whose exact
time to the ground is known in closed form (ocp.scenes.falling.time_to_ground).

    .venv/bin/python benchmarks/falling_integrators.py [--repeat 3]

First the falling times side by side: closed form and each method at its tightest setting (the
1-degree case times sqrt(0.15/9.8) s is the paper's example, 0.6490 s). Then, for each method and
setting (rtol = atol = tol for scipy's solve_ivp and CasADi's cvodes/idas; number of finite
elements per integrator call, a march step of 0.5 time units or a Newton step, for CasADi's
fixed-step rk and collocation): the largest relative error of the falling time over the cases,
and the wall time of one fall (best of `--repeat`, mean over the cases; CasADi integrators built
before timing). scipy locates the ground
by its event detection, CasADi by Newton on the integrator output (fall_time_casadi). Ratios
between rows are measured in this one run on this machine; nothing here is asserted.
"""

import argparse
import math
import platform
import time

import casadi
import numpy as np
import scipy

from ocp.scenes.falling import fall_time_casadi, fall_time_scipy, time_to_ground

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


def measure(fall, repeat):
    """(largest relative error, seconds per fall) of `fall` over CASES."""
    exact = [time_to_ground(x0) for x0 in CASES]
    errors = [abs(fall(x0) - e) / e for x0, e in zip(CASES, exact)]  # also builds CasADi integrators
    best = math.inf
    for _ in range(repeat):
        start = time.perf_counter()
        for x0 in CASES:
            fall(x0)
        best = min(best, time.perf_counter() - start)
    return max(errors), best / len(CASES)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"# {platform.processor() or platform.machine()}, Python {platform.python_version()}, numpy {np.__version__}, "
          f"scipy {scipy.__version__}, casadi {casadi.__version__}")
    tightest = {name: fall for name, _, fall in METHODS}  # the last setting of each method
    print(f"{'x0 = (theta, omega)':<22} {'closed form':>18} " + " ".join(f"{n:>18}" for n in tightest))
    for x0 in CASES:
        print(f"({x0[0]:.6f}, {x0[1]:4.1f})   {time_to_ground(x0):18.13f} "
              + " ".join(f"{fall(x0):18.13f}" for fall in tightest.values()))
    print()
    print(f"{'method':<20} {'setting':<10} {'max rel error':>14} {'ms per fall':>12}")
    for name, setting, fall in METHODS:
        err, sec = measure(fall, args.repeat)
        print(f"{name:<20} {setting:<10} {err:>14.2e} {1e3 * sec:>12.3f}")


if __name__ == "__main__":
    main()
