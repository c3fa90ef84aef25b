"""Robustness of the direct method from seeded random initial guesses, judged by the complete
search, on the four reference cases.

    python benchmarks/robustness.py [--seeds 20]

For each case and seed: `ocp.solve(problem, MultipleShooting(N=100), guess=random_guess(problem,
seed, 100))`, the direct solve from that one guess classified against the search's optimum
(`ocp.result.DirectClass`: optimum, inaccurate, local optimum, wrong structure, beyond horizon,
chattering, misses target, not converged, solver error). The table counts the classes per case;
the last columns say whether the answer (the search's) was proved optimal and certified every
time, and the mean wall time per solve (cold: every cache cleared before each).
"""

import argparse
import time
from collections import Counter

import ocp
from ocp.core import cache
from ocp.core.output import solver_output
from ocp.direct import random_guess
from ocp.result import DirectClass
from reference_cases import CASES


def run(seeds):
    rows = []
    with solver_output("devnull"):
        for name, (problem, reference) in CASES.items():
            T_ref = reference().T
            counts, optimal, certified = Counter(), 0, 0
            start = time.perf_counter()
            for seed in range(seeds):
                cache.clear()
                sol = ocp.solve(problem, ocp.MultipleShooting(N=100), guess=random_guess(problem, seed, 100))
                counts[sol.direct_class] += 1
                optimal += bool(sol.optimal) and abs(sol.T - T_ref) <= sol.T_error + reference().error
                certified += sol.certified
            rows.append((name, seeds, counts, optimal, certified, (time.perf_counter() - start) / seeds))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    rows = run(parser.parse_args().seeds)
    classes = [c for c in DirectClass if any(r[2][c] for r in rows)]
    head = " ".join(f"{c.name.lower().replace('_', ' '):>15}" for c in classes)
    print(f"{'case':<20} {'runs':>4} {head} {'optimal = T*':>12} {'certified':>9} {'s/run':>6}")
    for name, n, counts, optimal, certified, per_run in rows:
        print(f"{name:<20} {n:>4} " + " ".join(f"{counts[c]:>15}" for c in classes)
              + f" {optimal:>12} {certified:>9} {per_run:>6.2g}")


if __name__ == "__main__":
    main()
