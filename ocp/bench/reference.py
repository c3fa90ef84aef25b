"""The reference of a case: the optimum of its problem from `ocp.solve`'s complete search of
extremals (independent of every direct method scored), scanned to (1 + REFERENCE_MARGIN) times the
optimum so that slower direct answers are classified; T replaced by Finch's formula where one
applies to its structure and agrees within AGREE."""

import time

from ..core.errors import last_line
from ..solving import solve
from .row import Extremal, Reference

#: a formula and the search agree when their T differ by less than this
AGREE = 1e-9
#: the reference scans to (1 + REFERENCE_MARGIN) times the optimum, to classify slower direct answers
REFERENCE_MARGIN = 1.0


def _number(x):
    return None if x is None else float(x)


def _extremal(e):
    return Extremal(signs=tuple(int(s) for s in e.signs), branch=None if e.branch is None else int(e.branch),
                    T=float(e.T))


def reference(case):
    """The Reference of case.problem(): the search's optimum, its ties and every extremal found;
    `source` says where T comes from (or why there is none)."""
    problem = case.problem()
    start = time.perf_counter()
    try:
        sol = solve(problem, margin=REFERENCE_MARGIN)
    except Exception as err:        # noqa: BLE001  (no reference is a recorded fact, not a crash)
        return Reference(problem=case.problem_key, T=None, T_error=None, time_s=time.perf_counter() - start,
                         source=f"none: the search raised {type(err).__name__}: {last_line(err)}")
    if not sol.success or sol.answer is None:
        return Reference(problem=case.problem_key, T=None, T_error=None, source=f"none: {sol.message}",
                         time_s=time.perf_counter() - start)
    a, x = sol.answer, sol.crosscheck
    found = dict(T=float(a.T), T_error=_number(a.T_error), switch_times=tuple(map(float, a.switch_times)),
                 source="complete search of extremals" + ("" if sol.optimal else " (NOT proved optimal: unresolved)"))
    if x is not None and abs(x.T) < AGREE:
        found = dict(T=float(x.analytic.T), T_error=_number(x.analytic.error),
                     switch_times=tuple(map(float, x.analytic.switch_times)),
                     source=f"{x.formula}, agreeing with the complete search to {abs(x.T):.0e}")
    return Reference(problem=case.problem_key, arc_signs=tuple(int(s) for s in a.signs),
                     branch=None if a.branch is None else int(a.branch), optimal=bool(sol.optimal),
                     ties=tuple(map(_extremal, sol.ties)), extremals=tuple(map(_extremal, sol.extremals)),
                     horizon=float(sol.coverage.horizon), time_s=time.perf_counter() - start, **found)
