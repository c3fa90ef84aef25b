"""Speed of the complete search against the textbook direct method, side by side in one run.

    python benchmarks/search_speed.py [--repeats 5]
    python benchmarks/search_speed.py --kappa-table [--chart DIR] [--repeats 3]

For each standard case: the textbook CasADi method (multiple shooting, N = 200, RK4 with M = 4
steps, IPOPT, one start: the straight guess; its NLP built beforehand, so the time is the solve's)
and `ocp.solve` (complete search, verification, certificate; warm: the compiled kernels loaded by a
first call), each the median of `repeats` runs, with the error of T against Finch's formula where
one applies (else against the search's own answer, marked). Then the search alone per state, and
two whole processes: `ocp solve swing-up --kappa 1` and `ocp --help` (median of 3). Ratios, not
absolute times, are the finding: the machine is shared.

With --kappa-table: the cost against kappa (KAPPAS, 0.05 to 10) of both problems from their
standard starts, and of FAST starts: the search alone (warm, median of `repeats`), the extremals it
integrated, T and its switches; beside the textbook method at the least N of N_LADDER with
|T - T*| < 1e-4 (one solve per N, from the straight guess; "-" where no N of the ladder reaches
it within TEXTBOOK_BUDGET s of solves), and the ratio of the two times. --chart DIR also draws it (DIR/search_cost.png).
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
KAPPAS = (0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 5.0, 10.0)
FAST = [("swing-up", 1.0, (0.0, 5.0)), ("swing-up", 1.0, (0.0, 10.0)), ("damping", 1.0, (0.0, 10.0)),
        ("swing-up", 1.0, (0.0, 20.0))]
N_LADDER = (50, 100, 200, 400, 800)
#: seconds of textbook solves per case after which its ladder is left
TEXTBOOK_BUDGET = 30.0


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


def textbook_at_accuracy(problem, T_star):
    """(N, seconds) of the first N of N_LADDER whose textbook solve is verified with |T - T*| < 1e-4,
    or (None, seconds of the last tried); the ladder is left once its solves took TEXTBOOK_BUDGET s."""
    seconds, spent = None, 0.0
    for N in N_LADDER:
        if spent > TEXTBOOK_BUDGET:
            break
        method = ocp.MultipleShooting(N=N, integrator="rk4", M=4)
        straight = default_guesses(problem, N)[0]
        start = time.perf_counter()
        d = direct.solve(problem, method, guess=straight)
        seconds = time.perf_counter() - start
        spent += seconds
        if d.success and abs(d.T - T_star) < 1e-4:
            return N, seconds
    return None, seconds


def kappa_table(repeats, chart):
    """The cost against kappa of both problems, and of the FAST starts (see the module doc)."""
    problems = [ocp.core.problem.make(kind, kappa) for kind in ("swing-up", "damping") for kappa in KAPPAS]
    problems += [ocp.core.problem.make(kind, kappa, x0) for kind, kappa, x0 in FAST]
    search(problems[0])                                 # load the compiled kernels
    rows = []
    with solver_output("devnull"):
        for problem in problems:
            t_search, found = median_time(lambda: search(problem), repeats)
            best = found.best
            N, t_text = textbook_at_accuracy(problem, best.T)
            rows.append((problem, t_search, found, N, t_text))
            print(f"  {problem.describe()}: search {t_search:.4f} s, textbook N = {N}", file=sys.stderr, flush=True)
    print("| problem | start | kappa | T | switches | extremals | search s | textbook N (\|dT\| < 1e-4) | its s | ratio |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for problem, t_search, found, N, t_text in rows:
        best = found.best
        text = f"{N} | {t_text:.2f} | {t_text / t_search:.0f}" if N is not None else f"- (N <= {N_LADDER[-1]}) | - | -"
        print(f"| {problem.kind} | ({problem.x0[0]:.4g}, {problem.x0[1]:.4g}) | {problem.kappa:g} | "
              f"{best.T:.10f} | {best.n_switches} | {found.coverage.extremals} | {t_search:.4f} | {text} |")
    if chart:
        from pathlib import Path
        from ocp.core import plotting
        plt = plotting.plt
        with plotting.style():
            fig, ax = plt.subplots()
            for kind, marker in (("swing-up", "o"), ("damping", "s")):
                mine = [r for r in rows if r[0].kind == kind and r[0].x0 == ocp.core.problem.KINDS[kind].start]
                ax.loglog([r[0].kappa for r in mine], [r[1] for r in mine], marker=marker, label=f"search, {kind}")
                reached = [r for r in mine if r[3] is not None]
                ax.loglog([r[0].kappa for r in reached], [r[4] for r in reached], marker=marker, linestyle="--",
                          label=f"textbook at |dT| < 1e-4, {kind}")
            ax.set_xlabel("kappa")
            ax.set_ylabel("seconds (warm)")
            ax.set_title("cost of the minimum time against kappa, standard starts")
            ax.legend()
            paths = plotting.save(fig, Path(chart) / "search_cost", formats=("png",))
        print(f"\nchart: {', '.join(map(str, paths))}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--kappa-table", action="store_true", help="the cost against kappa (see the module doc)")
    parser.add_argument("--chart", metavar="DIR", help="with --kappa-table: draw DIR/search_cost.png")
    args = parser.parse_args()
    repeats = args.repeats
    if args.kappa_table:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
        print(f"commit {commit}, Python {platform.python_version()}, {platform.machine()}, repeats {repeats}\n")
        return kappa_table(repeats, args.chart)
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
