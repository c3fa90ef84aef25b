"""Crafted store contents never crash `ocp report` (issue 18, items 5 and 7): a session environment
that is a list, a row with zero time, an unknown outcome, NaN, huge strings, escape sequences,
and a Hypothesis fuzz of every field of a row and of a session. Each ends in a report (exit 0) or
one line (exit 1: the store is corrupted, naming the row or session), the store's bytes unchanged,
and no string from the store reaches the terminal with a control character.

References: the stored-row contract of ocp/bench/row.py (`from_dict`), the conventions of
ocp/core/errors.py, and `str.isprintable` as the allow-list of what a terminal is sent.
"""

import hashlib
import json
import sqlite3

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from ocp import cli
from ocp.bench import report
from ocp.bench.store import Store
from ocp.core.errors import Fault, InputError

ESCAPES = "\x1b[31mred\x1b]0;title\x07\x9b2J\u202eevil\r"


def row(N, **changes):
    """A row as `ocp bench` stores it (a direct answer of the optimal structure)."""
    data = {"case": "c", "case_label": "swing-up kappa=1", "problem": "p", "family": "MS rk4 M=4 / ipopt",
            "label": f"MS rk4 M=4 / ipopt N={N}", "outcome": "ok", "status": "verified", "success": True,
            "guess": "default", "N": N, "T": 4.0 + 1.0 / N**2, "T_error": 1.0 / N**2, "T_ref": 4.0,
            "T_ref_error": 1e-14, "T_minus_ref": 1.0 / N**2, "total_time_s": 0.01 * N, "message": "converged",
            "timing": {"note": "timed alone"}}
    return {**data, **changes}


def store_with(path, second, environment=None, raw_environment=None):
    """A store of two rows, the second `second` (any JSON text), and one session."""
    db = Store(path)
    session = db.open_session("crafted", "test", environment or {"cpu": "x"})
    db.add_result("c", "m20", session, row(20))
    db.add_result("c", "m40", session, row(40))
    db.close()
    with sqlite3.connect(path) as raw:
        raw.execute("update results set record = ? where method_key = 'm40'", (second,))
        if raw_environment is not None:
            raw.execute("update sessions set environment = ?", (raw_environment,))
    return path


def digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


def terminal_safe(text):
    return all(c == "\n" or c.isprintable() for c in text)


@pytest.mark.parametrize("name, second, environment, code, words", [
    ("environment a list", json.dumps(row(40)), "[1, 2]", 1, "session 1 is not as ocp bench writes it"),
    ("environment not JSON", json.dumps(row(40)), "{", 1, "session 1's environment is not JSON"),
    ("zero time", json.dumps(row(40, total_time_s=0)), None, 1, "an answer takes time"),
    ("negative time", json.dumps(row(40, total_time_s=-1.0)), None, 1, "is negative"),
    ("unknown outcome", json.dumps(row(40, outcome="superb")), None, 1, "not an outcome"),
    ("NaN", json.dumps(row(40, T=float("nan"))), None, 1, "holds NaN"),
    ("Infinity", json.dumps(row(40, T_minus_ref=float("inf"))), None, 1, "holds Infinity"),
    ("a list of rows", "[" + json.dumps(row(40)) + "]", None, 1, "is a list, not a record"),
    ("huge strings", json.dumps(row(40, case_label="x" * 2_000_000)), None, 1, "a text of 2000000 characters"),
    ("long strings", json.dumps(row(40, case_label="x" * 9_000, family="f" * 9_000, message="y" * 9_000)),
     "{\"cpu\": \"" + "z" * 9_000 + "\"}", 0, ""),
    ("escape sequences", json.dumps(row(40, family=ESCAPES, case_label=ESCAPES, message=ESCAPES,
                                        outcome="local optimum")), json.dumps({ESCAPES: ESCAPES}), 0, ""),
])
def test_a_crafted_store_is_reported_or_refused_in_one_line(name, second, environment, code, words, tmp_path, capsys):
    path = store_with(tmp_path / "s.sqlite", second, raw_environment=environment)
    before = digest(path)
    assert cli.main(["report", str(path), "--out", str(tmp_path / "out")]) == code
    out, err = capsys.readouterr()
    assert digest(path) == before and terminal_safe(out) and terminal_safe(err)
    if code:
        assert err.count("\n") == 1 and err.startswith("failed:") and words in err and "Traceback" not in err
        assert not (tmp_path / "out").exists()
    else:
        assert len(out) < 50_000 and "Traceback" not in err
        assert terminal_safe((tmp_path / "out" / "summary.md").read_text())
    if name == "escape sequences":
        assert "\\x1b[31mred" in out and "\\u202e" in out and "\\x9b" in out


json_value = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() |
                          st.text(st.characters(codec="utf-8"), max_size=8),
                          lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner,
                                                                                      max_size=3), max_leaves=6)
FIELDS = sorted(row(1)) + ["options", "times", "switch_times", "arc_signs", "branch", "solver_message", "resim_miss",
                           "peak_rss_mib", "timing.note", "timing.concurrent_sessions"]


@settings(derandomize=True, max_examples=100, deadline=None, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(changes=st.dictionaries(st.sampled_from(FIELDS) | st.text(max_size=4), json_value, min_size=1, max_size=4),
       environment=json_value, raw=st.booleans())
def test_any_store_contents_end_in_a_report_or_one_line(changes, environment, raw, tmp_path_factory):
    """Hypothesis (derandomized, about 20 s): up to four fields of a row set to any JSON value
    (nested fields too), any JSON as a session's environment: the report's tables and summary
    come back terminal-safe, or the store is refused in one line naming what is wrong; never an
    exception of another kind, and the store's bytes unchanged."""
    record = row(40)
    for key, value in changes.items():
        if key.startswith("timing."):
            record["timing"] = dict(record["timing"], **{key.split(".", 1)[1]: value})
        else:
            record[key] = value
    path = tmp_path_factory.mktemp("fuzz") / "s.sqlite"
    store_with(path, json.dumps(record), raw_environment=json.dumps(environment) if raw else None)
    before = digest(path)
    try:
        tables = report.report(path)
    except (Fault, InputError) as err:
        assert "\n" not in str(err) and "corrupted" in str(err)
    else:
        assert terminal_safe(report.summary_markdown(tables)) and tables["runs"] == 2
        db = Store(path, write=False)
        rows = db.results()
        db.close()
        assert set(report.profiles(rows)) == {"time", "error", "styles"} and report.work_precision_points(rows)
    assert digest(path) == before
