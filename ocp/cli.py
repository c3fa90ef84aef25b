"""The `ocp` command line: one line per common job, `--json` for scripts.

Bad input prints one line (what was wrong, what is accepted) and exits 2; a solve that fails
exits 1 (with `--json`, still one object with "success": false).
"""

import argparse
import json
import math
import sys

from .errors import InputError


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line and exit status 2."""

    def error(self, message):
        raise InputError(f"{self.prog}: {message}")


def _print_json(obj):
    print(json.dumps(obj, indent=2, allow_nan=False, default=_json_default))


def _json_default(obj):
    if hasattr(obj, "tolist"):
        return obj.tolist()
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


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


def main(argv=None):
    parser = _Parser(prog="ocp", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    _add_verify(sub)
    try:
        args = parser.parse_args(argv)
        return args.run(args)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
