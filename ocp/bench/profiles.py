"""The mathematics of the performance profiles (Dolan and More 2002), apart from their drawing
(`ocp.bench.report.profile_chart`).

For a cost c(p, s) of family s on case p, the ratio r(p, s) = c(p, s) / min over s' of c(p, s'),
and the profile rho_s(tau) = the share of cases with r(p, s) <= tau: rho_s(1) is how often s is
the best, rho_s(tau -> inf) how often it gets there at all. Both costs are relative to the best
family on the case, so the machine's speed cancels:

    time profile        c = the least solver time (`Measurement.solver_time_s`: build and NLP
                        solves, not the suite's checking) of a run of s with the optimal structure and
                        |T - T_ref| <= eps (any N), one panel per accuracy target eps (default
                        1e-2, 3e-3, 1e-3: the range the direct methods reach at N <= 100; below it
                        only the search remains, and the profile degenerates to it)
    accuracy profile    c = the least |T - T_ref| of a run of s with the optimal structure within a
                        time budget beta * t_min(p), t_min(p) the fastest such run of any family
                        on the case (the time to reach an answer, relative to the fastest method),
                        one panel per relative budget beta (default 2, 10); an error below the
                        reference's own accuracy counts as that accuracy

A cost of zero (a time below the clock's resolution) counts as the least positive one, so that no
ratio divides by zero. Every case is counted: one that no family gets through is a ratio of inf
for every family (it caps every curve below 1; `unreached` counts them). A suite that is not a full
product (`ocp.bench.suite`, groups) profiles each family over the cases it ran, against the best of
the families that ran each case.
"""

import math
from collections import defaultdict

from .outcomes import GOOD

#: the time profile's accuracy targets and the accuracy profile's relative time budgets (module doc)
ACCURACIES = (1e-2, 3e-3, 1e-3)
BUDGETS = (2.0, 10.0)
#: the least cost: a time or an error below it is not resolved
TINY = 1e-16


def error(r):
    """|T - T_ref| of a run, never below the reference's own accuracy (a smaller one is not resolved)."""
    return max(abs(r.T_minus_ref), r.T_ref_error or 0.0, TINY)


def profile_costs(records, accuracies=ACCURACIES, budgets=BUDGETS):
    """The costs of the two profiles (module doc): {("time", eps): {family: {case: cost}}} and
    {("error", beta): {family: {case: cost}}} over the cases each family ran, inf where it does
    not get there."""
    cases = list(dict.fromkeys(r.case for r in records))
    families = list(dict.fromkeys(r.family for r in records))
    ran = defaultdict(set)
    for r in records:
        ran[r.family].add(r.case)
    good = defaultdict(list)
    for r in records:
        if r.outcome in GOOD and r.T_minus_ref is not None:
            good[(r.family, r.case)].append(r)
    fastest = {c: min((r.solver_time_s for f in families for r in good[(f, c)]), default=math.inf) for c in cases}
    costs = {}
    for eps in accuracies:
        costs[("time", eps)] = {f: {c: min((r.solver_time_s for r in good[(f, c)] if error(r) <= eps),
                                           default=math.inf) for c in cases if c in ran[f]} for f in families}
    for beta in budgets:
        costs[("error", beta)] = {f: {c: min((error(r) for r in good[(f, c)]
                                              if r.solver_time_s <= beta * fastest[c]), default=math.inf)
                                      for c in cases if c in ran[f]} for f in families}
    return costs


def _cases(costs):
    return list(dict.fromkeys(c for by_case in costs.values() for c in by_case))


def performance_profile(costs):
    """{family: sorted ratios cost / best cost over the cases it ran} (Dolan and More 2002) of one
    cost table {family: {case: cost}}, the best among the families that ran the case; inf where the
    family failed, and for every family on a case no family gets through."""
    ratios = {f: [] for f in costs}
    for case in _cases(costs):
        here = [f for f in costs if case in costs[f]]
        best = min(costs[f][case] for f in here)
        for f in here:
            c = costs[f][case]
            ratios[f].append(max(c, TINY) / max(best, TINY) if math.isfinite(c) else math.inf)
    return {f: sorted(r) for f, r in ratios.items()}


def unreached(costs):
    """The number of cases of one cost table {family: {case: cost}} that no family gets through."""
    return sum(not any(math.isfinite(by_case.get(c, math.inf)) for by_case in costs.values()) for c in _cases(costs))
