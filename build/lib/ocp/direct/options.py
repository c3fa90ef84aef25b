"""NLP solver options as data: what may pass to `casadi.nlpsol` from a file or a command line.

Options pass to the solver untouched, except those that execute a program or read or write a
file: a JIT compiler and its command (`jit`, `compiler`, `jit_options`), output and option files
(`ipopt.output_file`, `ipopt.option_file_name`, ...), dumps (`dump`, `dump_dir`, ...), logs and
anything else with a path or a command in its name. They are refused from suite files always, and
from the command line unless `--allow-unsafe-options` is given.
"""

import re

from ..core.errors import InputError

#: a key (or the part after its last dot) matching this can execute or touch a file
UNSAFE = re.compile(r"jit|compiler|file|path|dir|command|cmd|exec|dump|log|out_?put|shell|plugin_libs", re.IGNORECASE)


def unsafe_keys(options, prefix=""):
    """The keys of `options` (nested tables included) that could run a program or touch a file."""
    found = []
    for key, value in options.items():
        name = f"{prefix}{key}"
        if UNSAFE.search(str(key).rsplit(".", 1)[-1]):
            found.append(name)
        if isinstance(value, dict):
            found += unsafe_keys(value, name + ".")
    return found


def checked(options, trusted=False, where="options"):
    """`options` as a plain dict, or InputError naming the unsafe keys (unless `trusted`)."""
    if options is None:
        return {}
    if not isinstance(options, dict) or not all(isinstance(k, str) for k in options):
        raise InputError(f"{where} must be a table of NLP solver options, not {type(options).__name__}")
    bad = unsafe_keys(options)
    if bad and not trusted:
        raise InputError(f"{where}: {', '.join(bad)} can run a program or read or write a file and is refused "
                         f"(from the command line, --allow-unsafe-options permits it)")
    return dict(options)
