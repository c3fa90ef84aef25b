"""`ocp bench` and `ocp report`: the command-line side of the benchmark suite.

    ocp bench [SUITE] [--store PATH] [--jobs N | --scheduler ADDRESS] [--shard I/N] [--yes] [--json]
    ocp merge OUT STORE [STORE ...] [--json]
    ocp report STORE [--out DIR] [--budget B1,B2] [--accuracy E1,E2] [--format png,pdf] [--json]

`ocp bench` runs a suite (default "quick") into a SQLite store, resuming what is already there,
with a progress bar on stderr and a summary table at the end (a suite of more than
`suite.CONFIRM_RUNS` solves needs --yes); with --shard I/N only the I-th of N disjoint slices of
its pairs (`runner.shard`), and `ocp merge` joins the shards' stores into one (`store.merge`);
`ocp report` draws tables and charts from a store alone, opened read-only. docs/cluster.md: a suite
on a Dask cluster, a batch cluster, or split across machines.
"""

import re
import sys
import time

from ..core.arguments import input_file, output_file, output_folder
from ..core.errors import Fault, InputError, finite, integer, short

MAX_JOBS = 256
MAX_SHARDS = 100_000
SHARD = re.compile(r"([1-9][0-9]{0,5})/([1-9][0-9]{0,5})")
#: `ocp bench` asks for --yes above this many solves (pairs x repeats)
CONFIRM_RUNS = 5_000


def add_commands(sub):
    sub.add_parser("bench", help="run a benchmark suite (cases x methods) into a results store",
                   arguments=add_bench).set_defaults(run=run_bench)
    p = sub.add_parser("merge", help="join results stores (the shards of a suite) into one")
    p.add_argument("out", help="the merged SQLite results file (created, or added to)")
    p.add_argument("stores", nargs="+", metavar="store", help="a results file written by ocp bench")
    p.add_argument("--json", action="store_true", help="print one JSON object (what was added)")
    p.set_defaults(run=run_merge)
    p = sub.add_parser("report", help="tables and charts from a benchmark results store")
    p.add_argument("store", help="the SQLite results file written by ocp bench")
    p.add_argument("--out", help="folder for charts, summary.md, results.csv and results.json "
                                 "(default: STORE without .sqlite, plus -report)")
    p.add_argument("--budget", default="2,10", help="time budgets of the accuracy profile, multiples (>= 1) of the "
                                                    "fastest answer on each case, comma separated; default 2,10")
    p.add_argument("--accuracy", default="1e-2,3e-3,1e-3",
                   help="|T - T_ref| targets of the time profile, comma separated; default 1e-2,3e-3,1e-3")
    p.add_argument("--format", default="png", help="chart formats, comma separated (png, pdf, svg); default png")
    p.add_argument("--json", action="store_true", help="print the tables as one JSON object")
    p.set_defaults(run=run_report)


def add_bench(p):
    from ..core.parallel import ACCEPTED

    p.add_argument("suite", nargs="?", default="quick",
                   help="a suite name in ocp/bench/suites/ (quick, full) or a TOML file; default quick")
    p.add_argument("--store", help="the SQLite results file (default ocp-bench-SUITE.sqlite); "
                                   "pairs already in it are not run again")
    p.add_argument("--jobs", default="1", help="local worker processes, default 1")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help=f"run on the Dask distributed scheduler at ADDRESS instead: {ACCEPTED}")
    p.add_argument("--shard", metavar="I/N", help="run only the I-th of N disjoint slices of the suite's pairs "
                                                  "(join the stores with ocp merge); default store "
                                                  "ocp-bench-SUITE-shard-I-of-N.sqlite")
    p.add_argument("--yes", action="store_true",
                   help=f"run a suite of more than {CONFIRM_RUNS} solves (pairs x repeats)")
    p.add_argument("--json", action="store_true", help="print one JSON object (summary, environment)")


def run_bench(args):
    from . import report as report_module, runner, suite as suite_module
    from .environment import environment
    from .store import Store
    from ..core.output import print_json, printable, solver_output
    from ..core.parallel import executor

    suite = suite_module.load(args.suite)
    jobs = integer("jobs", args.jobs, f"an integer from 1 to {MAX_JOBS} (local worker processes)", 1, MAX_JOBS)
    part = shard_of(args.shard) if args.shard is not None else None
    pairs = len(runner.pairs_of(suite, part))
    solves = pairs * suite.repeats
    if solves > CONFIRM_RUNS and not args.yes:
        raise InputError(f"suite {suite.name}: {pairs} pairs x {suite.repeats} repeats = {solves} "
                         f"solves, more than {CONFIRM_RUNS}; add --yes to run it (it can be "
                         f"interrupted and resumed)")
    default = f"ocp-bench-{suite.name}" + ("" if part is None else f"-shard-{part[0]}-of-{part[1]}") + ".sqlite"
    store_path = output_file("--store", args.store) if args.store is not None else default
    start = time.perf_counter()
    store = None
    try:
        # the executor first: a scheduler that cannot be used is refused before the store is created
        with executor(jobs, args.scheduler) as (pool, workers, name), solver_output("stderr"):
            store = Store(store_path)                    # a suite's name stays in this folder
            shard = "" if part is None else f" (shard {part[0]}/{part[1]} of {len(suite.pairs())})"
            print(f"ocp bench: suite {suite.name}, {pairs} pairs{shard} x {suite.repeats} repeats, {name}; "
                  f"store {printable(store.path)}; recording the environment", file=sys.stderr,
                  flush=True)
            env = environment()
            result = runner.run(suite, store, pool, workers, name, env, part)
    except KeyboardInterrupt:
        print(f"interrupted: {_kept(store)}; the same command resumes where it stopped")
        return 130
    except Fault as err:
        if store is None:
            raise
        raise Fault(f"{err}; {_kept(store)}; the same command resumes where it stopped") from None
    keys = {(c.key, m.key) for c, m in result["pairs"]}
    records = [r for r in store.results() if (r.case, r.method) in keys]
    store.close()
    best = report_module.best_known(records)
    summary = {
        "suite": suite.name, "store": str(store.path), "session": result["session"], "executor": result["executor"],
        "shard": None if part is None else f"{part[0]}/{part[1]}",
        "pairs": pairs, "run_now": len(result["records"]), "resumed": result["resumed"],
        "claimed_elsewhere": result["claimed_elsewhere"],
        "notes": result["notes"], "elapsed_s": time.perf_counter() - start,
        "outcomes": report_module.outcome_counts(records), "methods": report_module.method_table(records, best),
        "failures": report_module.failure_table(records), "environment": env,
    }
    if args.json:
        print_json(summary)
        return 0
    for note in result["notes"]:
        print(f"note: {note}")
    print(f"suite {suite.name}: {summary['pairs']} runs ({summary['run_now']} now, {summary['resumed']} already "
          f"stored) in {summary['elapsed_s']:.0f} s, {result['executor']}; store {store.path}")
    print(printable(f"outcomes: {', '.join(f'{k} {v}' for k, v in summary['outcomes'].items())}") + "\n")
    print(report_module.markdown(summary["methods"]))
    print(f"charts and failure table: ocp report {store.path}")
    return 0


def shard_of(text):
    """(I, N) of --shard I/N, 1 <= I <= N <= MAX_SHARDS, or InputError."""
    match = SHARD.fullmatch(text)
    if not match or not int(match[1]) <= int(match[2]) <= MAX_SHARDS:
        raise InputError(f"--shard {short(text)} is not a shard; accepted: I/N with 1 <= I <= N <= {MAX_SHARDS} "
                         f"(the I-th of N disjoint slices of the pairs), e.g. 1/4")
    return int(match[1]), int(match[2])


def run_merge(args):
    from .store import merge
    from ..core.output import print_json

    out = output_file("out", args.out)
    stores = [input_file("store", s) for s in args.stores]
    missing = [str(s) for s in stores if not s.is_file()]
    if missing:
        raise InputError(f"no results store at {missing[0]}")
    added = merge(out, stores)
    if args.json:
        print_json(added)
        return 0
    print(f"merged {added['stores']} stores into {out}: {added['rows']} rows, {added['references']} references and "
          f"{added['sessions']} sessions added; {added['total']} rows in it")
    return 0


def _kept(store):
    """How many finished rows the store keeps (closing it), in words."""
    if store is None:
        return "no store was opened"
    try:
        rows = len(store.done())
    except Fault:
        rows = "the"
    store.close()
    return f"{rows} finished rows are kept in {store.path}"


def run_report(args):
    from . import report as report_module
    from ..core.output import print_json

    formats = tuple(f.strip() for f in args.format.split(",") if f.strip())
    bad = [f for f in formats if f not in ("png", "pdf", "svg")]
    if bad or not formats:
        raise InputError(f"format {args.format!r}: accepted png, pdf, svg (comma separated)")
    budget = [finite("budget", b, "numbers >= 1 (multiples of the fastest answer), comma separated", 1, 1e6)
              for b in args.budget.split(",")]
    accuracy = [finite("accuracy", a, "numbers > 0, comma separated", 1e-300, 1e300) for a in args.accuracy.split(",")]
    store = input_file("store", args.store)
    out = output_folder("--out", args.out) if args.out is not None else store.with_name(store.stem + "-report")
    tables = report_module.report(store, out, budget, accuracy, formats)
    if args.json:
        print_json(tables)
        return 0
    print(report_module.summary_markdown(tables))
    print("written: " + ", ".join(tables["files"]))
    return 0
