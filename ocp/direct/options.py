"""NLP solver options as data: what may pass to `casadi.nlpsol` from a file or a command line.

An option is accepted only if it is on the allow-list of its solver (`ocp.direct.solvers`: the
options common to every solver and the solver's own, each typed: an integer option takes an
integer, a number is finite and in range, a plugin name is one CasADi ships and can load from its
folder, a nested table has typed fields of its own). Everything else is refused with one line
naming the option, why, and what is accepted: no option on a list names a file, a library, a
program or a callback. From the command line, `--allow-unsafe-options` (`trusted`) lets any option
pass untouched; a suite file never can.
"""

from ..core.errors import InputError, short
from . import solvers


def checked(options, trusted=False, where="options", solver="ipopt"):
    """`options` for `solver` as a plain dict of checked values, or InputError (the solver's name
    is checked in any case; its options only unless `trusted`)."""
    entry = solvers.solver(solver)
    if options is None:
        return {}
    if not isinstance(options, dict) or not all(isinstance(k, str) for k in options):
        raise InputError(f"{where} = {short(options)} is refused: not a table of NLP solver options")
    if trusted:
        return dict(options)
    try:
        return solvers.check_table(entry.fields, options, "")
    except InputError as err:
        raise InputError(f"{where}: {err} (solver {solver}; on the command line only, --allow-unsafe-options "
                         f"passes any option)") from None
