"""Speed of the complete search against the textbook direct method, side by side in one run.

    python benchmarks/search_speed.py [--repeats 5]

For each standard case: the textbook CasADi method (multiple shooting, N = 200, RK4 with M = 4
steps, IPOPT, one start: the straight guess; its NLP built beforehand, so the time is the solve's)
and `ocp.solve` (complete search, verification, certificate; warm: the compiled kernels loaded by a
first call), each the median of `repeats` runs, with the error of T against Finch's formula where
one applies (else against the search's own answer, marked). Then the search alone per state, and
two whole processes: `ocp solve swing-up --kappa 1` and `ocp --help` (median of 3). Ratios, not
absolute times, are the finding: the machine is shared.
"""

import argparse
import platform
import statistics
import subprocess
import sys
import time

import ocp
from ocp import direct
from ocp.core import cache
from ocp.core.output import solver_output
from ocp.direct.guess import default_guesses
from ocp.exact import finch
from ocp.indirect import search

CASES = [("swing-up", 1.0), ("swing-up", 0.75), ("swing-up", 0.5), ("swing-up", 0.3), ("damping", 1.0)]


def median_time(fn, repeats):
    times, value = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), value


def exact_T(problem):
    """Finch's formula for the standard start where one applies: one or two switches (whichever is
    faster), else None."""
    times = []
    for formula in (finch.one_switch, finch.two_switch):
        try:
            times.append(formula(problem.kind, problem.kappa).T)
        except ValueError:
            pass
    return min(times) if times else None


def process_time(args, repeats=3):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        subprocess.run(args, capture_output=True, check=False)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    repeats = parser.parse_args().repeats
    textbook = ocp.MultipleShooting(N=200, integrator="rk4", M=4)
    ocp.solve(ocp.swing_up(1.0))                        # load the compiled kernels
    rows = []
    with solver_output("devnull"):
        for kind, kappa in CASES:
            problem = ocp.core.problem.make(kind, kappa)
            straight = default_guesses(problem, textbook.N)[0]
            direct.solve(problem, textbook, guess=straight)           # build the NLP once
            t_direct, d = median_time(lambda: direct.solve(problem, textbook, guess=straight), repeats)
            t_solve, s = median_time(lambda: ocp.solve(problem), repeats)
            t_search, _ = median_time(lambda: search(problem), repeats)
            ref = exact_T(problem)
            rows.append({"case": f"{kind} kappa={kappa:g}", "textbook s": t_direct, "textbook status": d.status.name,
                         "textbook |dT|": abs(d.T - (ref if ref is not None else s.T)),
                         "ocp.solve s": t_solve, "ocp.solve |dT|": None if ref is None else abs(s.T - ref),
                         "ocp.solve estimate": s.T_error, "search s": t_search,
                         "ratio": t_solve / t_direct, "reference": "formula" if ref is not None else "search"})
    cache.clear()
    solve_process = process_time([sys.executable, "-m", "ocp.cli", "solve", "swing-up", "--kappa", "1"])
    help_process = process_time([sys.executable, "-m", "ocp.cli", "--help"])
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    print(f"commit {commit}, Python {platform.python_version()}, {platform.machine()}, repeats {repeats}\n")
    print("| case | textbook (N=200) s | its \\|T - T*\\| | ocp.solve s | its \\|T - T*\\| (estimate) | ratio | search alone s |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        err = "-" if r["ocp.solve |dT|"] is None else f"{r['ocp.solve |dT|']:.0e}"
        print(f"| {r['case']} | {r['textbook s']:.3f} ({r['textbook status'].lower()}) | {r['textbook |dT|']:.1e} "
              f"({r['reference']}) | {r['ocp.solve s']:.3f} | {err} ({r['ocp.solve estimate']:.0e}) | "
              f"{r['ratio']:.2f} | {r['search s']:.4f} |")
    print(f"\nwhole processes (median of 3): `ocp solve swing-up --kappa 1` {solve_process:.2f} s, "
          f"`ocp --help` {help_process:.2f} s")


if __name__ == "__main__":
    sys.exit(main())
