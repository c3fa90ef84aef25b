"""Speed of the complete search against the textbook direct method, side by side in one run.

    python benchmarks/search_speed.py [--repeats 5]
    python benchmarks/search_speed.py --kappa-table [--chart DIR] [--repeats 3]
    python benchmarks/search_speed.py --processes [--repeats 5]
    python benchmarks/search_speed.py --breakdown

For each standard case: the textbook CasADi method (multiple shooting, N = 200, RK4 with M = 4
steps, IPOPT, one start: the straight guess; its NLP built beforehand, so the time is the solve's)
and `ocp.solve` (complete search, verification, certificate; warm: the compiled kernels loaded by a
first call), each the median of `repeats` runs, with the error of T against Finch's formula where
one applies (else against the search's own answer, marked), and the textbook answer's class against
the search's (`ocp.result.DirectClass`: a control verified on the target may be another extremal's,
a local optimum). Then the search alone per state, and
two whole processes: `ocp solve swing-up --kappa 1` and `ocp --help` (median of 3). Ratios, not
absolute times, are the finding: the machine is shared.

With --kappa-table: the cost against kappa (KAPPAS, 0.05 to 10) of both problems from their
standard starts, and of FAST starts: the search alone (warm, median of `repeats` where a run takes
under 1 s, cut at SEARCH_LIMIT s and marked), the extremals it integrated, T and its switches;
beside the textbook method at the N it needs for |T - T*| < TEXTBOOK_TOL (N doubled along N_LADDER,
one solve per N from the straight guess; "needs > N" with its |T - T*| where no rung reaches it
within TEXTBOOK_BUDGET s of solves), and the ratio of the two times. --chart DIR also draws it
(DIR/search_cost.png).

With --processes: per standard case, a whole `ocp solve KIND --kappa K --json` process and the
search alone (warm), the least and the median of their runs, beside the goals of issue 22
(PROCESS_GOAL_S, SEARCH_GOAL_S).

With --breakdown: where the search alone spends its time on the standard cases (BREAKDOWN), in the
fastest of SEARCH_REPEATS runs: in the compiled integration of the extremals and their variations
(`_taylor.extremal_variations`, timed around each call) and in the rest, the scan's Python (its
samples' records, the examination of each interval, the roots' Newton steps), with the counts that
scale them: the integrations, the extremals, the intervals examined.

Every whole process is timed with the package's bytecode compiled first (`compileall`, as `pip
install` does): where PYTHONDONTWRITEBYTECODE is set (as on the machines of this project) a module
changed since its bytecode was last written would otherwise be compiled again in every process.
"""

import argparse
import compileall
import math
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

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
        ("swing-up", 1.0, (0.0, 20.0)), ("swing-up", 1.0, (0.0, 50.0)), ("damping", 1.0, (0.0, 50.0))]
N_LADDER = (50, 100, 200, 400, 800)
#: the goal of |T - T*| for the textbook method's N
TEXTBOOK_TOL = 1e-4
#: seconds of textbook solves per case after which its ladder is left
TEXTBOOK_BUDGET = 15.0
#: seconds of search per case in the kappa table: a longer one is cut there and said so
SEARCH_LIMIT = 30.0
#: the goals of issue 22 on the standard cases: a whole `ocp solve` process, the search alone (warm)
PROCESS_GOAL_S, SEARCH_GOAL_S = 0.5, 0.005
#: runs of the search alone per case with --processes (milliseconds each)
SEARCH_REPEATS = 20
#: the cases of --breakdown: the standard cases of issue 22's goal (kappa >= 0.5), and swing-up at 0.3
BREAKDOWN = [(kind, kappa) for kind in ("swing-up", "damping") for kappa in (1.0, 0.75, 0.5)] + [("swing-up", 0.3)]


def run_times(fn, repeats):
    """(sorted wall seconds of `repeats` calls of fn, its last value)."""
    times, value = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return sorted(times), value


def median_time(fn, repeats):
    times, value = run_times(fn, repeats)
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


def process_times(args, repeats=3):
    """Sorted wall seconds of `repeats` runs of the command `args`, the package's bytecode compiled first."""
    compileall.compile_dir(Path(ocp.__file__).parent, quiet=1)
    return run_times(lambda: subprocess.run(args, capture_output=True, check=False), repeats)[0]


def process_time(args, repeats=3):
    """Median wall seconds of `repeats` runs of the command `args` (`process_times`)."""
    return statistics.median(process_times(args, repeats))


def textbook_at_accuracy(problem, T_star):
    """(N, seconds, |T - T*| at the last N tried): N doubled along N_LADDER until the textbook solve
    (from the straight guess) is verified with |T - T*| < TEXTBOOK_TOL, then that solve timed again
    with its NLP built (as in the standard table); N None where no rung reached it, or its solves
    took TEXTBOOK_BUDGET s, each capped at the rest of it in IPOPT's CPU seconds (seconds is then the
    last N tried: "needs > N"; |T - T*| inf if that solve was not verified)."""
    spent, error, tried = 0.0, math.inf, None
    for N in N_LADDER:
        if spent > TEXTBOOK_BUDGET:
            break
        method = ocp.MultipleShooting(N=N, integrator="rk4", M=4)
        straight = default_guesses(problem, N)[0]
        cap = {"ipopt.max_cpu_time": max(TEXTBOOK_BUDGET - spent, 1.0)}      # a solve cut there is not verified
        start = time.perf_counter()
        d = direct.solve(problem, method, options=cap, guess=straight)
        spent, tried = spent + time.perf_counter() - start, N
        error = abs(d.T - T_star) if d.success else math.inf
        if error < TEXTBOOK_TOL:
            start = time.perf_counter()
            direct.solve(problem, method, options=cap, guess=straight)     # the same options: the NLP built
            return N, time.perf_counter() - start, error
    return None, tried, error


def timed_search(problem, repeats):
    """(seconds, Search): the search alone, warm, cut at SEARCH_LIMIT; the median of `repeats` runs
    where one takes less than a second."""
    seconds, found = median_time(lambda: search(problem, time_limit=SEARCH_LIMIT), 1)
    if seconds < 1.0 and repeats > 1:
        seconds, found = median_time(lambda: search(problem, time_limit=SEARCH_LIMIT), repeats)
    return seconds, found


def kappa_table(repeats, chart):
    """The cost against kappa of both problems, and of the FAST starts (see the module doc)."""
    problems = [ocp.core.problem.make(kind, kappa) for kind in ("swing-up", "damping") for kappa in KAPPAS]
    problems += [ocp.core.problem.make(kind, kappa, x0) for kind, kappa, x0 in FAST]
    search(problems[0])                                 # load the compiled kernels
    rows = []
    for problem in problems:
        with solver_output("devnull"):
            t_search, found = timed_search(problem, repeats)
            N, t_text, error = (None, None, None) if found.best is None else textbook_at_accuracy(problem, found.best.T)
        rows.append((problem, t_search, found, N, t_text, error))
        print(f"  {problem.describe()}: search {t_search:.4f} s ({found.status}), textbook N = {N}",
              file=sys.stderr, flush=True)
    print(f"| problem | start | kappa | T | switches | extremals | search s | textbook N (\\|dT\\| < {TEXTBOOK_TOL:g}) "
          f"| its s | ratio |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for problem, t_search, found, N, t_text, error in rows:
        best = found.best
        if best is None:
            text = "- | - | -"
        elif N is not None:
            text = f"{N} | {t_text:.2f} | {t_text / t_search:.0f}"
        else:                                           # t_text: the last N tried
            there = "not verified" if math.isinf(error) else f"\\|dT\\| = {error:.0e}"
            text = f"needs > {t_text} ({there} at {t_text}) | - | -"
        T = "none found" if best is None else f"{best.T:.10f}"
        cut = "" if found.status == "optimal" else f" ({found.status})"
        print(f"| {problem.kind} | ({problem.x0[0]:.4g}, {problem.x0[1]:.4g}) | {problem.kappa:g} | {T}{cut} | "
              f"{'-' if best is None else best.n_switches} | {found.coverage.extremals} | {t_search:.4f} | {text} |")
    print(f"\nsearch: warm, median of {repeats} where under 1 s, cut at {SEARCH_LIMIT:g} s (status shown if not "
          f"optimal); textbook: multiple shooting (RK4, M = 4, IPOPT, the straight guess), N doubled from "
          f"{N_LADDER[0]} to {N_LADDER[-1]}, one solve per N, left after {TEXTBOOK_BUDGET:g} s of solves (each "
          f"capped at the rest in IPOPT CPU seconds); ratio: "
          f"textbook s / search s")
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
                          label=f"textbook at |dT| < {TEXTBOOK_TOL:g}, {kind}")
            ax.set_xlabel("kappa")
            ax.set_ylabel("seconds (warm)")
            ax.set_title("cost of the minimum time against kappa, standard starts")
            ax.legend(loc="lower left")             # empty: at small kappa the search costs most
            paths = plotting.save(fig, Path(chart) / "search_cost", formats=("png",))
        print(f"\n![cost against kappa]({paths[0]})")


def processes(repeats):
    """Per standard case: a whole `ocp solve KIND --kappa K --json` process (`repeats` runs) and the
    search alone (warm, in this process, SEARCH_REPEATS runs), each the least and the median of its
    runs (on a shared machine the noise only adds: the least is the code's cost, the median what a
    user may see), beside the goals of issue 22."""
    search(ocp.swing_up(1.0))                           # load the compiled kernels
    print(f"| case | whole `ocp solve ... --json` process s, least / median of {repeats} (goal {PROCESS_GOAL_S:g}) "
          f"| search alone ms, warm, least / median of {SEARCH_REPEATS} (goal {1e3 * SEARCH_GOAL_S:g}) |")
    print("| --- | --- | --- |")
    for kind, kappa in CASES:
        problem = ocp.core.problem.make(kind, kappa)
        whole = process_times([sys.executable, "-m", "ocp.cli", "solve", kind, "--kappa", f"{kappa:g}", "--json"],
                              repeats)
        alone, _ = run_times(lambda: search(problem), SEARCH_REPEATS)
        print(f"| {kind} kappa={kappa:g} | {whole[0]:.2f} / {statistics.median(whole):.2f} "
              f"| {1e3 * alone[0]:.1f} / {1e3 * statistics.median(alone):.1f} |")
    print(f"\n`ocp solve --help`: {process_time([sys.executable, '-m', 'ocp.cli', 'solve', '--help']):.2f} s "
          f"(median of 3)")


def breakdown():
    """The search alone on the BREAKDOWN cases, its time split between the compiled kernel and the
    rest (the module doc), in the fastest of SEARCH_REPEATS runs."""
    from ocp.indirect import searching, taylor
    kernel, examine = taylor._taylor.extremal_variations, searching._examine
    spent = {"kernel": 0.0, "calls": 0, "examined": 0}

    def timed_kernel(*args):
        start = time.perf_counter()
        try:
            return kernel(*args)
        finally:
            spent["kernel"] += time.perf_counter() - start
            spent["calls"] += 1

    def counted_examine(*args, **kwargs):
        spent["examined"] += 1
        return examine(*args, **kwargs)

    print("| case | search alone ms | compiled kernel ms (share) | the rest, Python, ms | integrations | extremals "
          "| intervals examined | Python us per interval |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    taylor._taylor.extremal_variations, searching._examine = timed_kernel, counted_examine
    try:
        search(ocp.swing_up(1.0))                       # load the compiled kernels
        for kind, kappa in BREAKDOWN:
            problem = ocp.core.problem.make(kind, kappa)
            runs = []
            for _ in range(SEARCH_REPEATS):
                spent.update(kernel=0.0, calls=0, examined=0)
                start = time.perf_counter()
                found = search(problem)
                runs.append((time.perf_counter() - start, dict(spent)))
            total, least = min(runs, key=lambda run: run[0])
            rest = total - least["kernel"]
            print(f"| {kind} kappa={kappa:g} | {1e3 * total:.2f} | {1e3 * least['kernel']:.2f} "
                  f"({least['kernel'] / total:.0%}) | {1e3 * rest:.2f} | {least['calls']} | {found.coverage.extremals} | "
                  f"{least['examined']} | {1e6 * rest / max(least['examined'], 1):.0f} |")
    finally:
        taylor._taylor.extremal_variations, searching._examine = kernel, examine
    print(f"\nthe fastest of {SEARCH_REPEATS} runs, warm; the kernel timed around each call (perf_counter), the rest "
          f"the search's time less it")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--kappa-table", action="store_true", help="the cost against kappa (see the module doc)")
    parser.add_argument("--chart", metavar="DIR", help="with --kappa-table: draw DIR/search_cost.png")
    parser.add_argument("--processes", action="store_true", help="whole processes and the search alone on the "
                                                                 "standard cases (see the module doc)")
    parser.add_argument("--breakdown", action="store_true", help="the search's time, compiled kernel and the rest "
                                                                 "(see the module doc)")
    args = parser.parse_args()
    repeats = args.repeats
    if args.kappa_table or args.processes or args.breakdown:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
        shown = "" if args.breakdown else f", repeats {repeats}"
        print(f"commit {commit}, Python {platform.python_version()}, {platform.machine()}{shown}\n")
        return (kappa_table(repeats, args.chart) if args.kappa_table else processes(repeats) if args.processes
                else breakdown())
    textbook = ocp.MultipleShooting(N=200, integrator="rk4", M=4)
    ocp.solve(ocp.swing_up(1.0))                        # load the compiled kernels
    rows = []
    with solver_output("devnull"):
        for kind, kappa in CASES:
            problem = ocp.core.problem.make(kind, kappa)
            straight = default_guesses(problem, textbook.N)[0]
            direct.solve(problem, textbook, guess=straight)           # build the NLP once
            t_direct, d = median_time(lambda: direct.solve(problem, textbook, guess=straight), repeats)
            # the same solve, untimed, classified against the search's answer (a verified control may
            # be another extremal's: a local optimum)
            classified = ocp.solve(problem, textbook, guess=straight).direct_class
            t_solve, s = median_time(lambda: ocp.solve(problem), repeats)
            t_search, _ = median_time(lambda: search(problem), repeats)
            ref = exact_T(problem)
            rows.append({"case": f"{kind} kappa={kappa:g}", "textbook s": t_direct, "textbook class": str(classified),
                         "textbook |dT|": abs(d.T - (ref if ref is not None else s.T)),
                         "ocp.solve s": t_solve, "ocp.solve |dT|": None if ref is None else abs(s.T - ref),
                         "ocp.solve estimate": s.T_error, "search s": t_search,
                         "ratio": t_solve / t_direct, "reference": "formula" if ref is not None else "search"})
    cache.clear()
    solve_process = process_time([sys.executable, "-m", "ocp.cli", "solve", "swing-up", "--kappa", "1"])
    help_process = process_time([sys.executable, "-m", "ocp.cli", "--help"])
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    print(f"commit {commit}, Python {platform.python_version()}, {platform.machine()}, repeats {repeats}\n")
    print("| case | textbook (N=200) s (its class) | its \\|T - T*\\| | ocp.solve s | its \\|T - T*\\| (estimate) | ratio | search alone s |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        err = "-" if r["ocp.solve |dT|"] is None else f"{r['ocp.solve |dT|']:.0e}"
        print(f"| {r['case']} | {r['textbook s']:.3f} ({r['textbook class'].replace('_', ' ')}) | {r['textbook |dT|']:.1e} "
              f"({r['reference']}) | {r['ocp.solve s']:.3f} | {err} ({r['ocp.solve estimate']:.0e}) | "
              f"{r['ratio']:.2f} | {r['search s']:.4f} |")
    print(f"\nwhole processes (median of 3): `ocp solve swing-up --kappa 1` {solve_process:.2f} s, "
          f"`ocp --help` {help_process:.2f} s")


if __name__ == "__main__":
    sys.exit(main())
