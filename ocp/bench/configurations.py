"""Solver configurations of the bench, declared once: "default" (no options: CasADi's defaults under
ocp's quiet ones, `ocp.direct.nlp._solver_options`) and "fair", what a user of that solver would
choose with this CasADi wheel (checked by `casadi.has_conic` / `has_linsol`: qpOASES, qrqp, OSQP,
HPIPM... ship; HSL's MA27 and MA57 do not; MUMPS, CasADi's ldl and qr do).

Every fair configuration asks for the same convergence tolerance, TOL = 1e-8 (IPOPT's default,
the one the direct error bound of `ocp.direct.solve` was measured with), in each solver's own
words: IPOPT's and Bonmin's `tol` (scaled KKT error), fatrop's `tol`, the SQP methods' primal and
dual infeasibility `tol_pr`, `tol_du`, blockSQP's `opttol` and `nlinfeastol`.

A method row names its configuration (`Method.configuration`); the options applied are the
configuration's with the row's own `options` over them (`options`), and both are stored.
"""

from ..core.errors import InputError

TOL = 1e-8
DEFAULT = "default"
#: solver -> (options, why a user of that solver would choose them)
FAIR = {
    "ipopt": ({"ipopt.tol": TOL, "ipopt.linear_solver": "mumps"},
              "MUMPS: the linear solver the wheel ships (HSL's MA27/MA57 are absent); tol its own default"),
    "fatrop": ({"fatrop.tol": TOL}, "fatrop's own stage structure detection (ocp's default) and the common tolerance"),
    "bonmin": ({"bonmin.tol": TOL}, "no integer variables: Bonmin's NLP solver (IPOPT with MUMPS) at the common tolerance"),
    "sqpmethod": ({"qpsol": "qrqp", "hessian_approximation": "exact", "convexify_strategy": "regularize",
                   "tol_pr": TOL, "tol_du": TOL},
                  "exact Hessian regularised to be positive definite, so that the sparse active-set QP (qrqp) "
                  "always has a solution"),
    "feasiblesqpmethod": ({"qpsol": "qrqp", "hessian_approximation": "exact", "convexify_strategy": "regularize",
                           "tol_pr": TOL, "tol_du": TOL},
                          "as sqpmethod; its feasible start cannot be given: it is a transfer that reaches the "
                          "target, i.e. an answer of the problem"),
    "blocksqp": ({"linsol": "ldl", "schur": False, "restore_feas": False, "opttol": TOL, "nlinfeastol": TOL},
                 "MA27 is absent: CasADi's ldl, with qpOASES's dense QP (its Schur-complement QP needs a pivoting "
                 "factorisation, ldl has none) and no restoration phase (it builds a solver of its own on MA27)"),
}
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
