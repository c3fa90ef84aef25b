"""`ocp solve`: the minimum-time swing-up or damping of one problem (`ocp.solving.solve`).

The direct transcription's flags are made from the registry: `--transcription` from
`ocp.direct.TRANSCRIPTIONS`, one `--NAME` per setting of `ocp.direct.settings()` (help, range and
check from its declaration).
"""

import argparse
import json

from ..core.arguments import add_settings, given_settings
from ..core.errors import InputError, finite, integer, short

DEFAULTS = {"transcription": "multiple-shooting", "solver": "ipopt"}
#: the search's time limit by default: every accepted solve ends within it (or its direct solve's
#: stated time, `ocp.direct` size limits), with the best answer so far if it was cut
TIME_LIMIT_S = 60.0


def add_commands(sub):
    sub.add_parser("solve", help="the minimum-time swing-up or damping: complete search of extremals, and a direct "
                                 "transcription on request", arguments=add_arguments)


def _option(text):
    """KEY=VALUE for the NLP solver; VALUE read as JSON where it parses (numbers, true, lists), a
    non-finite number (NaN, Infinity) refused."""
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"{short(text)} is not KEY=VALUE (e.g. ipopt.tol=1e-10)")

    def refuse(constant):
        raise argparse.ArgumentTypeError(f"{short(text)}: {constant} is not a finite number")

    try:
        return key, json.loads(value, parse_constant=refuse)
    except (ValueError, RecursionError):        # not JSON, or an integer of more than 4300 digits
        return key, value


class _Shipped:
    """The NLP solvers this CasADi build ships, as --solver's help shows them: found (CasADi imported,
    its plugins loaded) only when the help is printed, not for every parse."""

    def __str__(self):
        from ..direct.solvers import available_solvers

        return ", ".join(available_solvers())


def add_arguments(p):
    from .. import direct
    from ..core.problem import KINDS

    p.add_argument("problem", help=f"one of: {', '.join(KINDS)}")
    p.add_argument("--kappa", required=True, help="torque bound tau0/(m g l)")
    p.add_argument("--x0", nargs=2, metavar=("THETA", "OMEGA"), help="initial state (rad, rad per unit time)")
    reading = p.add_mutually_exclusive_group()
    reading.add_argument("--branch", help="solve on the plane, target branch K pinned (swing-up: pi + 2 pi K, "
                                          "damping: 2 pi K); default: the circle, any branch")
    reading.add_argument("--plane", action="store_true", help="solve on the plane, the standard target (branch 0)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--time-limit", metavar="S", default=str(TIME_LIMIT_S),
                   help=f"end the search after S seconds (0.01 to 1e6; default {TIME_LIMIT_S:g}) with the best answer "
                        f"so far, marked as not proven optimal (exit 1 if there is none)")
    p.add_argument("--sample", metavar="DT", help="sample the answer every DT time units, every switch and T "
                                                  "included (t, theta, omega, u, p1, p2): with --csv or --json")
    p.add_argument("--csv", metavar="FILE", help="write the samples of --sample as CSV")
    p.add_argument("--plot", metavar="FILE", help="draw the solution (phase portrait; theta, omega, u against t; "
                                                 "the direct answer overlaid): FILE.png, .pdf or .svg")
    d = p.add_argument_group("direct transcription (classified against the search's optimum)")
    which = d.add_mutually_exclusive_group()
    which.add_argument("--direct", action="store_true", help="also solve a direct transcription and classify it")
    which.add_argument("--no-refine", action="store_true",
                       help="the direct transcription's answer alone: no search, optimality unknown")
    d.add_argument("--transcription", default=DEFAULTS["transcription"], choices=tuple(direct.TRANSCRIPTIONS),
                   help=f"one of {', '.join(direct.TRANSCRIPTIONS)}; default {DEFAULTS['transcription']}")
    takers = {name: [t for t, cls in direct.TRANSCRIPTIONS.items() if name in {s.name for s in cls.SETTINGS}]
              for name in direct.settings()}
    add_settings(d, direct.settings(), notes={name: f"{', '.join(t)} only" for name, t in takers.items()
                                               if len(t) < len(direct.TRANSCRIPTIONS)})
    solver = d.add_argument("--solver", default=DEFAULTS["solver"],
                            help=f"an NLP solver of ocp.direct.solvers that this CasADi build ships: "
                                 f"%(shipped)s; default {DEFAULTS['solver']}")
    solver.shipped = _Shipped()
    d.add_argument("--option", action="append", type=_option, default=[], metavar="KEY=VALUE",
                   help="an NLP solver option on its allow-list, typed (repeatable), e.g. ipopt.tol=1e-10")
    d.add_argument("--allow-unsafe-options", action="store_true",
                   help="pass any option untouched, also those that load a library, run a program or "
                        "touch a file (a relative path is then relative to a private empty folder)")
    d.add_argument("--miss-tol", help="largest re-simulated miss of a direct answer accepted, default 1e-6")
    p.set_defaults(run=run)


def method(args):
    """The direct transcription the flags ask for, or None (InputError for flags without --direct)."""
    from .. import direct

    declared = direct.settings()
    given = [name for name in declared if getattr(args, name) is not None]
    flags = [f"--{f}" for f, default in DEFAULTS.items() if getattr(args, f) != default]
    flags += [f"--{f}" for f in given] + (["--option"] if args.option else []) + (
        ["--miss-tol"] if args.miss_tol is not None else [])
    if not (args.direct or args.no_refine):
        if flags:
            raise InputError(f"{', '.join(flags)} appl{'ies' if len(flags) == 1 else 'y'} to a direct transcription: "
                             f"add --direct (classified against the search) or --no-refine (its answer alone)")
        return None
    return direct.make(args.transcription, **given_settings(args, declared))


def run(args):
    import sys

    from .. import solving
    from ..core.output import print_json, solver_output
    from ..core.problem import make
    from ..direct.solve import MISS_TOL_RANGE
    from ..direct.watch import stderr_progress

    branch = 0 if args.plane else (None if args.branch is None else integer(
        "branch", args.branch, "an integer k (the target branch)", -10**6, 10**6))
    problem = make(args.problem, args.kappa, args.x0, branch)
    transcription = method(args)
    low, high = MISS_TOL_RANGE
    miss_tol = None if args.miss_tol is None else finite("miss-tol", args.miss_tol, f"a number from {low:g} to {high:g}",
                                                         low, high)
    limit = finite("time-limit", args.time_limit, "seconds from 0.01 to 1e6", 0.01, 1e6)
    export = None
    if (args.sample, args.csv, args.plot) != (None, None, None):     # the drawing stack only when asked for
        from ..figures.solution import Export
        export = Export.of(args.sample, args.csv, args.plot, args.json)
    with solver_output("stderr"):
        result = solving.solve(problem, transcription, args.solver, dict(args.option), miss_tol=miss_tol,
                               search=not args.no_refine, trusted=args.allow_unsafe_options, time_limit=limit,
                               progress=stderr_progress())
    exported, lines = export.write(result) if export else ({}, [])
    if args.json:
        print_json(dict(result.to_dict(), **exported))
        for line in lines:
            print(line, file=sys.stderr)
    else:
        print("\n".join([result.summary(), *lines]))
    return 0 if result.success else 1
