"""`ocp figures`: the papers' figures from the suite's own computations, and the benchmark charts
(`ocp.figures.write`)."""

import argparse
import sys

from ..core.arguments import formats, input_file, output_folder


def add_commands(sub):
    sub.add_parser("figures", help="the papers' figures from the suite's own computations, and the benchmark charts",
                   arguments=add_arguments, formatter_class=argparse.RawDescriptionHelpFormatter)


def add_arguments(p):
    from ..figures import listing

    p.epilog = listing()
    p.add_argument("--out", default="figures", help="folder for the files, default ./figures")
    p.add_argument("--only", action="append", metavar="NAME",
                   help="only this figure (repeatable; a wrong name lists them all)")
    p.add_argument("--format", default="png,pdf", help="comma separated: png, pdf, svg; default png,pdf")
    p.add_argument("--store", default="ocp-bench-quick.sqlite",
                   help="the results store of `ocp bench` for the benchmark charts (skipped if absent), "
                        "default ./ocp-bench-quick.sqlite")
    p.set_defaults(run=run)


def run(args):
    from ..core.output import printable, solver_output
    from ..figures import write

    chosen, store, out = formats(args.format), input_file("--store", args.store), output_folder("--out", args.out)
    with solver_output("stderr"):
        written = write(out, args.only, chosen, store, progress=sys.stderr)
    for name, paths in written.items():
        print(printable(f"{name}: {paths}" if isinstance(paths, str) else f"{name}: {', '.join(map(str, paths))}"))
    return 0
