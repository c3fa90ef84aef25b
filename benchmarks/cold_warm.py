"""Cold and warm timings, reported apart, of the direct method and of `ocp.solve` on the four
reference cases (exact T from Finch's formulas, `reference_cases.py`).

    python benchmarks/cold_warm.py [--repeats 5]

cold   every built object forgotten before each run (`ocp.core.cache.clear()`: the NLP, the CasADi
       functions and integrators are built in the timed call), median of `repeats`
warm   the same call again with everything built, median of `repeats`
first  the very first call of its kind in this process, once: it also loads what no cache clear
       can unload (the CasADi plugins' shared libraries)

Methods: the direct method alone (multiple shooting, rk4 M = 4, IPOPT, the default three starts)
at N = 100 and 400, and `ocp.solve` (the complete search, verification, certificate, cross-check).
|T - T*| beside each: the direct answer's error (its bound h^2/2), the search's (about 1e-14).
Timings on a shared machine: ratios within the run are what to read; nothing is asserted.
"""

import argparse
import statistics
import time

import ocp
from ocp import direct
from ocp.core import cache
from ocp.core.output import solver_output
from reference_cases import CASES

METHODS = {
    "direct N=100": lambda p: direct.solve(p, ocp.MultipleShooting(N=100)),
    "direct N=400": lambda p: direct.solve(p, ocp.MultipleShooting(N=400)),
    "ocp.solve": lambda p: ocp.solve(p),
}


def timed(fn):
    start = time.perf_counter()
    value = fn()
    return time.perf_counter() - start, value


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    repeats = parser.parse_args().repeats
    rows = []
    with solver_output("devnull"):
        first = {name: None for name in METHODS}
        for case, (problem, reference) in CASES.items():
            T_ref = reference().T
            for name, solve in METHODS.items():
                if first[name] is None:
                    first[name] = timed(lambda: solve(problem))[0]
                cold = []
                for _ in range(repeats):
                    cache.clear()
                    cold.append(timed(lambda: solve(problem))[0])
                warm, sol = [], None
                for _ in range(repeats):
                    t, sol = timed(lambda: solve(problem))
                    warm.append(t)
                rows.append((case, name, statistics.median(cold), statistics.median(warm), abs(sol.T - T_ref)))
    print(f"{'case':<20} {'method':<14} {'cold s':>8} {'warm s':>8} {'cold/warm':>9} {'|T - T*|':>9}")
    for case, name, cold, warm, error in rows:
        print(f"{case:<20} {name:<14} {cold:>8.2g} {warm:>8.2g} {cold / warm:>9.2g} {error:>9.1e}")
    print("\nfirst call of each method in this process (plugins and compiled kernels loaded): "
          + ", ".join(f"{name} {t:.2g} s" for name, t in first.items()))


if __name__ == "__main__":
    main()
