"""The reference of a case: the optimum of its problem from `ocp.solve`'s complete search of
extremals (independent of every direct method scored), scanned to (1 + REFERENCE_MARGIN) times the
optimum so that slower direct answers are classified; T replaced by Finch's formula where one
applies to its structure and agrees within AGREE; read from the reference set (`ocp.reference`,
its T and switch times refined at 40 digits) where the set holds the problem, not searched again."""

import time

from ..core.errors import last_line
from ..reference import lookup
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


def _stored(e):
    return Extremal(signs=tuple(int(s) for s in e["arc_signs"]), branch=e["branch"], T=float(e["T"]))


def from_the_set(problem, key):
    """The Reference of `problem` from the reference set (its refined T and switch times, every
    extremal before the set's horizon), or None where the set lacks the problem."""
    row = lookup(problem)
    if row is None:
        return None
    o = row["optimum"]
    return Reference(problem=key, T=float(o["refined"]["T"]), T_error=float(o["refined"]["T_error"]),
                     source=f"the reference set ({row['id']}: complete search, refined at "
                            f"{o['refined']['digits'][-1]} digits)",
                     arc_signs=tuple(int(s) for s in o["arc_signs"]), branch=o["branch"], optimal=True,
                     switch_times=tuple(float(t) for t in o["refined"]["switch_times"]),
                     ties=tuple(map(_stored, row["ties"])), extremals=tuple(map(_stored, row["extremals"])),
                     horizon=float(row["coverage"]["horizon"]))


def reference(case):
    """The Reference of case.problem(): from the reference set where it holds the problem, else the
    search's optimum, its ties and every extremal found; `source` says where T comes from (or why
    there is none)."""
    problem = case.problem()
    stored = from_the_set(problem, case.problem_key)
    if stored is not None:
        return stored
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
