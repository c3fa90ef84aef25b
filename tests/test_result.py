"""A failed solve says so first and claims nothing for a trajectory that misses: `Solution.summary`
and `Solution.to_dict` for every failure status (`ocp.result.SolveStatus`), and the direct answer's
line when its control misses. Real solves where they are cheap to provoke (a coarse transcription
whose control misses, an iteration limit, a solver that cannot load); the two search failures,
which no standard problem provokes, by replacing the status of a real solution."""

import json
import re
from dataclasses import replace

import pytest

import ocp
from ocp.direct import DirectStatus
from ocp.result import DirectClass, SolveStatus

COARSE = ocp.MultipleShooting(N=8, M=1)        # RK4, one step per interval
#: IPOPT's tolerances loosened: it reports success on a control that misses by more than the
#: transcription's own accuracy at N = 8 (a miss within it is a discretisation result, issue 21)
LOOSE = {"ipopt.tol": 1e-1, "ipopt.constr_viol_tol": 1e-1, "ipopt.dual_inf_tol": 1e1, "ipopt.compl_inf_tol": 1e-1}
CLAIMS = ("T =", "+-", "error estimate", "cross-check", "certificate", "extremal u =")
SUCCESS_ONLY = {"T", "T_error", "error_source", "switch_times", "switch_time_error", "switch_states", "ties",
                "runner_up", "extremals", "certificate", "target", "n_switches", "arc_signs"}


@pytest.fixture(scope="module")
def with_search():
    """The optimum found by the search, beside a direct answer that misses the target."""
    return ocp.solve(ocp.swing_up(1.0), COARSE, options=LOOSE)


def failures(with_search):
    p = ocp.swing_up(1.0)
    return {
        "direct misses": ocp.solve(p, COARSE, options=LOOSE, search=False),
        "direct not converged": ocp.solve(p, ocp.MultipleShooting(N=20), options={"ipopt.max_iter": 1}, search=False),
        "direct solver error": ocp.solve(p, ocp.MultipleShooting(N=20), solver="blocksqp", search=False),
        "not verified": replace(with_search, status=SolveStatus.NOT_VERIFIED, best=None, resim_miss=1e-3),
        "no extremal": replace(with_search, status=SolveStatus.NO_EXTREMAL, best=None, answer=None, ties=(), runner_up=None,
                               extremals=(), certificate=None, crosscheck=None, resim_miss=None, direct_class=None),
        "stopped empty": replace(with_search, status=SolveStatus.STOPPED_EMPTY, best=None, answer=None, ties=(),
                                 runner_up=None, extremals=(), certificate=None, crosscheck=None, resim_miss=None,
                                 direct_class=None, coverage=replace(with_search.coverage, stopped=True)),
        "unresolved empty": replace(with_search, status=SolveStatus.UNRESOLVED_EMPTY, best=None, answer=None, ties=(),
                                    runner_up=None, extremals=(), certificate=None, crosscheck=None, resim_miss=None,
                                    direct_class=None, coverage=replace(with_search.coverage, unresolved=((1.0, 1.1, -1.0),),
                                                                        n_unresolved=1)),
    }


def test_every_failure_status_is_covered(with_search):
    statuses = {s.status for s in failures(with_search).values()}
    assert statuses == {s for s in SolveStatus if s < 0}


@pytest.mark.parametrize("name", ["direct misses", "direct not converged", "direct solver error", "not verified",
                                  "no extremal", "stopped empty", "unresolved empty"])
def test_a_failure_says_so_first_and_claims_no_time(with_search, name):
    sol = failures(with_search)[name]
    assert not sol.success and sol.T_error is None and sol.switch_time_error is None
    lines = sol.summary().splitlines()
    assert lines[0] == sol.problem.describe() and lines[1].startswith("NO SOLUTION: " + sol.message)
    text = "\n".join(lines[1:])
    assert not [c for c in CLAIMS if c in text], text
    if sol.status == SolveStatus.NOT_VERIFIED:
        assert "by 1e-03" in lines[1]                              # how far it misses: the evidence
    out = json.loads(json.dumps(sol.to_dict()))                    # JSON-ready
    assert out["success"] is False and out["status"] == sol.status.name.lower() and out["optimal"] == "unknown"
    assert not SUCCESS_ONLY & set(out), SUCCESS_ONLY & set(out)
    assert out["crosscheck"] is None
    if out["direct"] is not None:
        assert out["direct"]["T_bound"] is None and out["direct"]["T_minus_optimum"] is None


def test_a_direct_answer_that_misses_beside_the_optimum(with_search):
    """The search succeeds; the direct line says its control misses, by how much, and gives no T."""
    sol = with_search
    assert sol.success and sol.direct.status == DirectStatus.MISSES_TARGET
    assert sol.direct_class == DirectClass.MISSES_TARGET
    line = next(l for l in sol.summary().splitlines() if l.startswith("direct:"))
    assert "T =" not in line and "+-" not in line and "no time is claimed" in line
    assert re.search(r"by \de-0\d \(more than 1e-06\)", line)
    d = sol.to_dict()["direct"]
    assert d["T_bound"] is None and d["T_minus_optimum"] is None and d["classified"] == "misses_target"


def test_a_verified_direct_answer_prints_its_bound():
    sol = ocp.solve(ocp.swing_up(1.0), ocp.MultipleShooting(N=50))
    line = next(l for l in sol.summary().splitlines() if l.startswith("direct:"))
    bound = sol.direct.T_bound
    assert bound == ocp.direct.base.grid_bound(sol.direct.structure, 1.0, sol.direct.resim_miss)
    assert f"T = {ocp.core.numbers.plus_minus(sol.direct.T, bound)}, 1 switch," in line
