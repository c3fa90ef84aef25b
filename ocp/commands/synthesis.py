"""`ocp synthesis` and `ocp bifurcation`: the optimal synthesis over a window of the phase plane
(`ocp.synthesis.field`), a map (.npz) and its figure per kappa; the bifurcation values kappa_n of
N_kappa (`ocp.synthesis.results`), a JSON line per value in --store as soon as it is known (resumed).

The --out folder and the --store file are checked before the first map or case is computed.
"""


import sys

from ..core.arguments import add_window, formats, jobs, output_file, output_folder, problem_kappas, window
from ..core.errors import InputError, integer

#: --grid of a synthesis: points per axis
GRID = (11, 2001)
CHECKS = (0, 1000)


def add_commands(sub):
    sub.add_parser("synthesis", help="the optimal synthesis over a window of the phase plane: switch counts, value, "
                                     "switching and dispersal curves (a map and a figure per kappa)",
                   arguments=add_synthesis)
    sub.add_parser("bifurcation", help="the bifurcation values kappa_n of N_kappa, with error bars, attaining states "
                                       "and mechanisms", arguments=add_bifurcation)


def add_synthesis(p):
    from ..core.problem import KINDS

    p.add_argument("problem", help=f"one of: {', '.join(KINDS)}")
    p.add_argument("--kappa", nargs="+", required=True, help="one or more torque bounds")
    p.add_argument("--plane", action="store_true", help="the plane (target branch 0 only); default: the circle")
    add_window(p, (401, 241), f"grid points, each from {GRID[0]} to {GRID[1]}")
    p.add_argument("--check", default="0", help=f"re-solve this many random cells by ocp.solve and compare, "
                                                f"from {CHECKS[0]} to {CHECKS[1]}; default 0")
    p.add_argument("--out", default="synthesis", help="folder for the maps (.npz) and figures, default ./synthesis")
    p.add_argument("--format", default="png,pdf", help="figure formats, comma separated; default png,pdf")
    p.add_argument("--json", action="store_true", help="print one JSON array, an object per map")
    p.set_defaults(run=run_synthesis)


def run_synthesis(args):
    from ..core import plotting
    from ..core.heartbeat import heartbeat
    from ..core.output import print_json
    from ..synthesis.field import Window, check, save, summary, synthesize
    from ..figures.synthesis import draw_map

    kappas = problem_kappas(args)
    values, horizon = window(args, *GRID)
    checks = integer("check", args.check, f"an integer from {CHECKS[0]} to {CHECKS[1]}", *CHECKS)
    chosen = formats(args.format)
    out = output_folder("--out", args.out)
    reading = "plane" if args.plane else "circle"
    results = []
    for n, kappa in enumerate(kappas, 1):
        stem = out / f"{args.problem}-{reading}-kappa-{kappa:g}"
        data = stem.parent / (stem.name + ".npz")
        if not args.json:
            print(f"[{n}/{len(kappas)}] {args.problem}, {reading}, kappa = {kappa:g} ...", file=sys.stderr, flush=True)
        with heartbeat(None if args.json else sys.stderr, lambda: f"[{n}/{len(kappas)}] kappa = {kappa:g}: the field "
                                                                  f"of extremals"):
            s = synthesize(args.problem, kappa, reading, Window(*values), horizon)
        save(s, data)                               # written whole, or a Fault (ocp.core.files)
        with plotting.style():
            figures = plotting.save(draw_map(s), stem, chosen)
        result = dict(summary(s), files=[str(data)] + [str(f) for f in figures])
        if checks:
            rows = check(s, checks, seed=n)
            result["check"] = {"cells": len(rows), "largest |V - T|": max((abs(r[2] - r[4]) for r in rows), default=0.0),
                               "switch counts that differ": sum(r[3] != r[5] for r in rows)}
        results.append(result)
        if not args.json:
            counts = ", ".join(f"N = {k}: {v}" for k, v in result["switch_counts"].items())
            print(f"{args.problem}, {reading}, kappa = {kappa:g}: {counts} cells; covered {result['covered']:.1%}; "
                  f"{s.extremals} extremals in {s.time_s:.1f} s; {', '.join(result['files'])}")
            if checks:
                c = result["check"]
                print(f"  checked {c['cells']} random cells by ocp.solve: largest |V - T| {c['largest |V - T|']:.1e}, "
                      f"switch counts that differ: {c['switch counts that differ']}")
    if args.json:
        print_json(results)
    return 0

def add_bifurcation(p):
    from ..core.parallel import ACCEPTED

    p.add_argument("--case", action="append", metavar="KIND/READING/N",
                   help="only this case (repeatable), e.g. swing-up/circle/1; default: every located case")
    p.add_argument("--store", default="ocp-bifurcation.jsonl", help="results, a JSON line per value (resumed)")
    p.add_argument("--jobs", default="1", help="local worker processes, default 1")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help=f"run on the Dask distributed scheduler at ADDRESS instead: {ACCEPTED}")
    p.add_argument("--json", action="store_true", help="print the table as one JSON array")
    p.add_argument("--sweep", metavar="FILE", help="instead: compute (resumed) into FILE the sweep of the one --case "
                                                   "whose value is its fold and tie (the gaps above it), e.g. "
                                                   "ocp/synthesis/data/sweep-damping-3-0.50341.jsonl")
    p.set_defaults(run=run_bifurcation)


def run_bifurcation(args):
    from ..core.output import print_json
    from ..synthesis import results as store
    from ..core.parallel import Progress, drain, executor

    cases = store.cases(args.case)
    if args.sweep is not None:
        if len(cases) != 1 or getattr(cases[0], "above", None) is None:
            swept = ", ".join(c.id for c in store.cases() if getattr(c, "above", None) is not None)
            raise InputError(f"--sweep needs one --case with a sweep; accepted: {swept}")
        store.sweep(cases[0], output_file("--sweep", args.sweep))
        print(f"{cases[0].id}: the sweep at kappa = {cases[0].above:g} is in {args.sweep}")
        return 0
    workers = jobs(args.jobs)
    path = output_file("--store", args.store)
    rows = store.load(path)
    todo = [c for c in cases if c.id not in rows]

    def handle(case, row):
        store.append(path, row)                     # stored as soon as it is known: an interruption keeps it
        rows[row["case"]] = row
        return f"{row['case']}: kappa = {row['kappa']!r}"

    if todo:
        with executor(workers, args.scheduler) as (pool, workers, name):
            drain(pool, workers, [(store.compute, (c,), c) for c in todo], handle,
                  Progress(len(todo), "bifurcation values"), label=lambda case: case.id)
    table = [rows[c.id] for c in cases]
    if args.json:
        print_json(table)
    else:
        print(store.format_table(table))
    return 0
