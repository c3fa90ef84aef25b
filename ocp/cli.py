"""The `ocp` command line: one line per common job, `--json` for scripts.

Exit status: 0 done; 1 a solve that failed (with --json, still one object, "success": false) or a
fault of the environment (a folder not writable, a full disk, a corrupted store); 2 bad input (one
line says what was wrong and what is accepted). No traceback reaches the user.
"""

import argparse
import json
import os
import re
import sys

from .core.errors import Fault, InputError

#: direct-transcription flags of `ocp solve` -> the transcription setting they give
DIRECT_SETTINGS = {"N": "N", "integrator": "integrator", "M": "M", "tol": "tol", "degree": "degree"}


class _Parser(argparse.ArgumentParser):
    """argparse, with a usage error as one line and exit status 2, and negative numbers in
    e-notation (-1e-3) read as numbers, not options."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")

    def error(self, message):
        raise InputError(f"{self.prog}: {message}")


def _option(text):
    """KEY=VALUE for the NLP solver; VALUE read as JSON where it parses (numbers, true, lists)."""
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"{text!r} is not KEY=VALUE (e.g. ipopt.tol=1e-10)")
    try:
        return key, json.loads(value)
    except (json.JSONDecodeError, RecursionError):
        return key, value


def _add_solve(sub):
    from .core.problem import KINDS

    p = sub.add_parser("solve", help="the minimum-time swing-up or damping: complete search of extremals, "
                                     "and a direct transcription on request")
    p.add_argument("problem", help=f"one of: {', '.join(KINDS)}")
    p.add_argument("--kappa", required=True, help="torque bound tau0/(m g l)")
    p.add_argument("--x0", nargs=2, metavar=("THETA", "OMEGA"), help="initial state (rad, rad per unit time)")
    reading = p.add_mutually_exclusive_group()
    reading.add_argument("--branch", help="solve on the plane, target branch K pinned (swing-up: pi + 2 pi K, "
                                          "damping: 2 pi K); default: the circle, any branch")
    reading.add_argument("--plane", action="store_true", help="solve on the plane, the standard target (branch 0)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    d = p.add_argument_group("direct transcription (classified against the search's optimum)")
    d.add_argument("--direct", action="store_true", help="also solve a direct transcription and classify it")
    d.add_argument("--no-refine", action="store_true",
                   help="the direct transcription's answer alone: no search, optimality unknown")
    d.add_argument("--transcription", default="multiple-shooting",
                   help="multiple-shooting (default) or direct-collocation")
    d.add_argument("--N", help="intervals, default 100")
    d.add_argument("--integrator", help="multiple shooting: rk4 (default), cvodes, collocation")
    d.add_argument("--M", help="rk4 steps or collocation elements per interval, default 4")
    d.add_argument("--tol", help="cvodes tolerance, default 1e-10")
    d.add_argument("--degree", help="direct collocation: Radau points per interval, default 3")
    d.add_argument("--solver", default="ipopt", help="a casadi.nlpsol plugin (ipopt, fatrop, sqpmethod, ...)")
    d.add_argument("--option", action="append", type=_option, default=[], metavar="KEY=VALUE",
                   help="an NLP solver option, passed untouched (repeatable), e.g. ipopt.tol=1e-10")
    d.add_argument("--allow-unsafe-options", action="store_true",
                   help="permit options that run a program or read or write a file (jit, output_file, ...)")
    d.add_argument("--miss-tol", help="largest re-simulated miss of a direct answer accepted, default 1e-6")
    p.set_defaults(run=_run_solve)


def _method(args):
    """The direct transcription the flags ask for, or None (InputError for flags without --direct)."""
    from . import direct
    from .core.errors import finite, integer

    given = {name: getattr(args, flag) for flag, name in DIRECT_SETTINGS.items() if getattr(args, flag) is not None}
    wanted = args.direct or args.no_refine
    flags = [f"--{f.replace('_', '-')}" for f in ("solver", "transcription") if getattr(args, f) != {
        "solver": "ipopt", "transcription": "multiple-shooting"}[f]]
    flags += [f"--{f}" for f in given] + (["--option"] if args.option else []) + (
        ["--miss-tol"] if args.miss_tol is not None else [])
    if not wanted:
        if flags:
            raise InputError(f"{', '.join(flags)} appl{'ies' if len(flags) == 1 else 'y'} to a direct transcription: "
                             f"add --direct (classified against the search) or --no-refine (its answer alone)")
        return None
    numbers = {"N": lambda v: integer("N", v, "an integer from 2 to 5000", 2, 5000),
               "M": lambda v: integer("M", v, "an integer from 1 to 64", 1, 64),
               "degree": lambda v: integer("degree", v, "an integer from 1 to 9", 1, 9),
               "tol": lambda v: finite("tol", v, "a number in [1e-14, 1e-3]", 1e-14, 1e-3),
               "integrator": str}
    return direct.make(args.transcription, **{k: numbers[k](v) for k, v in given.items()})


def _run_solve(args):
    from .core.errors import finite, integer
    from .core.output import print_json, solver_output
    from .core.problem import make
    from .direct.solve import MISS_TOL_RANGE

    branch = 0 if args.plane else (None if args.branch is None else integer(
        "branch", args.branch, "an integer k (the target branch)", -10**6, 10**6))
    problem = make(args.problem, args.kappa, args.x0, branch)
    method = _method(args)
    low, high = MISS_TOL_RANGE
    miss_tol = None if args.miss_tol is None else finite("miss-tol", args.miss_tol, f"a number from {low:g} to {high:g}",
                                                         low, high)
    from . import solving as solve_module
    with solver_output("stderr"):
        result = solve_module.solve(problem, method, args.solver, dict(args.option), miss_tol=miss_tol,
                                    search=not args.no_refine, trusted=args.allow_unsafe_options)
    if args.json:
        print_json(result.to_dict())
    else:
        print(result.summary())
    return 0 if result.success else 1


def _add_verify(sub):
    p = sub.add_parser("verify", help="every published value beside the suite's computation of it")
    p.add_argument("--paper", help="only this paper (see --help for the ids)")
    p.add_argument("--json", action="store_true", help="one JSON array, a row per value")
    p.set_defaults(run=_run_verify)


def _run_verify(args):
    from .core.output import print_json
    from .papers import references, verify

    papers = references.papers()
    if args.paper is not None and args.paper not in papers:
        raise InputError(f"unknown paper {args.paper!r}; accepted: {', '.join(papers)}")
    table = verify.rows(args.paper, progress=sys.stderr)
    if args.json:
        print_json(verify.as_dicts(table))
    else:
        print(verify.format_table(table))
    return 0 if all(r.verdict != "disagrees" for r in table) else 1


def _add_figures(sub):
    p = sub.add_parser("figures", help="the papers' figures from the suite's own computations, and the benchmark charts")
    p.add_argument("--out", default="figures", help="folder for the files, default ./figures")
    p.add_argument("--only", action="append", metavar="NAME", help="only this figure (repeatable; a wrong name lists them all)")
    p.add_argument("--format", default="png,pdf", help="comma separated: png, pdf, svg; default png,pdf")
    p.add_argument("--store", default="ocp-bench-quick.sqlite",
                   help="the results store of `ocp bench` for the benchmark charts (skipped if absent), "
                        "default ./ocp-bench-quick.sqlite")
    p.set_defaults(run=_run_figures)


def _run_figures(args):
    from . import figures
    from .core.output import solver_output

    with solver_output("stderr"):
        written = figures.write(args.out, args.only, tuple(f.strip() for f in args.format.split(",")), args.store)
    for name, paths in written.items():
        print(f"{name}: {paths}" if isinstance(paths, str) else f"{name}: {', '.join(map(str, paths))}")
    return 0


def _add_window(p, grid, what):
    """--window, --grid (default `grid`, of `what`) and --horizon of a map of the phase plane."""
    p.add_argument("--window", nargs=4, metavar=("THETA_LO", "THETA_HI", "OMEGA_LO", "OMEGA_HI"),
                   default=["-3.141592653589793", "3.141592653589793", "-3", "3"], help="default [-pi, pi] x [-3, 3]")
    p.add_argument("--grid", nargs=2, metavar=("N_THETA", "N_OMEGA"), default=[str(g) for g in grid],
                   help=f"{what}, default {grid[0]} {grid[1]}")
    p.add_argument("--horizon", default="12", help="longest time-to-go of the synthesis drawn, default 12")


def _window(args, low, high):
    """(Window of --window and --grid, each count from `low` to `high`; --horizon), checked."""
    from .core.errors import finite, integer
    from .synthesis.field import Window

    lo_t, hi_t, lo_w, hi_w = (finite("window", v, "four numbers, |theta| <= 1000, |omega| <= 50", -1000, 1000)
                              for v in args.window)
    if not (lo_t < hi_t and lo_w < hi_w and max(abs(lo_w), abs(hi_w)) <= 50):
        raise InputError("window: THETA_LO < THETA_HI and OMEGA_LO < OMEGA_HI, |omega| <= 50")
    grid = [integer("grid", g, f"two integers from {low} to {high}", low, high) for g in args.grid]
    return (Window(lo_t, hi_t, lo_w, hi_w, *grid),
            finite("horizon", args.horizon, "a number of time units from 0.1 to 60", 0.1, 60))


def _problem_kappas(args):
    """The kappas of --kappa (each in the accepted range), the problem checked."""
    from .core.errors import finite
    from .core.problem import KINDS, KAPPA_RANGE

    if args.problem not in KINDS:
        raise InputError(f"unknown problem {args.problem!r}; accepted: {', '.join(KINDS)}")
    return [finite("kappa", k, f"numbers from {KAPPA_RANGE[0]:g} to {KAPPA_RANGE[1]:g}", *KAPPA_RANGE) for k in args.kappa]


def _formats(text):
    """The figure formats of a comma-separated --format."""
    from .core import plotting

    formats = tuple(f.strip() for f in text.split(",") if f.strip())
    if not formats or set(formats) - set(plotting.FORMATS):
        raise InputError(f"format {text!r}: accepted {', '.join(plotting.FORMATS)} (comma separated)")
    return formats


def _add_synthesis(sub):
    from .core.problem import KINDS

    p = sub.add_parser("synthesis", help="the optimal synthesis over a window of the phase plane: switch counts, "
                                         "value, switching and dispersal curves (a map and a figure per kappa)")
    p.add_argument("problem", help=f"one of: {', '.join(KINDS)}")
    p.add_argument("--kappa", nargs="+", required=True, help="one or more torque bounds")
    p.add_argument("--plane", action="store_true", help="the plane (target branch 0 only); default: the circle")
    _add_window(p, (401, 241), "grid points")
    p.add_argument("--check", default="0", help="re-solve this many random cells by ocp.solve and compare")
    p.add_argument("--out", default="synthesis", help="folder for the maps (.npz) and figures, default ./synthesis")
    p.add_argument("--format", default="png,pdf", help="figure formats, comma separated; default png,pdf")
    p.add_argument("--json", action="store_true", help="print one JSON array, an object per map")
    p.set_defaults(run=_run_synthesis)


def _run_synthesis(args):
    from pathlib import Path

    from .core import plotting
    from .core.errors import integer
    from .core.output import print_json
    from .figures.synthesis import draw_map
    from .synthesis.field import check, save, summary, synthesize

    kappas = _problem_kappas(args)
    window, horizon = _window(args, 11, 2001)
    checks = integer("check", args.check, "an integer from 0 to 1000", 0, 1000)
    formats = _formats(args.format)
    reading = "plane" if args.plane else "circle"
    out, results = Path(args.out), []
    for n, kappa in enumerate(kappas, 1):
        stem = out / f"{args.problem}-{reading}-kappa-{kappa:g}"
        data = stem.parent / (stem.name + ".npz")
        if not args.json:
            print(f"[{n}/{len(kappas)}] {args.problem}, {reading}, kappa = {kappa:g} ...", file=sys.stderr, flush=True)
        s = synthesize(args.problem, kappa, reading, window, horizon)
        save(s, data)                               # written whole, or a Fault (ocp.core.files)
        with plotting.style():
            figures = plotting.save(draw_map(s), stem, formats)
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


def _add_failure_map(sub):
    from .core.problem import KINDS

    p = sub.add_parser("failure-map", help="where a direct method fails: its outcome class (against the complete "
                                           "search) over a grid of starts at one kappa, or over kappa at one start")
    p.add_argument("problem", help=f"one of: {', '.join(KINDS)}")
    p.add_argument("--kappa", nargs="+", required=True,
                   help="one torque bound (a grid of starts), or LO HI with --sweep COUNT (a sweep of kappa)")
    p.add_argument("--sweep", metavar="COUNT", help="COUNT values of kappa from LO to HI, at the start --x0")
    p.add_argument("--x0", nargs=2, metavar=("THETA", "OMEGA"), help="the start of a sweep (default: the standard one)")
    p.add_argument("--transcription", default="multiple-shooting", help="multiple-shooting (default) or direct-collocation")
    p.add_argument("--N", default="25", help="intervals, default 25")
    p.add_argument("--solver", default="ipopt", help="a casadi.nlpsol plugin, default ipopt")
    p.add_argument("--configuration", default="default", help="default or fair (ocp.bench.configurations)")
    _add_window(p, (21, 15), "starts")
    p.add_argument("--jobs", default="1", help="local worker processes, default 1")
    p.add_argument("--out", default="failure-maps", help="folder for the map (.npz) and its figure, default ./failure-maps")
    p.add_argument("--format", default="png", help="figure formats, comma separated; default png")
    p.add_argument("--json", action="store_true", help="print one JSON object (the outcome counts and the reasons)")
    p.set_defaults(run=_run_failure_map)


def _run_failure_map(args):
    from dataclasses import replace
    from pathlib import Path

    import numpy as np

    from .bench import failure_map
    from .bench.runner import Progress, executor
    from .bench.suite import Method
    from .core import plotting
    from .core.errors import finite, integer
    from .core.output import print_json, solver_output
    from .figures.failure_map import draw_grid, draw_sweep
    from .synthesis.field import synthesize

    kappas = _problem_kappas(args)
    if len(kappas) != (1 if args.sweep is None else 2) or (args.sweep is not None and kappas[0] >= kappas[1]):
        raise InputError("kappa: one value (a grid of starts), or LO HI with LO < HI and --sweep COUNT")
    if args.x0 is not None and args.sweep is None:
        raise InputError("--x0 is the start of a sweep: add --sweep COUNT (a grid takes its starts from --window)")
    N = integer("N", args.N, "an integer from 2 to 400", 2, 400)
    method = Method(args.transcription, (("N", N),), args.solver, {}, args.configuration)
    jobs = integer("jobs", args.jobs, "an integer from 1 to 64", 1, 64)
    formats = _formats(args.format)
    if args.sweep is not None:
        cells = integer("sweep", args.sweep, "an integer from 2 to 401", 2, 401)
        x0 = None if args.x0 is None else tuple(finite("x0", v, "two numbers, |theta| <= 1000, |omega| <= 50", -1000, 1000)
                                                for v in args.x0)
    else:
        window, horizon = _window(args, 2, 201)
        cells = window.n_theta * window.n_omega
    with executor(jobs) as (pool, workers, _), solver_output("stderr"):
        progress = Progress(cells, "cells")
        if args.sweep is not None:
            fmap = failure_map.sweep(args.problem, np.linspace(kappas[0], kappas[1], cells), x0, method, pool, workers,
                                     progress)
        else:
            fmap = failure_map.grid(args.problem, kappas[0], method, window, pool, workers, progress)
            synthesis = synthesize(args.problem, kappas[0], "circle", replace(window, n_theta=401, n_omega=301), horizon)
    stem = Path(args.out) / failure_map.name(fmap)
    with plotting.style():
        figure = draw_sweep(fmap) if args.sweep is not None else draw_grid(fmap, synthesis)
        files = [failure_map.save(fmap, stem.with_name(stem.name + ".npz"))] + plotting.save(figure, stem, formats)
    result = dict(failure_map.summary(fmap), files=[str(f) for f in files])
    if args.json:
        print_json(result)
    else:
        print(f"{result['method']}, {args.problem}: {', '.join(f'{k} {v}' for k, v in result['outcomes'].items())} "
              f"cells in {fmap.time_s:.0f} s; {', '.join(result['files'])}")
        for reason in result["reasons"]:
            print(f"  {reason}")
    return 0


def _add_bifurcation(sub):
    p = sub.add_parser("bifurcation", help="the bifurcation values kappa_n of N_kappa, with error bars, attaining "
                                           "states and mechanisms")
    p.add_argument("--case", action="append", metavar="KIND/READING/N",
                   help="only this case (repeatable), e.g. swing-up/circle/1; default: every located case")
    p.add_argument("--store", default="ocp-bifurcation.jsonl", help="results, a JSON line per value (resumed)")
    p.add_argument("--jobs", default="1", help="local worker processes, default 1")
    p.add_argument("--scheduler", metavar="ADDRESS", help="a Dask distributed scheduler instead of local processes")
    p.add_argument("--json", action="store_true", help="print the table as one JSON array")
    p.set_defaults(run=_run_bifurcation)


def _run_bifurcation(args):
    from .bench.runner import Progress, drain, executor
    from .core.errors import integer
    from .core.output import print_json
    from .synthesis import results as store

    cases = store.cases(args.case)
    jobs = integer("jobs", args.jobs, "an integer from 1 to 64", 1, 64)
    rows = store.load(args.store)
    todo = [c for c in cases if c.id not in rows]
    def handle(case, row):
        store.append(args.store, row)               # stored as soon as it is known: an interruption keeps it
        rows[row["case"]] = row
        return f"{row['case']}: kappa = {row['kappa']!r}"

    if todo:
        with executor(jobs, args.scheduler) as (pool, workers, name):
            drain(pool, workers, [(store.compute, (c,), c) for c in todo], handle,
                  Progress(len(todo), "bifurcation values"))
    table = [rows[c.id] for c in cases]
    if args.json:
        print_json(table)
    else:
        print(store.format_table(table))
    return 0


def _one_line(err):
    """An error's message on one line (a value quoted in it may hold line breaks)."""
    return str(err).replace("\r", "\\r").replace("\n", "\\n")


def main(argv=None):
    parser = _Parser(prog="ocp", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    _add_solve(sub)
    _add_verify(sub)
    _add_figures(sub)
    _add_synthesis(sub)
    _add_bifurcation(sub)
    _add_failure_map(sub)
    from .bench.command import add_commands
    add_commands(sub)
    from .reference.command import add_commands as add_reference_commands
    add_reference_commands(sub)
    try:
        args = parser.parse_args(argv)
        return args.run(args)
    except InputError as err:
        print(f"error: {_one_line(err)}", file=sys.stderr)
        return 2
    except Fault as err:
        print(f"failed: {_one_line(err)}", file=sys.stderr)
        return 1
    except BrokenPipeError:          # the reader (e.g. `| head`) stopped reading: not an error of ours
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
