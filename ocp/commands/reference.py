"""`ocp reference` and `ocp score`: the command-line side of the reference set.

    ocp reference generate [--out DIR] [--jobs N] [--only ID ...]   compute what is missing (resumed)
    ocp reference show ID [--json]                                  one instance
    ocp score FILE [--instance ID] [--json]                         a solution from any tool, scored
"""

import sys

from ..core.arguments import input_file, jobs, output_folder
from ..core.errors import InputError
from ..core.heartbeat import heartbeat


def add_commands(sub):
    sub.add_parser("reference", help="the reference set: instances with certified global optima (reference/)",
                   arguments=add_reference_arguments)
    sub.add_parser("score", help="score a solution from any tool against its reference instance",
                   arguments=add_score_arguments)


def add_reference_arguments(p):
    actions = p.add_subparsers(dest="action", required=True, parser_class=type(p))
    g = actions.add_parser("generate", help="compute the instances not yet in the set (resumable, parallel)")
    g.add_argument("--out", help="the folder of instances.jsonl and index.csv (default: the set's own folder)")
    g.add_argument("--jobs", default="1", help="local worker processes, default 1")
    g.add_argument("--only", action="append", metavar="ID", help="only this instance (repeatable)")
    g.set_defaults(run=run_generate)
    s = actions.add_parser("show", help="one instance of the set")
    s.add_argument("id", help="an instance id (see reference/index.csv)")
    s.add_argument("--json", action="store_true", help="print its JSON row")
    s.set_defaults(run=run_show)


def add_score_arguments(p):
    p.add_argument("file", help="a bang-bang answer (JSON), a sampled control (CSV of t,u) or ocp's own JSON")
    p.add_argument("--instance", metavar="ID", help="the instance (needed for a CSV without an id line)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(run=run_score)


def run_generate(args):
    import concurrent.futures as cf

    from ..reference import data, generate, instances

    workers = jobs(args.jobs)
    wanted = instances.all_instances()
    if args.only:
        known = {i.id: i for i in wanted}
        unknown = [i for i in args.only if i not in known]
        if unknown:
            raise InputError(f"--only {unknown[0][:80]!r} is not an instance id; see reference/index.csv")
        wanted = [known[i] for i in dict.fromkeys(args.only)]
    out = output_folder("--out", args.out) if args.out is not None else data.folder()
    path = out / data.INSTANCES
    done = data.read(path)
    # the cheapest first (by the problem's rough time to the target), so that rows accumulate early
    todo = sorted((i for i in wanted if i.id not in done), key=lambda i: i.problem().time_estimate)
    print(f"{len(wanted) - len(todo)} of {len(wanted)} instances already in {path}; computing {len(todo)}",
          file=sys.stderr, flush=True)
    again = [r for r in done.values() if generate.stale(r)]
    if again:
        print(f"{len(again)} rows refined again (their refinement predates the current one)", file=sys.stderr)
    n = 0
    with cf.ProcessPoolExecutor(workers) as pool, heartbeat(sys.stderr, lambda: f"{n} of {len(todo)} done, "
                                                                                  f"{workers} worker(s) computing"):
        futures = {pool.submit(generate.refine_again, r): r for r in again}
        futures.update({pool.submit(generate.compute, i): i for i in todo})
        todo = again + todo
        for n, future in enumerate(cf.as_completed(futures), 1):
            row = future.result()
            data.append(path, row)
            print(f"[{n}/{len(todo)}] {row['id']}: {row['status']}"
                  f"{'' if row['status'] == 'solved' else ' (' + row['reason'] + ')'} "
                  f"in {row['provenance']['time_s']:.1f} s", file=sys.stderr, flush=True)
    rows = data.write_sorted(path, [i.id for i in instances.all_instances()], generate.relabelled)
    solved = sum(r["status"] == "solved" for r in rows)
    print(f"{solved} solved, {len(rows) - solved} skipped; {path} and {path.with_name(data.INDEX)} written")
    return 0


def run_show(args):
    from ..core.numbers import digits
    from ..core.output import print_json
    from ..reference import data

    row = data.instance(args.id)
    if args.json:
        print_json(row)
        return 0
    o = row["optimum"]
    print(f"{row['id']}: {row['kind']} on the {row['reading']}, kappa = {row['kappa']!r}, x0 = {row['x0']}")
    print(f"T = {o['refined']['T']} (error {o['refined']['T_error']}), arcs {o['arc_signs']}, branch {o['branch']}")
    for t, e in zip(o["refined"]["switch_times"], o["refined"]["switch_time_errors"]):
        print(f"  switch at t = {t} (error {e})")
    print(f"ties: {len(row['ties'])}; runner-up: "
          + ("none" if row["runner_up"] is None else f"T = {digits(row['runner_up']['T'], row['runner_up']['T_error'])} "
                                                     f"{row['runner_up']['arc_signs']} branch {row['runner_up']['branch']}"))
    print(f"tags: {', '.join(row['tags'])}")
    return 0


def run_score(args):
    from ..core.output import print_json
    from ..reference import score

    result = score.score(input_file("file", args.file), args.instance)
    if args.json:
        print_json(result.to_dict())
    else:
        print(result.summary())
    return 0
