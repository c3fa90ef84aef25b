"""`ocp failure-map`: where a direct method fails (`ocp.bench.failure_map`), a map (.npz) and its
figure (`ocp.figures.failure_map`).

Everything the cells need is checked before the first cell: the solver (among the plugins this
CasADi build has, no unknown name loaded), the transcription and its N, the configuration, the NLP
built once with them, the window, the formats and the --out folder.
"""

from ..core.arguments import add_settings, add_window, formats, given_settings, jobs, output_folder, problem_kappas, window
from ..core.errors import InputError, finite, integer, short

#: N of a map: each cell is a cold solve, so the map takes at most this many intervals
N_HIGH = 400
#: --grid of a map of starts (points per axis), --sweep of kappa (values)
GRID = (2, 201)
SWEEP = (2, 401)


def _n_setting():
    """The transcriptions' N, narrowed to N_HIGH and with the map's default 25."""
    from dataclasses import replace

    from ..direct import settings

    n = settings()["N"]
    return {"N": replace(n, default=25, high=min(n.high, N_HIGH))}


def add_commands(sub):
    sub.add_parser("failure-map", help="where a direct method fails: its outcome class (against the complete search) "
                                       "over a grid of starts at one kappa, or over kappa at one start",
                   arguments=add_arguments)


def add_arguments(p):
    from ..bench.configurations import CONFIGURATIONS
    from ..core.problem import KINDS
    from ..direct import TRANSCRIPTIONS
    from ..direct.solvers import available_solvers

    p.add_argument("problem", help=f"one of: {', '.join(KINDS)}")
    p.add_argument("--kappa", nargs="+", required=True,
                   help="one torque bound (a grid of starts), or LO HI with --sweep COUNT (a sweep of kappa)")
    p.add_argument("--sweep", metavar="COUNT", help=f"COUNT values of kappa from LO to HI, at the start --x0, "
                                                    f"from {SWEEP[0]} to {SWEEP[1]}")
    p.add_argument("--x0", nargs=2, metavar=("THETA", "OMEGA"), help="the start of a sweep (default: the standard one)")
    p.add_argument("--transcription", default="multiple-shooting", choices=tuple(TRANSCRIPTIONS),
                   help=f"one of {', '.join(TRANSCRIPTIONS)}; default multiple-shooting")
    add_settings(p, _n_setting(), notes={"N": f"at most {N_HIGH} here: every cell is a cold solve"})
    p.add_argument("--solver", default="ipopt", help=f"an NLP solver of ocp.direct.solvers that this CasADi build "
                                                     f"ships: {', '.join(available_solvers())}; default ipopt")
    p.add_argument("--configuration", default="default",
                   help=f"one of {', '.join(CONFIGURATIONS)} (ocp.bench.configurations), default default")
    add_window(p, (21, 15), f"starts, each from {GRID[0]} to {GRID[1]}")
    p.add_argument("--jobs", default="1", help="local worker processes, default 1")
    p.add_argument("--out", default="failure-maps", help="folder for the map (.npz) and its figure, default ./failure-maps")
    p.add_argument("--format", default="png", help="figure formats, comma separated; default png")
    p.add_argument("--json", action="store_true", help="print one JSON object (the outcome counts and the reasons)")
    p.set_defaults(run=run)


def run(args):
    from dataclasses import replace

    import numpy as np

    from ..bench import failure_map
    from ..core.parallel import Progress, executor
    from ..bench.suite import Method
    from ..core import plotting
    from ..core.output import print_json, printable, solver_output
    from ..core.problem import OMEGA_LIMIT, THETA_LIMIT
    from ..direct.nlp import build
    from ..direct.solvers import available_solvers
    from ..synthesis.field import Window, synthesize
    from ..figures.failure_map import draw_grid, draw_sweep

    kappas = problem_kappas(args)
    if len(kappas) != (1 if args.sweep is None else 2) or (args.sweep is not None and kappas[0] >= kappas[1]):
        raise InputError("kappa: one value (a grid of starts), or LO HI with LO < HI and --sweep COUNT")
    if args.x0 is not None and args.sweep is None:
        raise InputError("--x0 is the start of a sweep: add --sweep COUNT (a grid takes its starts from --window)")
    chosen = formats(args.format)
    out = output_folder("--out", args.out)
    solvers = available_solvers()
    if args.solver not in solvers:
        raise InputError(f"solver {short(args.solver)} is not available; accepted: {', '.join(solvers)}")
    N = given_settings(args, _n_setting()).get("N", 25)
    method = Method(args.transcription, (("N", N),), args.solver, {}, args.configuration)
    workers = jobs(args.jobs)
    if args.sweep is not None:
        cells = integer("sweep", args.sweep, f"an integer from {SWEEP[0]} to {SWEEP[1]}", *SWEEP)
        x0 = None if args.x0 is None else (
            finite("x0", args.x0[0], f"two numbers, |theta| <= {THETA_LIMIT:g}", -THETA_LIMIT, THETA_LIMIT),
            finite("x0", args.x0[1], f"two numbers, |omega| <= {OMEGA_LIMIT:g}", -OMEGA_LIMIT, OMEGA_LIMIT))
    else:
        values, horizon = window(args, *GRID)
        grid = Window(*values)
        cells = grid.n_theta * grid.n_omega
    with solver_output("devnull"):          # the NLP once, last: a solver that cannot build it is one line,
        build(method.transcription_object(), method.solver, method.applied, "circle")   # not a map of build errors
    with executor(workers) as (pool, workers, _), solver_output("stderr"):
        progress = Progress(cells, "cells")
        if args.sweep is not None:
            fmap = failure_map.sweep(args.problem, np.linspace(kappas[0], kappas[1], cells), x0, method, pool, workers,
                                     progress)
        else:
            fmap = failure_map.grid(args.problem, kappas[0], method, grid, pool, workers, progress)
            synthesis = synthesize(args.problem, kappas[0], "circle", replace(grid, n_theta=401, n_omega=301), horizon)
    stem = out / failure_map.name(fmap)
    with plotting.style():
        figure = draw_sweep(fmap) if args.sweep is not None else draw_grid(fmap, synthesis)
        files = [failure_map.save(fmap, stem.with_name(stem.name + ".npz"))] + plotting.save(figure, stem, chosen)
    result = dict(failure_map.summary(fmap), files=[str(f) for f in files])
    if args.json:
        print_json(result)
    else:
        print(printable(f"{result['method']}, {args.problem}: {', '.join(f'{k} {v}' for k, v in result['outcomes'].items())} "
                        f"cells in {fmap.time_s:.0f} s; {', '.join(result['files'])}"))
        for reason in result["reasons"]:
            print(f"  {printable(reason)}")
    return 0
