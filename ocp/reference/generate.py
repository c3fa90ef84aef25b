"""Computing the reference set: a JSON line per instance, appended as each is done (resumable).

For one instance (`compute`, run in a worker process):

    search        `ocp.solve` with margin MARGIN: the complete search of extremals (the global optimum,
                  its ties, every extremal arriving before (1 + MARGIN) times the optimum), the answer
                  certified (`ocp.indirect.certify`)
    local optima  every extremal certified too: first order, strict bang-bang and a positive definite
                  reduced Hessian make it a strict strong local minimum (a trap for a local method)
    refinement    the optimum and its ties solved again at 32 and 40 digits by
                  `ocp.reference.multiprecision` (nothing shared with the search's integrator), the
                  40-digit values stored as decimal text with their error bounds; the double-precision
                  answer must agree within its stated error (`agreement` <= 1)

An instance whose search takes longer than BUDGET_S, or does not prove its optimum, is stored as
skipped with the reason.
"""

import math
import platform
import signal
import time
from contextlib import contextmanager

import mpmath

from ..core.provenance import git_commit
from . import multiprecision as mp_route

#: the search scans to (1 + MARGIN) times the optimum: the runner-up and the traps up to twice it
MARGIN = 1.0
#: an instance whose search exceeds this is skipped (recorded with the reason)
BUDGET_S = 60
COMMAND = "ocp reference generate --jobs 2"
#: relative gap to the runner-up under which an instance is tagged near-tie
NEAR_TIE = 1e-6


class _OverBudget(Exception):
    pass


@contextmanager
def _budget(seconds):
    """SIGALRM raises _OverBudget after `seconds` (a worker's main thread)."""
    def alarm(signum, frame):
        raise _OverBudget()
    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def decimal(value, error):
    """(value, error) as text: the value to the digit of the error's leading digit (at least 20
    significant digits are asked of the data), the error rounded up to two digits."""
    error = mpmath.mpf(error)
    exponent = int(mpmath.floor(mpmath.log10(error)))
    places = max(0, -exponent + 1)
    with mpmath.workdps(60):
        text = mpmath.nstr(mpmath.mpf(value), max(1, int(mpmath.floor(mpmath.log10(abs(value)))) + 1 + places)
                           if value else 1, min_fixed=-100, max_fixed=100, strip_zeros=False)
        err = mpmath.ceil(error / mpmath.mpf(10) ** (exponent - 1)) * mpmath.mpf(10) ** (exponent - 1)
    return text, mpmath.nstr(err, 2, min_fixed=1, max_fixed=0)


#: what the refinement takes as exact (a row without this text is refined again)
INPUTS = "x0 and kappa: the decimals written; the target: (2k + 1) pi (swing-up) or 2k pi (damping), exact"


def _refined(problem, extremal):
    """The refined record of an extremal: 40-digit values as text with their errors, and the agreement
    |T_mp - T_double| / T_error of the search."""
    target_over_pi = round(problem.base / math.pi) + 2 * extremal.branch
    r = mp_route.refine(problem.x0, problem.kappa, extremal.signs, target_over_pi, extremal.phi, extremal.durations)
    T, T_err = decimal(r.T, r.T_error)
    return {
        "T": T, "T_error": T_err,
        "switch_times": [decimal(t, e)[0] for t, e in zip(r.switch_times, r.switch_time_errors)],
        "switch_time_errors": [decimal(t, e)[1] for t, e in zip(r.switch_times, r.switch_time_errors)],
        "switch_states": [[decimal(v, e)[0] for v, e in zip(s, se)] for s, se in zip(r.switch_states, r.switch_state_errors)],
        "switch_state_errors": [[decimal(v, e)[1] for v, e in zip(s, se)]
                                for s, se in zip(r.switch_states, r.switch_state_errors)],
        "p0": [decimal(v, e)[0] for v, e in zip(r.p0, r.p0_errors)],
        "p0_errors": [decimal(v, e)[1] for v, e in zip(r.p0, r.p0_errors)],
        "costate_angle": decimal(r.phi, r.phi_error)[0],
        "digits": list(r.digits), "taylor_steps": r.steps, "inputs": INPUTS,
        "agreement": float(abs(r.T - mpmath.mpf(extremal.T)) / extremal.T_error),
    }


def _extremal(e, certified=None):
    """An extremal of the search as plain data (double precision, its stated errors)."""
    d = {"arc_signs": list(e.signs), "branch": e.branch, "T": e.T, "T_error": e.T_error,
         "switch_times": list(e.switch_times), "switch_time_error": e.switch_time_error}
    if certified is not None:
        d["local_optimum"] = certified
    return d


def _structure(e):
    """An extremal with its switch states and costate (double precision)."""
    return dict(_extremal(e), switch_states=[list(s) for s in e.switch_states], p0=list(e.p0), costate_angle=e.phi)


def _solution(problem, e):
    """The record of an optimal extremal: structure, double-precision values, refined ones."""
    return dict(_structure(e), double={"T": e.T, "T_error": e.T_error}, refined=_refined(problem, e))


def labels(families, hardness):
    """The tags of a solved instance: its families, and "tie" (several optimal controls), "near-tie"
    (the runner-up within NEAR_TIE relative), "local-optima" (a slower extremal is a strict local
    minimum), "many-switches" (4 or more)."""
    out = list(families)
    gap = hardness["relative_gap_to_runner_up"]
    out += ["tie"] if hardness["ties"] else []
    out += ["near-tie"] if gap is not None and gap < NEAR_TIE else []
    out += ["local-optima"] if hardness["local_optima"] else []
    out += ["many-switches"] if hardness["switches"] >= 4 else []
    return out


def versions():
    import numpy
    import scipy
    return {"python": platform.python_version(), "numpy": numpy.__version__, "scipy": scipy.__version__,
            "mpmath": mpmath.__version__}


def compute(instance):
    """The JSON-ready row of one Instance (run in a worker)."""
    from ..indirect import certify
    from ..solving import solve

    start = time.perf_counter()
    problem = instance.problem()
    row = {"id": instance.id, "kind": instance.kind, "reading": problem.reading, "kappa": instance.kappa,
           "x0": list(instance.x0), "branch_pinned": instance.branch, "families": list(instance.families)}
    provenance = {"command": COMMAND, "commit": git_commit(), "versions": versions(), "margin": MARGIN}
    try:
        with _budget(BUDGET_S):
            sol = solve(problem, margin=MARGIN)
    except _OverBudget:
        return dict(row, status="skipped", reason=f"the search took longer than {BUDGET_S} s",
                    provenance=dict(provenance, time_s=time.perf_counter() - start))
    if sol.answer is None or not sol.optimal or not sol.answer.signs:
        reason = sol.message if sol.answer is None or not sol.optimal else "the start is on the target"
        return dict(row, status="skipped", reason=reason, provenance=dict(provenance, time_s=time.perf_counter() - start))
    if len(sol.answer.signs) < 2:
        return dict(row, status="skipped", reason="the optimum has no switch (no costate to refine)",
                    provenance=dict(provenance, time_s=time.perf_counter() - start))
    local = [e is sol.answer or any(e is t for t in sol.ties) or
             (len(e.signs) > 0 and certify(e, problem.x0, problem.kappa).certified) for e in sol.extremals]
    optimum = _solution(problem, sol.answer)
    optimum["certificate"] = sol.certificate.to_dict()
    ties = [_solution(problem, t) for t in sol.ties]
    runner = None if sol.runner_up is None else _structure(sol.runner_up)
    durations = sol.answer.durations
    gap = None if sol.runner_up is None else (sol.runner_up.T - sol.answer.T) / sol.answer.T
    others = [_extremal(e, flag) for e, flag in zip(sol.extremals, local)]
    tags = {"switches": len(sol.answer.signs) - 1, "ties": len(sol.ties),
            "relative_gap_to_runner_up": gap, "local_optima": sum(local) - 1 - len(sol.ties),
            "extremals": len(sol.extremals), "shortest_arc": float(min(durations)),
            "distance_to_switching_curve": None, "distance_to_dispersal_curve": None,
            "distances": "not computed (the shortest arc and the gap to the runner-up stand for them)"}
    return dict(row, status="solved", optimum=optimum, ties=ties, runner_up=runner, extremals=others,
                tags=labels(instance.families, tags), hardness=tags,
                coverage={"complete": sol.coverage.complete, "horizon": sol.coverage.horizon,
                          "extremals_integrated": sol.coverage.extremals,
                          "description": sol.coverage.describe()},
                provenance=dict(provenance, time_s=time.perf_counter() - start,
                                search_time_s=sol.search_time_s))


def stale(row):
    """Whether a solved row's refinement predates INPUTS (then `refine_again` redoes it)."""
    return row["status"] == "solved" and row["optimum"]["refined"].get("inputs") != INPUTS


def refine_again(row):
    """The row with the refinement of its optimum and ties redone from their stored costate angle and
    arc durations (no search)."""
    from types import SimpleNamespace

    from ..core.problem import make

    problem = make(row["kind"], row["kappa"], row["x0"], row["branch_pinned"])

    def redo(e):
        times = (0.0, *e["switch_times"], e["T"])
        extremal = SimpleNamespace(signs=tuple(e["arc_signs"]), branch=e["branch"], phi=e["costate_angle"], T=e["T"],
                                   T_error=e["T_error"], durations=tuple(b - a for a, b in zip(times, times[1:])))
        return dict(e, refined=_refined(problem, extremal))

    optimum, ties = redo(row["optimum"]), [redo(t) for t in row["ties"]]
    provenance = dict(row["provenance"], refined_again_commit=git_commit())
    return dict(row, optimum=optimum, ties=ties, provenance=provenance)


def relabelled(row):
    """The row with its tags recomputed by `labels` and its provenance's command as COMMAND (rows written
    by an earlier version of this module: other tags, a command misspelt, a timing of the refinement
    done again that measured nothing)."""
    provenance = {k: v for k, v in row["provenance"].items() if k != "refined_again_s"}
    provenance["command"] = COMMAND
    if "refined_commit" in provenance:
        provenance["refined_again_commit"] = provenance.pop("refined_commit")
    row = dict(row, provenance=provenance)
    return row if row["status"] != "solved" else dict(row, tags=labels(row["families"], row["hardness"]))
