"""Speed and accuracy of the textbook direct method against the full pipeline (issue 5).

In one process, side by side, on the four reference cases (exact T and switch times from
`ocp.analytic`): the direct method alone (multiple shooting, RK4 with M = 4, IPOPT, default guess
family) at N = 100, 200, 400, and the pipeline (direct at N = 100 + refinement + competing
structures + certificate), and the same from a direct solve at N = 50 (which only has to find the
structure). Build time (once per NLP, cached afterwards) and solve time (median of
--repeats) are reported apart, and the first call of each (which also builds what the refinement
compiles once per process: its CasADi functions for each arc count); errors are |T - T_ref| and
the largest switch-time error.

    python benchmarks/pipeline_speed.py [--repeats 3]
"""

import argparse
import statistics
import time

import ocp
from ocp.transcription import MultipleShooting, build
from reference_cases import CASES

METHODS = {
    "direct N=100": (MultipleShooting(N=100), False),
    "direct N=200": (MultipleShooting(N=200), False),
    "direct N=400": (MultipleShooting(N=400), False),
    "pipeline (N=100)": (MultipleShooting(N=100), True),
    "pipeline (N=50)": (MultipleShooting(N=50), True),
}


def errors(sol, ref):
    dt = max((abs(a - b) for a, b in zip(sol.switch_times, ref.switch_times)), default=0.0)
    same = sol.n_switches == ref.n_switches and sol.first_u == ref.first_u
    return abs(sol.T - ref.T), dt if same else float("inf")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    repeats = parser.parse_args().repeats
    build_times = {name: build(m).build_time_s for name, (m, _) in METHODS.items()}
    print(f"{'case':<20} {'method':<18} {'build s':>8} {'solve s':>8} {'refine s':>8} {'total s':>8} "
          f"{'first s':>8} {'|T err|':>9} {'switch err':>10}  verdict")
    ratios = []
    for case, (problem, reference) in CASES.items():
        ref = reference()
        rows = {}
        for name, (method, refine) in METHODS.items():
            times = []
            for _ in range(repeats):
                start = time.perf_counter()
                sol = ocp.solve(problem, method, refine=refine)
                times.append((time.perf_counter() - start, sol.solve_time_s, sol.refine_time_s))
            wall = statistics.median(t[0] for t in times)
            eT, es = errors(sol, ref)
            rows[name] = (wall, eT)
            print(f"{case:<20} {name:<18} {build_times[name]:>8.2f} {statistics.median(t[1] for t in times):>8.3f} "
                  f"{statistics.median(t[2] for t in times):>8.3f} {wall + build_times[name]:>8.2f} "
                  f"{times[0][0]:>8.2f} {eT:>9.1e} {es:>10.1e}  {sol.verdict[:60]}")
        textbook = [(build_times[n] + w, n) for n, (w, e) in rows.items() if n.startswith("direct") and e < 1e-4]
        if textbook:
            t, n = min(textbook)
            ratios.append((case, [(p, (build_times[p] + rows[p][0]) / t) for p in rows if p.startswith("pipeline")], n))
    print("\npipeline time (to ~1e-11) / time of the cheapest textbook run with |T err| < 1e-4 (build included):")
    for case, pairs, n in ratios:
        print(f"  {case:<20} " + "  ".join(f"{p}: {r:4.2f}" for p, r in pairs) + f"   (textbook: {n})")


if __name__ == "__main__":
    main()
