"""The bench's typed values (issue 19): one outcome table that every outcome the scoring can produce
is in, and that takes a new outcome in one line (seen in the store and the report); rows validated
when read back; the parallel plumbing handling tasks as they finish, with a progress line from the
start that says what runs.

References: the classification order of ocp/bench/scoring.py and ocp/solving.py (`classify`), the
stored-row contract of ocp/bench/row.py; the extremals and references below are constructed so
that each branch applies (no solve runs here).
"""

import concurrent.futures as cf
import io
import json
import re
import subprocess
import sys
import time
from dataclasses import replace

import pytest

from ocp.bench import outcomes, scoring
from ocp.bench.outcomes import Outcome
from ocp.bench.row import Extremal, Measurement, Reference, Row, from_dict, to_dict
from ocp.core.parallel import Progress, drain

TIE = Extremal(signs=(-1, 1), branch=-1, T=4.0)
OTHER = Extremal(signs=(1, -1, 1), branch=0, T=5.0)
REF = Reference(problem="p", T=4.0, T_error=1e-14, source="constructed", arc_signs=(1, -1), switch_times=(3.0,),
                branch=0, ties=(TIE,), extremals=(TIE, OTHER), horizon=8.0)
DIRECT = Measurement(status="verified", direct_status=0, success=True, bang_bang=True, T=4.001, T_error=0.002,
                     arc_signs=(1, -1), branch=0, switch_times=(3.001,), total_time_s=1.0)
SEARCH = Measurement(status="optimal", success=True, T=4.0, T_error=1e-13, arc_signs=(1, -1), branch=0,
                     switch_times=(3.0,), total_time_s=0.1)

#: one input for every branch of `scoring.outcome` and of `ocp.solving.classify`: (measurement, reference, limit)
BRANCHES = {
    "build error": (Measurement(success=False, status="build_error", message="build error: x"), REF, 60),
    "time limit": (replace(DIRECT, limited=True), REF, 60),
    "over the CPU limit": (replace(DIRECT, solver_cpu_time_s=0.6), REF, 0.5),
    "no reference": (DIRECT, Reference(problem="p", T=None, T_error=None, source="none: x"), 60),
    "search ok": (SEARCH, REF, 60),
    "search inaccurate": (replace(SEARCH, T=4.1), REF, 60),
    "search failed": (replace(SEARCH, success=False, T=None), REF, 60),
    "raised": (Measurement(success=False, status="solver_error", message="solver error: x"), REF, 60),
    "direct solver error": (replace(DIRECT, direct_status=3, success=False), REF, 60),
    "direct not converged": (replace(DIRECT, direct_status=2, success=False), REF, 60),
    "direct misses": (replace(DIRECT, direct_status=1, success=False), REF, 60),
    "chattering": (replace(DIRECT, bang_bang=False), REF, 60),
    "optimum": (DIRECT, REF, 60),
    "discretisation": (replace(DIRECT, direct_status=4, success=False, resim_miss=5e-6, miss_bound=1e-5), REF, 60),
    "tie": (replace(DIRECT, arc_signs=(-1, 1), branch=-1), REF, 60),
    "inaccurate": (replace(DIRECT, T=4.01), REF, 60),
    "local optimum": (replace(DIRECT, T=5.0, arc_signs=(1, -1, 1)), REF, 60),
    "wrong structure": (replace(DIRECT, branch=3), REF, 60),
    "beyond horizon": (replace(DIRECT, T=9.0, arc_signs=(1, -1, 1, -1)), REF, 60),
}


def test_every_outcome_the_scoring_produces_is_in_the_table_and_every_entry_is_produced():
    """Issue 19: runner.py returned "no convergence", which the table (then "not converged") lacked.
    Run over an input of every branch, the scoring gives only members of the table, and all of
    them; each has its chart style, and the ranks order the classification without ties."""
    produced = {name: scoring.outcome(*inputs) for name, inputs in BRANCHES.items()}
    assert all(isinstance(o, Outcome) for o in produced.values())
    assert set(produced.values()) == set(Outcome)
    assert produced["search failed"] == Outcome.NOT_CONVERGED == "not converged"
    assert produced["tie"] == produced["optimum"] == "ok"
    assert sorted(o.rank for o in Outcome) == list(range(len(Outcome)))
    assert all(o.colour.startswith("#") and o.marker for o in Outcome)
    assert all(bool(o.open_marker) == (o.structure == "another") for o in Outcome)
    assert produced["over the CPU limit"] == produced["time limit"] == "time limit"
    assert replace(DIRECT, total_time_s=100.0).solver_time_s < 60 and scoring.outcome(
        replace(DIRECT, total_time_s=100.0), REF, 60) == "ok"          # the checking's time is not the solver's
    assert [o for o in Outcome if o.success] == [Outcome.OK, Outcome.DISCRETISATION]


def row(**changes):
    data = {"case": "c", "case_label": "swing-up kappa=1", "problem": "p", "family": "MS rk4 M=4 / ipopt",
            "label": "MS rk4 M=4 / ipopt N=20", "outcome": "ok", "status": "verified", "success": True,
            "guess": "default", "N": 20, "T": 4.001, "T_error": 0.002, "T_ref": 4.0, "T_ref_error": 1e-14,
            "T_minus_ref": 0.001, "total_time_s": 0.2, "timing": {"note": "timed alone"}}
    return {k: v for k, v in {**data, **changes}.items() if v is not ...}


def test_a_row_reads_back_as_it_was_written_and_a_bad_one_says_which_field():
    """A Row written as plain data (`to_dict`) reads back equal; a stored row with a field of the
    wrong type, a missing one, an unknown outcome or an answer in no time is refused naming it."""
    r = from_dict(Row, row())
    assert from_dict(Row, json.loads(json.dumps(to_dict(r)))) == r and r.outcome is Outcome.OK
    for changes, words in (({"outcome": "great"}, "outcome = 'great': not an outcome"),
                           ({"total_time_s": 0.0}, "an answer takes time"),
                           ({"T": "fast"}, "T = 'fast': not a finite number"),
                           ({"N": True}, "N = True: not an integer"),
                           ({"timing": []}, "timing = []: is a list, not a record"),
                           ({"case": ...}, "has no 'case'"),
                           ({"N": None}, "N = None for the family")):
        with pytest.raises(ValueError, match=re.escape(words)):
            from_dict(Row, row(**changes))


DUMMY = '''
import importlib.util, json, sys
from pathlib import Path
import ocp.bench
source = Path(ocp.bench.__file__).with_name("outcomes.py").read_text()
line = '    NO_REFERENCE = "no reference"'
assert line in source
source = source.replace(line, '    DUMMY = "dummy outcome", 12, False, "", "#123456", "*"\\n' + line)
module = importlib.util.module_from_spec(importlib.util.spec_from_loader("ocp.bench.outcomes", loader=None))
exec(compile(source, "outcomes.py", "exec"), module.__dict__)
sys.modules["ocp.bench.outcomes"] = module
from ocp import cli
from ocp.bench.store import Store
store = Store(sys.argv[1])
session = store.open_session("dummy", "test", {})
store.add_result("c", "m", session, json.loads(sys.argv[2]))
assert [r.outcome.colour for r in store.results()] == ["#123456"]
store.close()
sys.exit(cli.main(["report", sys.argv[1], "--out", sys.argv[3], "--json"]))
'''


def test_an_outcome_added_in_one_line_is_stored_and_reported(tmp_path):
    """Issue 19 (done when): adding an outcome takes one place. One line added to the table (in a
    fresh interpreter) and a row of that outcome is stored, validated, counted and listed."""
    out = subprocess.run([sys.executable, "-c", DUMMY, str(tmp_path / "s.sqlite"),
                          json.dumps(row(outcome="dummy outcome")), str(tmp_path / "report")],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    tables = json.loads(out.stdout)
    assert tables["outcomes"] == {"dummy outcome": 1}
    assert [f["outcome"] for f in tables["failures"]] == ["dummy outcome"]
    assert "dummy outcome 1" in (tmp_path / "report" / "summary.md").read_text()


def test_rows_are_handled_as_they_finish_and_the_progress_line_says_what_runs():
    """Issue 24: the bench showed nothing for its first seconds and printed rows in submission order,
    so one slow row held back finished ones. With two workers, a fast task submitted second is
    handled first; the first line is written at once, and a line names the task still running."""
    stream = io.StringIO()
    handled = []

    def handle(name, result):
        handled.append(name)
        return f"{name} done"

    with cf.ThreadPoolExecutor(2) as pool:
        begun = time.perf_counter()
        drain(pool, 2, [(time.sleep, (1.0,), "slow"), (time.sleep, (0.05,), "fast")], handle,
              Progress(2, "tasks", stream), label=str)
    lines = stream.getvalue().splitlines()
    assert handled == ["fast", "slow"] and time.perf_counter() - begun < 5
    assert lines[0].startswith("[") and "0/2 tasks" in lines[0] and "estimating" in lines[0]
    assert any("1/2 tasks" in line and "running: slow" in line and "last: fast done" in line for line in lines)
    assert "2/2 tasks" in lines[-1]


def test_old_outcome_labels_and_the_failure_map_indices_stay():
    """Saved failure maps hold indices into OUTCOMES: the first twelve stay in their old order."""
    assert list(outcomes.OUTCOMES)[:12] == ["ok", "build error", "time limit", "inaccurate", "local optimum",
                                            "wrong structure", "beyond horizon", "chattering", "misses target",
                                            "not converged", "solver error", "no reference"]


def test_a_row_keeps_the_solvers_time_apart_from_the_checking_and_every_starts_message():
    """Issue 21 (items 1-2, as new fields only): the solver's own build and NLP solve times, apart
    from the suite's checking (the re-simulation of every start), and each start's own message.
    The parts add up to the total (each a difference of perf_counter readings: to rounding)."""
    from ocp.bench import measurement, suite
    from ocp.direct.solve import DirectStatus, default_guesses

    case = suite.Case("swing-up", 1.0)
    m = measurement.measure(case, suite.Method(settings=(("N", 20),)))
    assert m.build_time_s > 0 and m.solve_time_s > 0 and m.check_time_s > 0 and m.cpu_time_s > 0
    assert m.build_time_s + m.solve_time_s + m.check_time_s == pytest.approx(m.total_time_s, abs=1e-9)
    assert [s.guess for s in m.every_start] == [g.label for g in default_guesses(case.problem(), 20)]
    assert all(s.solver_message and s.status in {d.name.lower() for d in DirectStatus} for s in m.every_start)
    assert m.solver_message in {s.solver_message for s in m.every_start if s.status == m.status}
    assert sum(s.solve_time_s for s in m.every_start) == pytest.approx(m.solve_time_s, rel=1e-12)
    assert from_dict(Measurement, json.loads(json.dumps(to_dict(m)))) == m


def test_a_store_of_the_untyped_version_is_refused_naming_its_version(tmp_path):
    """Schema version 2 holds typed rows; a version-1 store (untyped records) is refused in one line."""
    import sqlite3

    from ocp.bench.store import Store
    from ocp.core.errors import InputError

    Store(tmp_path / "old.sqlite").close()
    with sqlite3.connect(tmp_path / "old.sqlite") as db:
        db.execute("pragma user_version = 1")
    for write in (False, True):
        with pytest.raises(InputError, match="schema version 1; this ocp reads version 2") as caught:
            Store(tmp_path / "old.sqlite", write=write)
        assert "\n" not in str(caught.value)
