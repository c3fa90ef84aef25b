"""Fuzzing the command line, suite files and stores (issue 11): whatever the arguments or the files,
`ocp` ends with exit status 0, 1 or 2 and never a traceback, an error is one line, an input store is
never changed, and exit 0 of `ocp solve` comes only with an answer re-simulated within its
tolerance.

Hypothesis, derandomized (the same examples on every run, no example database) and bounded
(max_examples), so that CI is deterministic and this file takes a few tens of seconds. The fuzz of
the arguments stops each command where its work would begin (the solve, the run of a suite, the
papers' computations, the drawing): what is fuzzed is everything that reads input; a handful of
real solves with small N check the answer's property.

References: the exit statuses of ocp/cli.py and README ("Solving": 0 solved, 1 no solution or a
fault, 2 bad input, one line), ocp.solving.VERIFY_TOL and the miss tolerance of ocp.direct.
"""

import argparse
import contextlib
import hashlib
import io
import json
import math
import sqlite3

import pytest
from hypothesis import HealthCheck, event, given, settings, strategies as st

from ocp import cli, solving
from ocp.bench import runner, suite
from ocp.bench.command import CONFIRM_RUNS
from ocp.bench.store import Store
from ocp.direct.solve import MISS_TOL

FUZZ = settings(max_examples=150, deadline=None, derandomize=True, database=None,
                suppress_health_check=list(HealthCheck))


class Reached(Exception):
    """The command got past its input: its work (a solve, a run, a drawing) is not done here."""


def stop(*args, **kwargs):
    raise Reached


def call(argv):
    """(exit status, stdout, stderr) of `ocp ARGV` in this process; status None where it got past
    its input (`Reached`)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = cli.main(argv)
        except Reached:
            code = None
        except SystemExit as exit_:          # argparse's --help
            code = exit_.code
    return code, out.getvalue(), err.getvalue()


def assert_well_ended(code, err):
    event("got past its input" if code is None else f"exit {code}")     # --hypothesis-show-statistics
    assert code in (None, 0, 1, 2), code
    assert "Traceback" not in err
    if code == 2:
        assert err.count("\n") == 1 and err.startswith("error:"), err
    if code == 1 and err:
        assert err.count("\n") == 1 and err.startswith("failed:"), err


@pytest.fixture
def stopped(monkeypatch):
    """Every command stopped where its work would begin."""
    monkeypatch.setattr(solving, "solve", stop)
    monkeypatch.setattr(runner, "run", stop)
    monkeypatch.setattr("ocp.core.parallel.executor", stop)    # no worker process runs an unpatched command
    monkeypatch.setattr("ocp.synthesis.field.synthesize", stop)
    monkeypatch.setattr("ocp.direct.nlp.build", lambda *args, **kwargs: None)    # failure-map's trial build
    monkeypatch.setattr("ocp.bench.environment.environment", dict)
    monkeypatch.setattr("ocp.papers.verify.rows", stop)
    monkeypatch.setattr("ocp.bench.report.report", stop)
    monkeypatch.setattr("ocp.figures.write", stop)
    monkeypatch.setattr("ocp.bench.failure_map.grid", stop)
    monkeypatch.setattr("ocp.bench.failure_map.sweep", stop)


def commands():
    """{name: parser} of every command of `ocp`, its arguments added: what the fuzz draws from, so
    that a new command or flag is fuzzed without editing this file."""
    top = cli.parser()
    sub = next(a for a in top._actions if isinstance(a, argparse._SubParsersAction))
    return {name: parser.complete() for name, parser in sub.choices.items()}


COMMANDS = commands()
#: every flag, choice and default of every command, and values that once broke a parser
FLAGS = sorted(set(COMMANDS) | {o for p in COMMANDS.values() for a in p._actions for o in a.option_strings}
               | {str(c) for p in COMMANDS.values() for a in p._actions for c in (a.choices or ())}
               | {str(a.default) for p in COMMANDS.values() for a in p._actions if isinstance(a.default, str)}
               | {"swing-up", "damping", "quick", "finch2015", "finch-fig1", "ipopt.tol=1e-8", "jit=true",
                  "ipopt.max_iter=-1", "fatrop", "sqpmethod", "swing-up/circle/1", "--kap", "--dir"})
NUMBERS = ["0", "1", "-1", "0.5", "-1e-3", "1e9", "1e999", "nan", "inf", "-inf", "9" * 400, "1_000", "0x10", " 2 ",
           "", "1,5", "3.0", "\u00b2", "+-1", "\u0661", "1e-3e3", ".", "/", "\x1b[31m"]
token = st.one_of(st.sampled_from(FLAGS), st.sampled_from(NUMBERS), st.text(st.characters(blacklist_characters="\0"),
                                                                           max_size=12))
#: commands that get past their input, to be changed by a few edits
VALID = [["solve", "swing-up", "--kappa", "1"],
         ["solve", "damping", "--kappa", "0.5", "--x0", "1", "0", "--direct", "--N", "30", "--json"],
         ["solve", "swing-up", "--kappa", "1", "--no-refine", "--transcription", "direct-collocation", "--degree", "2"],
         ["solve", "swing-up", "--kappa", "2", "--branch", "-1", "--direct", "--integrator", "cvodes", "--tol", "1e-8",
          "--option", "ipopt.tol=1e-8", "--miss-tol", "1e-5"],
         ["bench", "ok.toml", "--store", "s.sqlite", "--jobs", "2"],
         ["report", "s.sqlite", "--format", "png,svg", "--budget", "2", "--accuracy", "1e-3"],
         ["verify", "--paper", "finch2015", "--json"],
         ["figures", "--only", "finch-fig1", "--format", "png", "--out", "figs"],
         ["failure-map", "swing-up", "--kappa", "1", "--grid", "3", "3", "--solver", "sqpmethod", "--configuration",
          "fair", "--out", "maps"],
         ["failure-map", "damping", "--kappa", "0.5", "1.5", "--sweep", "3", "--x0", "0.5", "0", "--jobs", "2"]]
edits = st.lists(st.tuples(st.sampled_from(["insert", "replace", "delete"]), st.integers(0, 20), token), max_size=3)


def edited(argv, changes):
    argv = list(argv)
    for how, at, text in changes:
        at = at % (len(argv) + 1)
        if how == "insert":
            argv.insert(at, text)
        elif at < len(argv):
            argv[at:at + 1] = [text] if how == "replace" else []
    return argv


#: values that pass many checks, so that the fuzz gets past the first one
PLAUSIBLE = ["1", "0.5", "2", "20", "swing-up", "damping", "quick", "ok.toml", "s.sqlite", "out", "png",
             "swing-up/circle/1", "finch2015", "finch-fig1"]


def values(action):
    """A strategy of the tokens `action` takes: its choices, its default, numbers and any text, as
    many as its nargs asks (sometimes one too few or too many)."""
    count = {None: 1, "?": 1, "*": 2, "+": 2, argparse.REMAINDER: 1, argparse.PARSER: 1}.get(action.nargs, action.nargs)
    pool = [st.sampled_from(NUMBERS), st.sampled_from(PLAUSIBLE), st.text(st.characters(blacklist_characters="\0"),
                                                                           max_size=8)]
    pool += [st.sampled_from([str(c) for c in action.choices])] if action.choices else []
    pool += [st.just(str(action.default))] if isinstance(action.default, str) else []
    token = st.one_of(pool)
    return st.integers(max(0, count - 1), count + 1).flatmap(lambda n: st.lists(token, min_size=n, max_size=n))


@st.composite
def command_line(draw):
    """A command, its positionals, and up to four of its flags (or another command's), with values."""
    name = draw(st.sampled_from(sorted(COMMANDS)))
    actions = [a for a in COMMANDS[name]._actions if not isinstance(a, argparse._HelpAction)]
    argv = [name]
    for action in [a for a in actions if not a.option_strings]:
        argv += draw(values(action))
    flags = [a for a in actions if a.option_strings]
    required = [a for a in flags if a.required]
    for action in required + (draw(st.lists(st.sampled_from(flags), max_size=4)) if flags else []):
        argv.append(draw(st.sampled_from(action.option_strings)))
        argv += draw(values(action))
    return draw(st.sampled_from([argv, argv + [draw(st.sampled_from(FLAGS))]]))


@settings(FUZZ, max_examples=200)
@given(argv=command_line())
def test_every_flag_of_every_command_ends_well(argv, stopped, tmp_path, monkeypatch):
    """Every command with any of its flags (drawn from the parsers themselves) and any values: exit
    0, 1 or 2 (or it gets past its input), no traceback, one-line errors."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "ok.toml").write_text(GOOD_SUITE)
    code, out, err = call(argv)
    assert_well_ended(code, err)


def test_the_fuzz_sees_every_command_and_flag():
    """The parsers are walked whole: every command, and the transcription settings of ocp.direct."""
    from ocp import direct

    assert {"solve", "verify", "figures", "synthesis", "bifurcation", "failure-map", "bench", "report"} <= set(COMMANDS)
    assert {f"--{name}" for name in direct.settings()} <= set(FLAGS)


GOOD_SUITE = 'name = "ok"\n[[cases]]\nkind = "swing-up"\nkappa = 1.0\n[[methods]]\nN = 20\n'


@FUZZ
@given(argv=st.sampled_from(VALID), changes=edits)
def test_any_arguments_end_well(argv, changes, stopped, tmp_path, monkeypatch):
    """A valid command with up to three arguments inserted, replaced or deleted: exit 0, 1 or 2 (or
    it gets past its input), no traceback, one-line errors."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "ok.toml").write_text(GOOD_SUITE)
    code, out, err = call(edited(argv, changes))
    assert_well_ended(code, err)


def toml(value):
    """A TOML value (inline) of plain data."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if value != value else ("inf" if value > 0 else "-inf")
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(map(toml, value)) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {toml(v)}" for k, v in value.items()) + "}"


scalar = st.one_of(st.integers(-2**63, 2**63 - 1), st.floats(), st.text(max_size=8), st.booleans())
anything = st.recursive(scalar, lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner,
                                                                                            max_size=3), max_leaves=6)
case = st.fixed_dictionaries({"kind": st.sampled_from(["swing-up", "damping"]),
                              "kappa": st.floats(0.05, 3) | st.lists(st.floats(0.3, 2), min_size=1, max_size=3)},
                             optional={"x0": st.lists(st.floats(-5, 5), min_size=2, max_size=2),
                                       "guess": st.sampled_from(["default", 0, 7])})
method = st.one_of(
    st.fixed_dictionaries({"transcription": st.just("multiple-shooting"), "N": st.integers(2, 60)},
                          optional={"integrator": st.just("rk4"), "M": st.integers(1, 8),
                                    "solver": st.sampled_from(["ipopt", "fatrop", "nosuch"]),
                                    "options": st.just({"ipopt": {"ipopt.tol": 1e-8}})}),
    st.fixed_dictionaries({"transcription": st.just("direct-collocation"), "N": st.integers(2, 60)},
                          optional={"degree": st.integers(1, 9)}),
    st.just({"transcription": "extremal-search"}))
valid_suite = st.fixed_dictionaries(
    {"cases": st.lists(case, min_size=1, max_size=3), "methods": st.lists(method, min_size=1, max_size=3)},
    optional={"name": st.from_regex(suite.NAME, fullmatch=True), "description": st.text(max_size=20),
              "repeats": st.integers(1, 3), "time_limit_s": st.floats(1, 100), "miss_tol": st.floats(1e-9, 1e-3)})
FIELDS = ["name", "description", "repeats", "time_limit_s", "miss_tol", "cases", "methods", "extra",
          "cases.kind", "cases.kappa", "cases.x0", "cases.guess", "cases.extra", "methods.transcription", "methods.N",
          "methods.solver", "methods.M", "methods.tol", "methods.degree", "methods.integrator", "methods.options"]


@FUZZ
@given(data=valid_suite, changes=st.lists(st.tuples(st.sampled_from(FIELDS), st.booleans(), anything), max_size=2))
def test_any_suite_file_ends_well(data, changes, stopped, tmp_path):
    """A valid suite with up to two fields set to anything or removed: a one-line error (exit 2), or
    a suite within the limits whose default store stays in the working folder."""
    for field, remove, value in changes:
        table, _, key = field.rpartition(".")
        target = (data[table][0] if isinstance(data.get(table), list) and data[table] else None) if table else data
        if not isinstance(target, dict):         # an earlier change replaced the table
            continue
        if remove:
            target.pop(key, None)
        else:
            target[key] = value
    path = tmp_path / "suite.toml"
    path.write_text("\n".join(f"{json.dumps(k)} = {toml(v)}" for k, v in data.items()) + "\n")
    code, out, err = call(["bench", str(path), "--store", str(tmp_path / "s.sqlite")])
    assert_well_ended(code, err)
    if code is None:
        loaded = suite.load(path)
        assert suite.NAME.fullmatch(loaded.name) and "/" not in loaded.name
        assert len(loaded.pairs()) * loaded.repeats <= CONFIRM_RUNS


@settings(FUZZ, max_examples=60)
@given(content=st.binary(max_size=300) | st.text(max_size=300).map(lambda t: t.encode("utf-16")))
def test_any_bytes_as_a_suite_end_well(content, stopped, tmp_path):
    """Any bytes as a suite file: a one-line error (exit 2), never a traceback."""
    path = tmp_path / "suite.toml"
    path.write_bytes(content)
    code, out, err = call(["bench", str(path), "--store", str(tmp_path / "s.sqlite")])
    assert_well_ended(code, err)


def row(N):
    """A record as `ocp bench` stores it (the search's answer on its reference)."""
    return {"case": "c", "case_label": "swing-up kappa=1", "problem": "p", "family": "MS rk4 M=4 / ipopt",
            "label": f"MS rk4 M=4 / ipopt N={N}", "outcome": "ok", "status": "verified", "success": True,
            "guess": "default", "N": N, "T": 4.0 + 1.0 / N**2, "T_error": 1.0 / N**2, "T_ref": 4.0, "T_ref_error": 1e-14,
            "T_minus_ref": 1.0 / N**2, "total_time_s": 0.01 * N, "timing": {"note": "timed alone"}}


json_value = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=6),
                          lambda inner: st.lists(inner, max_size=2) | st.dictionaries(st.text(max_size=3), inner,
                                                                                      max_size=2), max_leaves=4)


@settings(FUZZ, max_examples=6)         # each a real report with its charts, about 2 s
@given(key=st.sampled_from(sorted(row(1))) | st.text(max_size=4), value=json_value)
def test_any_stored_record_ends_well_and_the_store_is_unchanged(key, value, tmp_path_factory):
    """A store whose second row has any value in any field: `ocp report` ends with a report (exit 0)
    or one line (exit 1, no file written half), and the store's bytes are unchanged."""
    tmp = tmp_path_factory.mktemp("report")
    db = Store(tmp / "s.sqlite")
    session = db.open_session("fuzz", "test", {})
    db.add_result("c", "m20", session, row(20))
    db.add_result("c", "m40", session, row(40))
    db.close()
    with sqlite3.connect(tmp / "s.sqlite") as raw:
        raw.execute("update results set record = ? where method_key = 'm40'",
                    (json.dumps(dict(row(40), **{key: value})),))
    before = hashlib.sha256((tmp / "s.sqlite").read_bytes()).hexdigest()
    code, out, err = call(["report", str(tmp / "s.sqlite"), "--out", str(tmp / "out"), "--json"])
    assert_well_ended(code, err)
    assert code in (0, 1) and hashlib.sha256((tmp / "s.sqlite").read_bytes()).hexdigest() == before
    assert not list(tmp.glob("out/.*.part"))


@settings(FUZZ, max_examples=4)
@given(kind=st.sampled_from(["swing-up", "damping"]), kappa=st.sampled_from(["0.6", "1", "1.5"]),
       N=st.integers(4, 30), direct_only=st.booleans(), miss_tol=st.sampled_from([None, "1e-9", "1e-3"]))
def test_a_solve_exits_0_only_with_a_resimulated_answer(kind, kappa, N, direct_only, miss_tol):
    """Real solves with small N: exit 0 exactly when the JSON says success, and then the answer
    re-simulated misses the target by at most its tolerance (the search's VERIFY_TOL plus the
    re-simulation's error estimate; --miss-tol, or
    the default, for a direct answer alone)."""
    argv = ["solve", kind, "--kappa", kappa, "--json", "--N", str(N), "--no-refine" if direct_only else "--direct"]
    argv += [] if miss_tol is None else ["--miss-tol", miss_tol]
    code, out, err = call(argv)
    assert_well_ended(code, err)
    answer = json.loads(out)
    assert (code == 0) == answer["success"]
    tolerance = ((MISS_TOL if miss_tol is None else float(miss_tol)) if direct_only else
                 solving.VERIFY_TOL + ((answer.get("certificate") or {}).get("final_state_error") or 0.0))
    assert not answer["success"] or answer["resim_miss"] <= tolerance
