"""Robustness of the pipeline (issue 5): seeded random initial guesses on the four reference cases.

For each case and seed, `ocp.solve(problem, guess=random_guess(problem, seed))` runs from that one
guess (no default family): the direct solve, then the competing structures, then the certificate.
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
import math
import time

import numpy as np

import ocp
from ocp.direct import Guess
from reference_cases import CASES



def random_guess(problem, seed, N=100):
    """T uniform in [0.5, 2] times the default's; theta a straight line to the nearest target plus
    three sine modes of N(0, 1) rad amplitude; u uniform in [-1, 1] on each interval."""
    rng = np.random.default_rng(seed)
    theta0, omega0 = problem.x0
    theta_t = problem.target(problem.guess_branch)[0]
    T = rng.uniform(0.5, 2.0) * (2 + abs(theta_t - theta0)) / math.sqrt(problem.kappa)
    s = np.linspace(0.0, 1.0, N + 1)
    theta = theta0 + (theta_t - theta0) * s + sum(rng.normal() * np.sin(j * math.pi * s) for j in (1, 2, 3))
    omega = np.gradient(theta, s) / T
    omega[0] = omega0
    return Guess(T, tuple(s), tuple(theta), tuple(omega), tuple(rng.uniform(-1, 1, N)), f"random seed {seed}")


def run(seeds):
    rows = []
    for name, (problem, reference) in CASES.items():
        ref = reference()
        counts = dict(direct_failed=0, direct_wrong=0, final_right=0, certified=0)
        start = time.perf_counter()
        for seed in range(seeds):
            sol = ocp.solve(problem, guess=random_guess(problem, seed))
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
