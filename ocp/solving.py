"""`ocp.solve`: the minimum time of a problem, and how each method fares against it.

    [direct transcription]     if a method is given: its answer, verified by re-simulation
    complete extremal search   every extremal reaching the target set before the horizon
                               (`ocp.indirect.searching`); the least T is the answer, ties reported
    [on to the direct T]       if the direct answer (verified, or a discretisation result) is slower
                               than the search's horizon over (1 + margin) and no extremal found has
                               its structure: a scan on to (1 + margin) times its T, so that the
                               extremal it converged to is found and classified, cut after
                               CLASSIFY_FACTOR times the search's time (then beyond the horizon)
    verification and certificate  the answer's state and costate integrated again by CVODES, with
                               the costate of automatic differentiation: the miss at the target
                               and the first- and second-order conditions (`ocp.indirect.certificate`)
    cross-check                Finch's one- or two-switch formula, where one applies (the direct
                               answer's too, when it is the answer)
    classification             the direct answer against the search's (`ocp.result.DirectClass`)

With `search=False` the direct answer alone is returned (verified, or a discretisation result: status
DIRECT_DISCRETISATION): `optimal` is then unknown.
"""

import math
import threading
import time
import numpy as np

from .core.errors import InputError
from .core.output import QUIET_S
from .core.problem import Problem
from .indirect import certify, search as search_extremals
from .indirect.searching import HORIZON_BAND, MARGIN
from .result import Answer, DirectClass, SolveStatus, Solution

#: the answer's re-simulated miss must be below this (a refined extremal lands to ~1e-12), plus the
#: re-simulation's own error estimate (`Certificate.final_state_error`, which grows with the length)
VERIFY_TOL = 1e-8
#: the scan on to a slower direct answer's T runs at most this many times the search's own time, and at
#: least CLASSIFY_MIN_S seconds (within the time limit): cut there, the direct answer is beyond the horizon
CLASSIFY_FACTOR, CLASSIFY_MIN_S = 2.0, 2.0


def _tie(a, b):
    """Whether two extremals' times agree within their accuracy."""
    return abs(a.T - b.T) <= 10 * (a.T_error + b.T_error) + 8 * 2.2e-16 * max(a.T, b.T)


def _ranked(extremals):
    """(answer, ties, runner-up): among the optimal ties, the branch nearest k = 0 (then the larger
    k) is the answer."""
    if not extremals:
        return None, (), None
    best = extremals[0]
    optimal = [e for e in extremals if _tie(e, best)]
    answer = min(optimal, key=lambda e: (abs(e.branch), -e.branch))
    slower = [e for e in extremals if not _tie(e, best)]
    return answer, tuple(e for e in optimal if e is not answer), (slower[0] if slower else None)


def _crosscheck(problem, extremal):
    """`ocp.exact.finch.crosscheck`, imported only where a formula can apply (a start at rest on a
    multiple of pi)."""
    theta0, omega0 = problem.x0
    if omega0 != 0 or abs(theta0 / math.pi - round(theta0 / math.pi)) > 1e-9:
        return None
    from .exact import finch
    return finch.crosscheck(problem, extremal)


def classify(direct, answer, ties, extremals, horizon):
    """The DirectClass of a direct solution against the search's answer, its ties and the other
    extremals found before `horizon`; a discretisation result (`DirectStatus.DISCRETISATION`) is
    classified as a verified one, its optimum told apart (DISCRETISATION)."""
    from .direct import DirectStatus as status
    if direct.status == status.SOLVER_ERROR:
        return DirectClass.SOLVER_ERROR
    if direct.status == status.NOT_CONVERGED:
        return DirectClass.NOT_CONVERGED
    if direct.status == status.MISSES_TARGET:
        return DirectClass.MISSES_TARGET
    if not direct.structure.bang_bang:
        return DirectClass.CHATTERING
    same = lambda e: tuple(e.signs) == tuple(direct.structure.arc_signs) and e.branch == direct.branch
    if any(same(e) for e in (answer, *ties)):
        bound = direct.T_bound
        if bound is not None and abs(direct.T - answer.T) > bound:
            return DirectClass.INACCURATE
        return DirectClass.DISCRETISATION if direct.status == status.DISCRETISATION else DirectClass.OPTIMUM
    if any(same(e) for e in extremals):
        return DirectClass.LOCAL_OPTIMUM
    return DirectClass.BEYOND_HORIZON if direct.T > horizon else DirectClass.WRONG_STRUCTURE


def _on_to_direct(problem, direct, found, margin, budget, progress):
    """(extremals, reach, note) against which to classify a direct answer: the extremals found and
    the direct T up to which the classification holds, the complete scan's horizon over (1 + margin)
    (a discretised T is not exact). A bang-bang direct answer past that reach, of a structure (arc
    signs, branch) no extremal found has, is scanned on to: to (1 + margin) times its T, cut after
    `budget` seconds (then the search's extremals and those the cut scan found of other structures,
    and the search's reach)."""
    extremals, reach = found.arrivals, found.coverage.horizon / (1 + margin)
    structure = lambda e: (tuple(e.signs), e.branch)
    if not (direct is not None and direct.lands_on_target and math.isfinite(direct.T) and direct.T > reach
            and direct.structure.bang_bang and found.coverage.complete and budget > 0) \
            or (tuple(direct.structure.arc_signs), direct.branch) in {structure(e) for e in extremals}:
        return extremals, reach, None
    on = _search(problem, direct.T * (1 + margin) / (1 - HORIZON_BAND), margin, budget, progress)
    if on.coverage.complete:
        return (on.arrivals, on.coverage.horizon / (1 + margin),
                f"scanned on to {on.coverage.horizon:.4g} to classify the direct answer")
    seen = {structure(e) for e in extremals}
    extremals = tuple(sorted((*extremals, *(e for e in on.arrivals if structure(e) not in seen)), key=lambda e: e.T))
    return extremals, reach, (f"the scan on to the direct answer's T = {direct.T:.4g} was cut after {budget:.2g} s "
                              f"(at most {CLASSIFY_FACTOR:g} times the search's time, at least {CLASSIFY_MIN_S:g} s)")


def _search(problem, horizon, margin, time_limit, progress):
    """The search, its reports given to `progress` as lines from QUIET_S seconds on. Until its first
    report (which comes after its first integration, where the compiled kernels are loaded, or
    compiled, the first time after an install) a line every second from QUIET_S on says so."""
    if progress is None:
        return search_extremals(problem, horizon, margin, time_limit, None)
    begun, reported = time.perf_counter(), threading.Event()

    def lines(report):
        reported.set()
        if report.elapsed >= QUIET_S:
            progress(str(report))

    def meanwhile():
        wait = QUIET_S
        while not reported.wait(wait):
            progress(f"search {time.perf_counter() - begun:.0f} s: in its first integration (where the compiled "
                     f"Taylor kernels are loaded; compiled, the first time after an install, in about a minute)")
            wait = 1.0

    thread = threading.Thread(target=meanwhile, daemon=True)
    thread.start()
    try:
        return search_extremals(problem, horizon, margin, time_limit, lines)
    finally:
        reported.set()
        thread.join()


def solve(problem, method=None, solver="ipopt", options=None, guess=None, miss_tol=None,
          search=True, trusted=False, margin=MARGIN, time_limit=None, progress=None):
    """The minimum-time Solution of `problem` (see the module doc).

    method, solver, options, guess, miss_tol, trusted: the direct transcription (`ocp.direct.solve`),
    run only when `method` is given or `search` is False; the answer comes from the search unless
    `search` is False; it scans to (1 + margin) times the optimum at least (to classify a slower direct
    answer, on to (1 + margin) times its T: `_on_to_direct`).
    miss_tol None: `ocp.direct.MISS_TOL`. time_limit: seconds of search at most, then the best answer
    so far, not proven optimal (`ocp.indirect.search`): status STOPPED, or STOPPED_EMPTY if none was
    found. progress: None or a callable given a line of
    text about what runs (the direct solve's stage and iteration, the search's horizon and
    arrivals), every second once that stage has run QUIET_S seconds."""
    if not isinstance(problem, Problem):
        raise InputError(f"problem must be an ocp Problem (ocp.swing_up, ocp.damping), not {type(problem).__name__}")
    start = time.perf_counter()
    direct = None
    if method is not None or not search:
        from . import direct as direct_layer
        direct = direct_layer.solve(problem, method, solver, options, guess,
                                    direct_layer.MISS_TOL if miss_tol is None else miss_tol, trusted, progress)
    direct_time = time.perf_counter() - start
    if not search:
        status = SolveStatus.DIRECT_ONLY if direct.success else \
            SolveStatus.DIRECT_DISCRETISATION if direct.lands_on_target else SolveStatus.DIRECT_FAILED
        best = Answer.of_direct(direct) if direct.lands_on_target else None
        return Solution(problem=problem, status=status, best=best, direct=direct,
                        resim_miss=direct.resim_miss if best else None,
                        crosscheck=_crosscheck(problem, best) if best else None,
                        direct_time_s=direct_time, total_time_s=time.perf_counter() - start)
    begun = time.perf_counter()
    found = _search(problem, None, margin, time_limit, progress)
    search_time = time.perf_counter() - begun
    budget = max(CLASSIFY_FACTOR * search_time, CLASSIFY_MIN_S)
    budget = budget if time_limit is None else min(budget, time_limit - search_time)
    extremals, reach, note = _on_to_direct(problem, direct, found, margin, budget, progress)
    search_time = time.perf_counter() - begun
    answer, ties, runner_up = _ranked(found.arrivals)
    begun = time.perf_counter()
    miss = certificate = crosscheck = None
    if answer is None:
        status = SolveStatus.STOPPED_EMPTY if found.coverage.stopped else \
            SolveStatus.NO_EXTREMAL if found.coverage.complete else SolveStatus.UNRESOLVED_EMPTY
    else:
        miss = 0.0
        if answer.signs:
            certificate = certify(answer, problem.x0, problem.kappa)
            miss = float(np.hypot(*np.subtract(certificate.final_state, problem.target(answer.branch))))
            crosscheck = _crosscheck(problem, answer)
        if not miss <= VERIFY_TOL + (certificate.final_state_error if certificate else 0.0):
            status = SolveStatus.NOT_VERIFIED
        elif found.coverage.complete:
            status = SolveStatus.OPTIMAL
        elif found.coverage.stopped:
            status = SolveStatus.STOPPED
        else:
            status = SolveStatus.BEST_FOUND
    certificate_time = time.perf_counter() - begun
    direct_class = None if direct is None or answer is None else classify(direct, answer, ties, extremals, reach)
    return Solution(problem=problem, status=status, best=Answer.of_extremal(answer) if status >= 0 else None,
                    answer=answer, ties=ties, runner_up=runner_up, extremals=extremals, coverage=found.coverage,
                    resim_miss=miss, certificate=certificate, crosscheck=crosscheck, direct=direct,
                    direct_class=direct_class, notes=found.notes + ((note,) if note else ()), search_time_s=search_time,
                    certificate_time_s=certificate_time, direct_time_s=direct_time,
                    total_time_s=time.perf_counter() - start)
