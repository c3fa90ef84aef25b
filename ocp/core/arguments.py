"""The pieces every command of the command line shares: the strict parser, the flags made from a
registry of settings, the window of a phase-plane map, and the checks of paths before any work.

Each value is read by one strict function per type (`ocp.core.errors.finite`, `integer`, and the
checks here): a bad value is an `InputError` with one line (exit 2), a folder that cannot be written
a `Fault` (exit 1), both raised before anything is computed.
"""

import argparse
import errno
import os
import re
import sys
from pathlib import Path

from .errors import Fault, InputError, finite, integer, short

#: --jobs: local worker processes
JOBS = (1, 64)


class Parser(argparse.ArgumentParser):
    """argparse with a usage error as one line (InputError, exit 2), no prefix matching of long
    options (`--kap 2` is an error, not --kappa), and negative numbers in e-notation (-1e-3) read
    as numbers, not options. `arguments(parser)`, if given, adds the arguments when the parser is
    first used (parsing, help): a command's flags made from a registry (ocp.direct) are then built
    only for that command, and `ocp --help` imports none of them."""

    def __init__(self, *args, arguments=None, **kwargs):
        kwargs["allow_abbrev"] = False
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")
        self._arguments = arguments

    def complete(self):
        """The parser with its arguments added (once)."""
        if self._arguments is not None:
            add, self._arguments = self._arguments, None
            add(self)
        return self

    def parse_known_args(self, args=None, namespace=None):
        return super(Parser, self.complete()).parse_known_args(args, namespace)

    def format_usage(self):
        return super(Parser, self.complete()).format_usage()

    def format_help(self):
        return super(Parser, self.complete()).format_help()

    def error(self, message):
        raise InputError(f"{self.prog}: {message}")

    def _print_message(self, message, file=None):
        """Help and usage written, a failed write not ignored (argparse's own swallows OSError, so
        `ocp --help > /dev/full` would exit 0)."""
        if message:
            (file or sys.stdout).write(message)


def _help(text):
    """Help text as argparse takes it (a % would be read as a format)."""
    return text.replace("%", "%%")


def add_settings(group, settings, defaults=None, notes=None):
    """A `--NAME` flag per setting of `settings` ({name: Setting}, ocp.direct.base), its help made
    from the declaration ("intervals, an integer from 2 to 5000, default 100") with `defaults`
    ({name: value}) in place of the declared ones and `notes` ({name: text}) appended."""
    for name, setting in settings.items():
        default = (defaults or {}).get(name, setting.default)
        note = (notes or {}).get(name)
        group.add_argument(f"--{name}", metavar=name.upper(),
                           help=_help(f"{setting.help}, {setting.accepted()}, default {default:g}" if setting.kind is not str
                                      else f"{setting.help}, {setting.accepted()}, default {default}")
                           + (f" ({_help(note)})" if note else ""))


def given_settings(args, settings):
    """{name: value} of the settings given on the command line, each parsed by its declaration."""
    return {name: setting.parse(getattr(args, name)) for name, setting in settings.items()
            if getattr(args, name) is not None}


def jobs(text):
    """--jobs: local worker processes, an integer from JOBS[0] to JOBS[1]."""
    return integer("jobs", text, f"an integer from {JOBS[0]} to {JOBS[1]} (local worker processes)", *JOBS)


def _nonempty(flag, text):
    if not text or not text.strip() or "\0" in text:
        raise InputError(f"{flag} {short(text)} is not a path; {flag} accepts a non-empty path")
    return Path(text)


def _checked(check):
    """A path check whose OSError (a name too long, a loop of links; a folder not searchable) is
    one line: InputError for the path's fault, Fault for the environment's."""
    def run(flag, text):
        try:
            return check(flag, text)
        except OSError as err:
            kind = InputError if err.errno in (errno.ENAMETOOLONG, errno.ELOOP, errno.ENOTDIR) else Fault
            raise kind(f"{flag} {short(text)}: {err.strerror}") from None
    run.__doc__ = check.__doc__
    return run


def _writable_parent(flag, path):
    """The nearest existing ancestor of `path` is a folder we may write in (else a Fault, as the
    failed mkdir would be)."""
    parent = path.absolute().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise Fault(f"{flag} {str(path)!r}: cannot be made, {str(parent)!r} is a file, not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise Fault(f"{flag} {str(path)!r}: cannot write in {str(parent)!r} (permission denied)")


def _output(flag, text, folder):
    """The path of `flag` checked before any work: non-empty (else InputError); a folder (`folder`)
    or a file as asked, that can be written or made (else Fault, as the failed write would be)."""
    path = _nonempty(flag, text)
    if path.exists():
        if path.is_dir() != folder:
            raise Fault(f"{flag} {text!r} is a {'file, not a folder' if folder else 'folder, not a file'}")
        if not os.access(path, os.W_OK | (os.X_OK if folder else os.R_OK)):
            raise Fault(f"{flag} {text!r}: cannot write {'in this folder' if folder else 'this file'} (permission denied)")
    else:
        _writable_parent(flag, path)
    return path


@_checked
def output_folder(flag, text):
    """The folder of `flag` (e.g. --out), made when the first file is written (`_output`)."""
    return _output(flag, text, folder=True)


@_checked
def output_file(flag, text):
    """The file of `flag` (e.g. --store), appended to or created (`_output`)."""
    return _output(flag, text, folder=False)


@_checked
def input_file(flag, text):
    """A file read (it may be absent where the command says so): a non-empty path, not a folder."""
    path = _nonempty(flag, text)
    if path.is_dir():
        raise InputError(f"{flag} {short(text)} is a folder, not a file")
    return path


def problem_kappas(args):
    """The kappas of --kappa (each in the accepted range), the problem checked."""
    from .problem import KAPPA_RANGE, KINDS

    if args.problem not in KINDS:
        raise InputError(f"unknown problem {short(args.problem)}; accepted: {', '.join(KINDS)}")
    return [finite("kappa", k, f"numbers from {KAPPA_RANGE[0]:g} to {KAPPA_RANGE[1]:g}", *KAPPA_RANGE) for k in args.kappa]


def formats(text):
    """The figure formats of a comma-separated --format."""
    from . import plotting

    chosen = tuple(f.strip() for f in text.split(",") if f.strip())
    if not chosen or set(chosen) - set(plotting.FORMATS):
        raise InputError(f"format {short(text)}: accepted {', '.join(plotting.FORMATS)} (comma separated)")
    return chosen


def add_window(p, grid, what):
    """--window, --grid (default `grid`, of `what`) and --horizon of a map of the phase plane."""
    p.add_argument("--window", nargs=4, metavar=("THETA_LO", "THETA_HI", "OMEGA_LO", "OMEGA_HI"),
                   default=["-3.141592653589793", "3.141592653589793", "-3", "3"], help="default [-pi, pi] x [-3, 3]")
    p.add_argument("--grid", nargs=2, metavar=("N_THETA", "N_OMEGA"), default=[str(g) for g in grid],
                   help=f"{what}, default {grid[0]} {grid[1]}")
    p.add_argument("--horizon", default="12", help="longest time-to-go of the synthesis drawn, default 12")


def window(args, low, high):
    """((theta_lo, theta_hi, omega_lo, omega_hi, n_theta, n_omega) of --window and --grid, each
    count from `low` to `high`; --horizon), checked: the fields of ocp.synthesis.field.Window."""
    from .problem import OMEGA_LIMIT, THETA_LIMIT

    accepted = f"four numbers, |theta| <= {THETA_LIMIT:g}, |omega| <= {OMEGA_LIMIT:g}"
    lo_t, hi_t = (finite("window", v, accepted, -THETA_LIMIT, THETA_LIMIT) for v in args.window[:2])
    lo_w, hi_w = (finite("window", v, accepted, -OMEGA_LIMIT, OMEGA_LIMIT) for v in args.window[2:])
    if not (lo_t < hi_t and lo_w < hi_w):
        raise InputError(f"window: THETA_LO < THETA_HI and OMEGA_LO < OMEGA_HI; accepted {accepted}")
    grid = [integer("grid", g, f"two integers from {low} to {high}", low, high) for g in args.grid]
    return ((lo_t, hi_t, lo_w, hi_w, *grid),
            finite("horizon", args.horizon, "a number of time units from 0.1 to 60", 0.1, 60))
