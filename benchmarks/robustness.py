"""Robustness of the pipeline (issue 5): seeded random initial guesses on the four reference cases.

For each case and seed, `ocp.solve(problem, guess=ocp.direct.random_guess(problem, seed, 100))`
runs from that one guess (the default family only if it fails): the direct solve, then the
competing structures, then the certificate.
The table counts, per case, how often each stage failed and whether the final answer has the
reference structure and T (analytic formulas, `ocp.analytic`):

    direct failed      the direct solve from the random guess did not converge or its control
                       missed the target (the pipeline then tries its default guesses)
    direct wrong       the direct solve that went on converged to another structure (a local
                       solution; the competing structures are to recover it)
    final right        the returned structure and T agree with the formula (|dT| < 1e-9)
    certified          the returned solution passed the certificate

    python benchmarks/robustness.py [--seeds 20]
"""

import argparse
import time

import ocp
from ocp.direct import random_guess
from reference_cases import CASES


def run(seeds):
    rows = []
    for name, (problem, reference) in CASES.items():
        ref = reference()
        counts = dict(direct_failed=0, direct_wrong=0, final_right=0, certified=0)
        start = time.perf_counter()
        for seed in range(seeds):
            sol = ocp.solve(problem, guess=random_guess(problem, seed, 100))
            direct_signs = tuple(sol.structure.arc_signs)
            ref_signs = tuple(ref.first_u * (-1) ** i for i in range(ref.n_switches + 1))
            counts["direct_failed"] += not sol.starts[0]["success"]
            counts["direct_wrong"] += sol.success and direct_signs != ref_signs
            counts["final_right"] += (sol.refined is not None and sol.arc_signs == ref_signs
                                      and abs(sol.T - ref.T) < 1e-9)
            counts["certified"] += sol.certified
        rows.append((name, seeds, counts, (time.perf_counter() - start) / seeds))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    rows = run(parser.parse_args().seeds)
    print(f"{'case':<22} {'runs':>4} {'direct failed':>13} {'direct wrong':>12} {'final right':>11} {'certified':>9} {'s/run':>6}")
    for name, n, c, per_run in rows:
        print(f"{name:<22} {n:>4} {c['direct_failed']:>13} {c['direct_wrong']:>12} {c['final_right']:>11} "
              f"{c['certified']:>9} {per_run:>6.2f}")


if __name__ == "__main__":
    main()
