"""Solver configurations of the bench: "default" (no options: CasADi's defaults under ocp's quiet
ones, `ocp.direct.solvers.quiet_options`) and "fair", what a user of that solver would choose with
this CasADi wheel, declared with the solver in `ocp.direct.solvers.SOLVERS` (qpOASES, qrqp, OSQP,
HPIPM... ship; HSL's MA27 and MA57 do not; MUMPS, CasADi's ldl and qr do).

Every fair configuration asks for the same convergence tolerance, TOL = 1e-8 (IPOPT's default,
the one the direct error bound of `ocp.direct.solve` was measured with), in each solver's own
words: IPOPT's and Bonmin's `tol` (scaled KKT error), fatrop's `tol`, the SQP methods' primal and
dual infeasibility `tol_pr`, `tol_du`, blockSQP's `opttol` and `nlinfeastol`.

A method row names its configuration (`Method.configuration`); the options applied are the
configuration's with the row's own `options` over them (`options`), and both are stored.
"""

from ..core.errors import InputError
from ..direct.solvers import SOLVERS

DEFAULT = "default"
#: solver -> (options, why a user of that solver would choose them): the fair entries of the registry
FAIR = {name: (entry.fair, entry.why) for name, entry in SOLVERS.items() if entry.fair is not None}
CONFIGURATIONS = (DEFAULT, "fair")


def options(solver, configuration):
    """The nlpsol options of `configuration` for `solver` (InputError where it has none)."""
    if configuration == DEFAULT:
        return {}
    if configuration != "fair":
        raise InputError(f"configuration = {configuration!r}; accepted: {', '.join(CONFIGURATIONS)}")
    if solver not in FAIR:
        raise InputError(f"no fair configuration for {solver!r}; accepted: {', '.join(FAIR)} (or configuration = "
                         f"\"default\")")
    return dict(FAIR[solver][0])
