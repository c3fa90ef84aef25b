"""`ocp.solve`: direct solution, then refinement and certificate of the best of competing structures.

    direct multiple shooting  ->  structure (signs, arc durations, branch)
    -> candidates: the structure found; one switch less (first or last arc dropped); one switch
       more (an arc of the opposite sign before or after); the other first sign; the structures
       of direct solves pinned to the neighbouring target branches k - 1 and k + 1, and of a
       direct solve started the other way round (its guess first moves against the first arc)
    -> each refined (`ocp.refine`) and re-simulated independently (`ocp.simulate.arcs`)
    -> the best verified candidate certified (`ocp.certificate`)
    -> the answer cross-checked against Finch's one- or two-switch formula where one applies.

A candidate whose arc collapses to zero length is recorded as such; failures stay in the list.
"Best of K candidate structures" is what the result claims; global optimality is never claimed.
"""

import time
from dataclasses import dataclass

import numpy as np

from . import analytic, direct, simulate
from .certificate import certify
from .problems import Problem
from .transcription import MultipleShooting
from .refine import refine, with_error_estimate

#: a refined candidate is verified when its independent re-simulation lands this close
CANDIDATE_MISS_TOL = 1e-8
#: candidates whose T differ by less than this (relative) are equally good
TIE = 1e-9


@dataclass(frozen=True)
class Candidate:
    label: str
    signs: tuple
    branch: int
    status: str               # "extremal", "no extremal: ...", "misses ...", "duplicate of ..."
    T: float | None
    refined: object = None
    resim_miss: float | None = None

    @property
    def valid(self):
        return self.status == "extremal"

    def to_dict(self):
        return {"label": self.label, "signs": list(self.signs), "branch": self.branch, "status": self.status,
                "T": self.T, "resim_miss": self.resim_miss,
                "T_error": None if self.refined is None else self.refined.T_error}


def neighbours(signs, durations):
    """(label, signs, durations) of the structure found and its neighbours (see module doc)."""
    signs, d = tuple(signs), list(durations)
    T = sum(d)
    out = [("found", signs, d)]
    if len(signs) > 1:
        out.append(("one switch less (first arc dropped)", signs[1:], [d[0] + d[1]] + d[2:]))
        out.append(("one switch less (last arc dropped)", signs[:-1], d[:-2] + [d[-2] + d[-1]]))
    short = 0.05 * T
    out.append(("one switch more (arc before)", (-signs[0],) + signs, [short, max(d[0] - short, short)] + d[1:]))
    out.append(("one switch more (arc after)", signs + (-signs[-1],), d[:-1] + [max(d[-1] - short, short), short]))
    out.append(("other first sign", tuple(-s for s in signs), d))
    return out


def _durations(sol):
    return np.diff(np.concatenate([[0.0], sol.structure.switch_times, [sol.T_direct]]))


def _candidate(problem, label, signs, durations, branch):
    target = problem.target(branch)
    r = refine(problem.x0, problem.kappa, target, signs, durations)
    if not r.converged:
        return Candidate(label, tuple(signs), branch, f"no extremal: {r.status}", None, r)
    end = simulate.arcs(problem.x0, signs, r.durations, problem.kappa)[-1]
    miss = float(np.hypot(*(end - np.array(target))))
    status = "extremal" if miss <= CANDIDATE_MISS_TOL else f"misses the target by {miss:.1e} on re-simulation"
    return Candidate(label, tuple(signs), branch, status, r.T, r, miss)


def explore(problem, sol, method, solver, options):
    """Refined candidates around the direct solution `sol` (list, valid ones first by T); the
    neighbouring branches are reached by direct solves from the straight guess."""
    method = method or MultipleShooting()
    found = [(label, signs, d, sol.branch) for label, signs, d in neighbours(sol.structure.arc_signs, _durations(sol))]
    candidates = []
    solves = []
    if problem.branch is None:
        for k in (sol.branch - 1, sol.branch + 1):
            pinned = Problem(problem.kind, problem.kappa, problem.x0, k)
            solves.append((f"direct solve to branch {k}", pinned, direct.default_guesses(pinned, method.N)[0]))
    # the other way round: the default guess whose first motion opposes the first arc found
    straight, backswing, overswing = direct.default_guesses(problem, method.N)
    towards = sol.structure.first_u * (straight.theta[-1] - straight.theta[0]) > 0
    solves.append(("direct solve started the other way round", problem, backswing if towards else overswing))
    for label, pinned, guess in solves:
        other = direct.solve(pinned, method, solver, options, guess)
        k = other.branch
        if other.success:
            found.append((label, other.structure.arc_signs, _durations(other), k))
        else:
            candidates.append(Candidate(label, other.structure.arc_signs, k,
                                        f"no extremal: the direct solve failed ({other.status})", None))
    for label, signs, d, branch in found:
        c = _candidate(problem, label, signs, d, branch)
        twin = next((o for o in candidates if o.valid and c.valid and o.signs == c.signs and o.branch == c.branch
                     and abs(o.T - c.T) <= TIE * max(1.0, o.T)), None)
        if twin is not None:
            c = Candidate(c.label, c.signs, c.branch, f"duplicate of '{twin.label}'", c.T, c.refined, c.resim_miss)
        candidates.append(c)
    ranked = sorted(candidates, key=lambda c: (not c.valid, c.T if c.T is not None else np.inf))
    if ranked[0].valid:
        # equal times (a symmetric start: mirror images) keep the branch the direct solve reached
        tie = [c for c in ranked if c.valid and c.T - ranked[0].T <= TIE * max(1.0, ranked[0].T)]
        first = min(tie, key=lambda c: (c.branch != sol.branch, ranked.index(c)))
        ranked.remove(first)
        ranked.insert(0, first)
    return ranked


def solve(problem, method=None, solver="ipopt", options=None, guess=None, miss_tol=direct.MISS_TOL,
          refine=True):
    """The minimum-time solution of `problem`: `ocp.direct.solve` (same arguments), then, when
    `refine` and the direct solve succeeded, the candidates of `explore`, the best refined and
    certified. A given `guess` whose direct solve fails is followed by the default guesses. A
    direct solve that converged but whose control misses the target is refined all the same: the
    result succeeds when a refined candidate is verified (`direct_success` keeps the direct verdict).
    Returns the direct `Solution` with `refined`, `certificate` and `candidates` set."""
    start = time.perf_counter()
    sol = direct.solve(problem, method, solver, options, guess, miss_tol)
    if refine and not sol.success and guess is not None:
        # the given guess failed: the default family is the next start (all starts stay recorded)
        fallback = direct.solve(problem, method, solver, options, None, miss_tol)
        fallback.starts = sol.starts + fallback.starts
        fallback.solve_time_s += sol.solve_time_s
        sol = fallback
    if not refine or not sol.solver_success:
        return _finished(sol, start)
    refine_start = time.perf_counter()
    sol.candidates = explore(problem, sol, method, solver, options)
    best = sol.candidates[0]
    if best.valid:
        x0 = np.asarray(problem.x0, float)
        sol.refined = with_error_estimate(best.refined, x0, problem.kappa, problem.target(best.branch))
        sol.refined_branch = best.branch
        sol.refined_resim_miss = best.resim_miss
        if not sol.success:     # the direct control missed; its structure, refined, does not
            sol.success = True
            sol.status = (f"refined answer verified (re-simulated miss {best.resim_miss:.0e}); "
                          f"the direct solve: {sol.status}")
        sol.certificate = certify(sol.refined, x0, problem.kappa)
    sol.refine_time_s = time.perf_counter() - refine_start
    return _finished(sol, start)


def _finished(sol, start):
    """`sol` with its cross-check against the analytic formula of its structure, where one applies
    (`ocp.analytic.crosscheck`), and its total time."""
    if sol.success:
        sol.crosscheck = analytic.crosscheck(sol, sol.answer_branch)
    sol.total_time_s = time.perf_counter() - start
    return sol
