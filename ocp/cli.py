"""The `ocp` command line: one line per common job, `--json` for scripts.

Bad input prints one line (what was wrong, what is accepted) and exits 2; a solve that fails
exits 1 (with `--json`, still one object with "success": false).
"""

import argparse
import json
import math
import os
import sys

from .errors import InputError
from .redirect import solver_output


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line and exit status 2."""

    def error(self, message):
        raise InputError(f"{self.prog}: {message}")


def _print_json(obj):
    """One JSON document on stdout; numpy values as lists, non-finite numbers as null."""
    print(json.dumps(_plain(obj), indent=2, allow_nan=False))


def _plain(obj):
    if isinstance(obj, dict):
        return {k: _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if hasattr(obj, "tolist"):
        return _plain(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _option(text):
    """KEY=VALUE for the NLP solver; VALUE read as JSON where it parses (numbers, true, lists)."""
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"{text!r} is not KEY=VALUE (e.g. ipopt.tol=1e-10)")
    try:
        return key, json.loads(value)
    except json.JSONDecodeError:
        return key, value


def _add_solve(sub):
    from .problems import KINDS
    from .transcription import INTEGRATORS

    p = sub.add_parser("solve", help="minimum-time swing-up or damping by multiple shooting")
    p.add_argument("problem", help=f"one of: {', '.join(KINDS)}")
    p.add_argument("--kappa", required=True, help="torque bound tau0/(m g l), > 0")
    p.add_argument("--x0", nargs=2, metavar=("THETA", "OMEGA"), help="initial state (rad, rad per unit time)")
    p.add_argument("--branch", help="pin the target branch k (swing-up: pi + 2*pi*k, damping: 2*pi*k); default: any")
    p.add_argument("--transcription", default="multiple-shooting", help="multiple-shooting (default) or direct-collocation")
    p.add_argument("--N", default="100", help="intervals (>= 2), default 100")
    p.add_argument("--integrator", default="rk4", help=f"one of: {', '.join(INTEGRATORS)}; default rk4")
    p.add_argument("--M", default="4", help="rk4 steps or collocation elements per interval, default 4")
    p.add_argument("--tol", default="1e-10", help="cvodes tolerance, default 1e-10")
    p.add_argument("--degree", default="3", help="direct collocation: Radau points per interval, default 3")
    p.add_argument("--solver", default="ipopt", help="a casadi.nlpsol plugin (ipopt, fatrop, sqpmethod, ...)")
    p.add_argument("--option", action="append", type=_option, default=[], metavar="KEY=VALUE",
                   help="an NLP solver option, passed untouched (repeatable), e.g. ipopt.tol=1e-10")
    p.add_argument("--miss-tol", default="1e-6", help="largest re-simulated miss accepted as success")
    p.add_argument("--no-refine", action="store_true",
                   help="the plain direct answer: no refinement, no competing structures, no certificate")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(run=_run_solve)


def _integer(name, text, accepted):
    try:
        return int(text)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {text!r} is not an integer; {name} accepts {accepted}") from None


def _run_solve(args):
    from . import pipeline, problems
    from .errors import finite
    from .transcription import DirectCollocation, MultipleShooting

    problem = problems.make(args.problem, args.kappa, args.x0,
                            None if args.branch is None else _integer("branch", args.branch, "an integer k"))
    N = _integer("N", args.N, "an integer >= 2")
    if args.transcription == "multiple-shooting":
        method = MultipleShooting(N, args.integrator, _integer("M", args.M, "an integer >= 1"),
                                  finite("tol", args.tol, "a number in (0, 1)"))
    elif args.transcription == "direct-collocation":
        method = DirectCollocation(N, _integer("degree", args.degree, "an integer from 1 to 9"))
    else:
        raise InputError(f"unknown transcription {args.transcription!r}; accepted: multiple-shooting, direct-collocation")
    miss_tol = finite("miss-tol", args.miss_tol, "a number > 0")
    with solver_output("stderr"):
        result = pipeline.solve(problem, method, args.solver, dict(args.option), miss_tol=miss_tol,
                                refine=not args.no_refine)
    if args.json:
        _print_json(result.to_dict())
    else:
        print(result.summary())
    return 0 if result.success else 1


def _add_verify(sub):
    p = sub.add_parser("verify", help="every published value beside the suite's computation of it")
    p.add_argument("--paper", help="only this paper (a file stem in reference/)")
    p.add_argument("--json", action="store_true", help="one JSON array, a row per value")
    p.set_defaults(run=_run_verify)


def _run_verify(args):
    from . import references, verify

    if args.paper and args.paper not in references.papers():
        raise InputError(f"unknown paper {args.paper!r}; accepted: {', '.join(references.papers())}")
    table = verify.rows(args.paper)
    if args.json:
        _print_json(verify.as_dicts(table))
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

    with solver_output("stderr"):
        written = figures.write(args.out, args.only, tuple(f.strip() for f in args.format.split(",")), args.store)
    for name, paths in written.items():
        print(f"{name}: {paths}" if isinstance(paths, str) else f"{name}: {', '.join(map(str, paths))}")
    return 0


def main(argv=None):
    parser = _Parser(prog="ocp", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    _add_solve(sub)
    _add_verify(sub)
    _add_figures(sub)
    from .bench.command import add_commands as _add_bench_and_report
    _add_bench_and_report(sub)
    try:
        args = parser.parse_args(argv)
        return args.run(args)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:          # the reader (e.g. `| head`) stopped reading: not an error of ours
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
