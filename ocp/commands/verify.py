"""`ocp verify`: every published value beside the suite's computation of it (`ocp.papers.verify`)."""

import sys

from ..core.errors import InputError, short


def add_commands(sub):
    sub.add_parser("verify", help="every published value beside the suite's computation of it", arguments=add_arguments)


def add_arguments(p):
    from ..papers import references

    p.add_argument("--paper", help=f"only this paper, one of: {', '.join(references.papers())}")
    p.add_argument("--json", action="store_true", help="one JSON array, a row per value")
    p.set_defaults(run=run)


def run(args):
    from ..core.output import print_json
    from ..papers import references, verify

    papers = references.papers()
    if args.paper is not None and args.paper not in papers:
        raise InputError(f"unknown paper {short(args.paper)}; accepted: {', '.join(papers)}")
    table = verify.rows(args.paper, progress=sys.stderr)
    if args.json:
        print_json(verify.as_dicts(table))
    else:
        print(verify.format_table(table))
    return 0 if all(r.verdict != "disagrees" for r in table) else 1
