"""The error of the direct method against the exact transfers: the evidence behind the bound of T
that `ocp.direct.solve` states (`T_bound`: `ocp.direct.base.grid_bound`, up to `BOUND_N_MAX`).

    python benchmarks/direct_error.py [--N 25 50 100 200 400 800 1600 3200] [--jobs 2] [--markdown]
    nice python benchmarks/direct_error.py --coverage 300 [--N 100] [--out benchmarks/direct_coverage.jsonl]
    python benchmarks/direct_error.py --coverage-summary [--out benchmarks/direct_coverage.jsonl]

Coverage (--coverage K): K seeded random instances (`random_instance`: swing-up or damping, kappa
log-uniform in [0.25, 2], x0 uniform in [-pi, pi] x [-2, 2]), each solved by `ocp.solve` with
multiple shooting (rk4, M = 4, N = 100) beside the exact search; one JSON line per instance
(resumable). --coverage-summary: on the instances whose direct answer has the optimum's structure,
how many the stated bound (recomputed from the rows' switch states) and the former h^2/2 cover.

Method: multiple shooting, rk4 with M = 4 steps per interval, IPOPT with ocp's quiet defaults
(tol 1e-8), the default family of three initial guesses (`ocp.direct.solve`, exactly what
`ocp solve --no-refine` runs). Cases: the four transfers of Finch (2015) from the standard starts,
swing-up kappa = 1 (one switch), 1/2 and 3/4 (two switches) and damping kappa = 1 (one switch).
References: `ocp.exact.finch.one_switch` / `two_switch` (quadrature, error below 1e-13, checked
against 30-digit mpmath and DOP853 shooting in tests/test_analytic.py), so every error printed
here is the direct method's own to far below its last digit.

Per case and N (h = T/N): |dT| = |T - T*|, |dT|/h^2, |dT| over the former bound h^2/2 and over
the stated one (above 1: the bound fails; "none": none stated), and the largest switch-time error over h and over h^2 (a one-switch time is
fixed by the end constraint, O(h^2); two-switch times move along a direction in which T is
stationary, O(h)). The structure read off the control must be the formula's (else the row says
so). Errors are printed to two significant digits: they are exact to far more (the reference's
error is below 1e-13), two are what a ratio needs. Nothing is asserted here; tests/test_direct.py
uses the bound at N = 100, ocp/direct/shooting.py states it up to BOUND_N_MAX.
"""

import argparse
import concurrent.futures as cf
import json
import math
import os
import platform
import sys
import time

import ocp
from ocp.direct import solve as direct_solve
from ocp.direct.shooting import BOUND_N_MAX
from ocp.exact import finch

#: name -> (problem, reference transfer)
CASES = {
    "swing-up kappa=1": (lambda: ocp.swing_up(1.0), lambda: finch.one_switch("swing-up", 1.0)),
    "swing-up kappa=1/2": (lambda: ocp.swing_up(0.5), lambda: finch.two_switch("swing-up", 0.5)),
    "swing-up kappa=3/4": (lambda: ocp.swing_up(0.75), lambda: finch.two_switch("swing-up", 0.75)),
    "damping kappa=1": (lambda: ocp.damping(1.0), lambda: finch.one_switch("damping", 1.0)),
}
NS = (25, 50, 100, 200, 400, 800, 1600, 3200)


def signs(bb):
    return tuple(bb.first_u * (-1) ** i for i in range(bb.n_switches + 1))


def measure(case, N):
    """One row: the direct solve of `case` at N against its reference."""
    problem, reference = CASES[case]
    ref = reference()
    start = time.perf_counter()
    sol = direct_solve(problem(), ocp.MultipleShooting(N=N))
    wall = time.perf_counter() - start
    s = sol.structure
    h = sol.T / N
    row = {"case": case, "N": N, "status": sol.status.name.lower(), "h": h, "T": sol.T, "T_ref": ref.T,
           "ref_error": ref.error, "time_s": wall, "stated_bound": sol.T_bound, "n_switches": ref.n_switches}
    # a mirror image (theta -> -theta, u -> -u, target -pi) has the same times
    row["structure"] = "formula's" if s.arc_signs in (signs(ref), tuple(-u for u in signs(ref))) else \
        f"other: u = {s.arc_signs}"
    dT = abs(sol.T - ref.T)
    row.update(dT=dT, dT_h2=dT / h**2, over_bound=dT / (h**2 / 2))
    if row["structure"] == "formula's":
        dt = max(abs(a - b) for a, b in zip(s.switch_times, ref.switch_times))
        row.update(dt=dt, dt_h=dt / h, dt_h2=dt / h**2)
    else:
        row.update(dt=math.nan, dt_h=math.nan, dt_h2=math.nan)
    return row


def _g(x):
    """Two significant digits (see the module doc), or '-' for a missing value."""
    return "-" if x is None or not math.isfinite(x) else f"{x:.2g}"


COLUMNS = ("case", "N", "|dT|", "|dT|/h^2", "|dT|/(h^2/2)", "max |dt|/h", "max |dt|/h^2", "structure",
           "|dT|/stated", "solve s")


def cells(row):
    return (row["case"], str(row["N"]), _g(row["dT"]), _g(row["dT_h2"]), _g(row["over_bound"]), _g(row["dt_h"]),
            _g(row["dt_h2"]), row["structure"] if row["status"] == "verified" else row["status"],
            _g(row["dT"] / row["stated_bound"]) if row["stated_bound"] else "none", f"{row['time_s']:.1f}")


def summary(rows):
    """The largest ratios over the measured range N <= BOUND_N_MAX and beyond it (lines of text)."""
    lines = []
    ok = [r for r in rows if r["status"] == "verified" and r["structure"] == "formula's"]
    for label, part in (("N <= %d" % BOUND_N_MAX, [r for r in ok if r["N"] <= BOUND_N_MAX]),
                        ("N > %d" % BOUND_N_MAX, [r for r in ok if r["N"] > BOUND_N_MAX])):
        if not part:
            continue
        worst = max(part, key=lambda r: r["over_bound"])
        one = [r["dt_h2"] for r in part if r["n_switches"] == 1]
        two = [r["dt_h"] for r in part if r["n_switches"] == 2]
        lines.append(f"{label}: largest |dT|/h^2 = {_g(max(r['dT_h2'] for r in part))} "
                     f"(|dT| / (h^2/2) = {_g(worst['over_bound'])}, {worst['case']}, N = {worst['N']}); "
                     f"one switch: largest |dt|/h^2 = {_g(max(one, default=math.nan))}; "
                     f"two switches: largest |dt|/h = {_g(max(two, default=math.nan))}")
    bad = [r for r in rows if r not in ok]
    if bad:
        lines.append("rows without the formula's structure or not verified: "
                     + "; ".join(f"{r['case']} N = {r['N']}: {r['status']}, {r['structure']}" for r in bad))
    return lines


def random_instance(seed):
    """A seeded random instance: swing-up or damping, kappa log-uniform in [0.25, 2], x0 uniform in
    [-pi, pi] x [-2, 2]."""
    import numpy as np

    rng = np.random.default_rng(seed)
    kind = ("swing-up", "damping")[int(rng.integers(2))]
    kappa = float(np.exp(rng.uniform(np.log(0.25), np.log(2.0))))
    x0 = (float(rng.uniform(-math.pi, math.pi)), float(rng.uniform(-2.0, 2.0)))
    return kind, round(kappa, 4), x0


def cover(seed, N):
    """One coverage row: the direct answer (multiple shooting, rk4, M = 4, N) of a random instance
    against the exact search (`ocp.solve`), with what the stated error needs (switch states, h, miss)."""
    kind, kappa, x0 = random_instance(seed)
    start = time.perf_counter()
    sol = ocp.solve((ocp.swing_up if kind == "swing-up" else ocp.damping)(kappa, x0), ocp.MultipleShooting(N=N))
    d, a = sol.direct, sol.answer
    row = {"seed": seed, "kind": kind, "kappa": kappa, "x0": x0, "N": N, "time_s": round(time.perf_counter() - start, 1),
           "direct_status": d.status.name.lower(), "class": sol.direct_class.name.lower() if sol.direct_class is not None else None,
           "T": d.T, "h": d.T / N, "arc_signs": list(d.structure.arc_signs), "bang_bang": d.structure.bang_bang,
           "switch_states": [list(x) for x in d.structure.switch_states], "resim_miss": d.resim_miss,
           "T_star": a.T if a else None, "T_star_error": a.T_error if a else None,
           "same_structure": bool(a) and tuple(a.signs) == tuple(d.structure.arc_signs) and a.branch == d.branch}
    return row


def cover_reference(row, N):
    """A coverage row of an instance of the reference set (`ocp.reference`): the direct answer
    (multiple shooting, rk4, M = 4, N) against the set's optimum refined at 40 digits; classed
    "optimum" where it has the structure and branch of the optimum or of a tie, else "other"."""
    from ocp.core.problem import make

    start = time.perf_counter()
    sol = ocp.solve(make(row["kind"], row["kappa"], row["x0"], row["branch_pinned"]), ocp.MultipleShooting(N=N),
                    search=False)
    d, o = sol.direct, row["optimum"]
    optimal = {(tuple(e["arc_signs"]), e["branch"]) for e in [o, *row["ties"]]}
    same = d.success and (tuple(d.structure.arc_signs), d.branch) in optimal
    return {"id": row["id"], "kind": row["kind"], "kappa": row["kappa"], "x0": row["x0"], "N": N,
            "time_s": round(time.perf_counter() - start, 1), "direct_status": d.status.name.lower(),
            "class": "optimum" if same else "other", "T": d.T, "h": d.T / N, "arc_signs": list(d.structure.arc_signs),
            "bang_bang": d.structure.bang_bang, "switch_states": [list(x) for x in d.structure.switch_states],
            "resim_miss": d.resim_miss, "T_star": float(o["refined"]["T"]), "T_star_error": float(o["refined"]["T_error"]),
            "same_structure": same}


def reference_coverage(out, N, jobs):
    """Coverage rows of every solved instance of the reference set appended to `out` (resumable)."""
    from ocp.reference import load

    done = set()
    if os.path.exists(out):
        with open(out) as f:
            done = {(r["id"], r["N"]) for r in map(json.loads, f) if r}
    todo = [r for r in load().values() if r["status"] == "solved" and (r["id"], N) not in done]
    with cf.ProcessPoolExecutor(jobs) as pool:
        for row in pool.map(cover_reference, todo, [N] * len(todo)):
            with open(out, "a") as f:
                f.write(json.dumps(row) + "\n")
            print(f"direct_error: {row['id']} {row['class']}", file=sys.stderr, flush=True)


def coverage(out, seeds, N):
    """Coverage rows for `seeds` appended to `out` (JSON Lines; seeds already there are skipped)."""
    done = set()
    if os.path.exists(out):
        with open(out) as f:
            done = {(r["seed"], r["N"]) for r in map(json.loads, f) if r}
    for seed in seeds:
        if (seed, N) in done:
            continue
        row = cover(seed, N)
        with open(out, "a") as f:
            f.write(json.dumps(row) + "\n")
        print(f"direct_error: seed {seed} {row['class']}", file=sys.stderr, flush=True)


def coverage_summary(path):
    """Lines, per N: how often the stated bound (`ocp.direct.base.grid_bound`, recomputed from each
    row's switch states) and the former h^2/2 cover |T - T*| (plus the search's error) on the rows
    of `path` whose direct answer has the optimum's structure (classified optimum or inaccurate)."""
    from types import SimpleNamespace

    from ocp.direct.base import grid_bound

    with open(path) as f:
        rows = [json.loads(line) for line in f if line.strip()]
    lines = []
    for N in sorted({r["N"] for r in rows}):
        part = [r for r in rows if r["N"] == N]
        same = [r for r in part if r["class"] in ("optimum", "inaccurate")]
        ratios, none = [], 0
        for r in same:
            read = SimpleNamespace(bang_bang=r["bang_bang"], switch_states=r["switch_states"], h=r["h"])
            bound = grid_bound(read, r["kappa"], r["resim_miss"])
            error = abs(r["T"] - r["T_star"]) + r["T_star_error"]
            if bound is None:
                none += 1
            else:
                ratios.append((error / bound, error / (r["h"] ** 2 / 2)))
        classes = {}
        for r in part:
            classes[r["class"]] = classes.get(r["class"], 0) + 1
        lines += [f"N = {N}: {len(part)} instances ({', '.join(f'{k}: {v}' for k, v in sorted(classes.items(), key=str))}); "
                  f"{len(same)} with the optimum's structure",
                  f"  stated bound: covers {sum(a <= 1 for a, _ in ratios)} of {len(ratios)} where stated (none stated on "
                  f"{none}); largest |T - T*| / bound = {_g(max((a for a, _ in ratios), default=math.nan))}",
                  f"  former h^2/2: covers {sum(b <= 1 for _, b in ratios)} of {len(ratios)}; largest |T - T*| / (h^2/2) = "
                  f"{_g(max((b for _, b in ratios), default=math.nan))}"]
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", default=list(NS))
    parser.add_argument("--case", action="append", choices=list(CASES), help="only this case (repeatable)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (the wall times are then shared)")
    parser.add_argument("--markdown", action="store_true", help="a Markdown table (for benchmarks/README.md)")
    parser.add_argument("--coverage", type=int, metavar="K", help="instead: K seeded random instances against the search")
    parser.add_argument("--reference", action="store_true",
                        help="instead: every solved instance of the reference set against its refined optimum")
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--out", default="benchmarks/direct_coverage.jsonl", help="coverage rows (JSON Lines, resumable)")
    parser.add_argument("--coverage-summary", action="store_true", help="instead: summarise the rows of --out")
    args = parser.parse_args(argv)
    if args.coverage_summary:
        return print("\n".join(coverage_summary(args.out)))
    if args.reference:
        return reference_coverage(args.out, args.N[0] if args.N != list(NS) else 100, args.jobs)
    if args.coverage:
        return coverage(args.out, range(args.first_seed, args.first_seed + args.coverage), args.N[0] if args.N != list(NS) else 100)
    pairs = [(case, N) for case in args.case or CASES for N in args.N]
    with cf.ProcessPoolExecutor(args.jobs) if args.jobs > 1 else cf.ThreadPoolExecutor(1) as pool:
        futures = [pool.submit(measure, case, N) for case, N in pairs]
        for (case, N), future in zip(pairs, futures):
            future.result()
            print(f"direct_error: {case} N = {N} done", file=sys.stderr, flush=True)
    rows = [f.result() for f in futures]
    if args.markdown:
        escape = lambda texts: " | ".join(t.replace("|", "\\|") for t in texts)
        print("| " + escape(COLUMNS) + " |")
        print("|" + "|".join(" --- " for _ in COLUMNS) + "|")
        for r in rows:
            print("| " + escape(cells(r)) + " |")
    else:
        widths = [max(len(c), *(len(cells(r)[i]) for r in rows)) for i, c in enumerate(COLUMNS)]
        print("  ".join(c.ljust(w) for c, w in zip(COLUMNS, widths)))
        for r in rows:
            print("  ".join(c.ljust(w) for c, w in zip(cells(r), widths)))
    print()
    for line in summary(rows):
        print(line)
    print(f"\n(Python {platform.python_version()}, {platform.machine()}, {args.jobs} worker process(es); `solve s`: the "
          f"wall time of the direct solve with its three starts, its NLP built in it)")


if __name__ == "__main__":
    main()
