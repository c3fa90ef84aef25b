"""Suite files as data, as issue 11 asks: every value checked (type and range) with one line naming the
file, the table and the field (exit 2, no store created); a name cannot lead the store out of the
working folder; sizes are limited, and a large suite needs --yes.

References: the conventions of ocp/core/errors.py (InputError: one line "error: ...", exit 2), the
suite format of ocp/bench/suite.py, and the ranges the command line accepts (README, "Solving").
"""

from pathlib import Path

import pytest

from ocp import cli
from ocp.bench import configurations, runner, suite
from ocp.bench.command import CONFIRM_RUNS
from ocp.direct.shooting import INTEGRATORS

GOOD = """name = "ok"
repeats = 1
[[cases]]
kind = "swing-up"
kappa = 1.0
[[methods]]
N = 20
"""

BAD = {                                           # what replaces a line of GOOD (or is added) -> words of the error
    "cases as a list of strings": ('[[cases]]\nkind = "swing-up"\nkappa = 1.0', 'cases = ["a", "b"]', "cases"),
    "[methods] as a table": ("[[methods]]", "[methods]", "methods"),
    "a string for a number": ("kappa = 1.0", 'kappa = "1"', "kappa"),
    "a string for N": ("N = 20", 'N = "20"', "N = '20'"),
    "a float for N": ("N = 20", "N = 20.5", "N = 20.5"),
    "x0 = 5": ("kappa = 1.0", "kappa = 1.0\nx0 = 5", "x0 = 5"),
    "x0 of three numbers": ("kappa = 1.0", "kappa = 1.0\nx0 = [1, 2, 3]", "x0"),
    "miss_tol = -1": ("repeats = 1", "repeats = 1\nmiss_tol = -1", "miss_tol"),
    "time_limit_s = -5": ("repeats = 1", "repeats = 1\ntime_limit_s = -5", "time_limit_s"),
    "time_limit_s as text": ("repeats = 1", 'repeats = 1\ntime_limit_s = "60"', "time_limit_s"),
    "guess = -1": ("kappa = 1.0", "kappa = 1.0\nguess = -1", "guess"),
    "guess = true": ("kappa = 1.0", "kappa = 1.0\nguess = true", "guess"),
    "refine = \"yes\"": ("N = 20", 'N = 20\nrefine = "yes"', "refine"),
    "repeats = 10**9": ("repeats = 1", "repeats = 1000000000", "repeats"),
    "repeats = 0": ("repeats = 1", "repeats = 0", "repeats"),
    "name leaving the folder": ('name = "ok"', 'name = "../../x"', "name"),
    "name with a slash": ('name = "ok"', 'name = "a/b"', "name"),
    "an absolute name": ('name = "ok"', 'name = "/tmp/x"', "name"),
    "kind not a string": ('kind = "swing-up"', "kind = 3", "kind"),
    "kind as a table": ('kind = "swing-up"', "kind = { a = 1 }", "kind"),
    "a date as an option": ("N = 20", "N = 20\noptions = { ipopt = { when = 1979-05-27 } }", "options.ipopt.when"),
    "an unsafe option": ("N = 20", 'N = 20\noptions = { ipopt = { "ipopt.output_file" = "x" } }', "output_file"),
    "a solver name with a path": ("N = 20", 'N = 20\nsolver = "../../lib/x"', "solver"),
    "an unknown solver": ("N = 20", 'N = 20\nsolver = "evil"', "solver = 'evil'"),
    "an option off the allow-list": ("N = 20", 'N = 20\noptions = { ipopt = { "ipopt.hsllib" = "./x.so" } }',
                                     "ipopt.hsllib"),
    "a linear solver that is not shipped": ("N = 20", 'N = 20\noptions = { ipopt = { "ipopt.linear_solver" = "ma27" } }',
                                            "mumps"),
    "a float for an integer option": ("N = 20", 'N = 20\noptions = { ipopt = { "ipopt.max_iter" = 1.5 } }',
                                      "ipopt.max_iter = 1.5"),
    "an infinite tolerance": ("N = 20", 'N = 20\noptions = { ipopt = { "ipopt.tol" = inf } }', "not finite"),
    "a QP solver by a made-up name": ("N = 20", 'N = 20\nsolver = "sqpmethod"\noptions = { sqpmethod = { qpsol = "evil" } }',
                                      "qpsol = 'evil'"),
    "a QP option of the wrong type": ("N = 20", 'N = 20\nsolver = "sqpmethod"\noptions = { sqpmethod = { qpsol = "qrqp", '
                                      'qpsol_options = { max_iter = "9" } } }', "qpsol_options.max_iter"),
    "a case without kappa": ("kappa = 1.0", "", "kappa"),
    "an unknown configuration": ("N = 20", 'N = 20\nconfiguration = "tuned"', "configuration = 'tuned'"),
    "a configuration as a number": ("N = 20", "N = 20\nconfiguration = 1", "configuration"),
    "no fair configuration": ("N = 20", 'N = 20\nsolver = "alpaqa"\nconfiguration = "fair"', "'alpaqa'"),
    "10^6 cases": ("kappa = 1.0", f"kappa = {[1.0] * 1000}\nguess = {list(range(1000))}", "at most 100000"),
    "10^6 pairs": ("kappa = 1.0\n", f"kappa = {[0.5 + i / 1000 for i in range(400)]}\n", "at most 100000"),
}


@pytest.mark.parametrize("name", list(BAD))
def test_a_bad_suite_is_one_line_naming_file_and_field(name, tmp_path, capsys):
    """Issue 11: wrong shapes gave tracebacks and wrong values were accepted; each is one line (exit
    2) naming the file and the field, and no store is created."""
    old, new, words = BAD[name]
    text = GOOD.replace(old, new, 1)
    if name == "10^6 pairs":
        text = text.replace("N = 20", f"N = {list(range(2, 302))}")
    assert text != GOOD
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert cli.main(["bench", str(path), "--store", str(tmp_path / "s.sqlite")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"error: {path}:") and words in err, err
    assert not (tmp_path / "s.sqlite").exists()


@pytest.mark.parametrize("content", [
    "name = 'x'\n".encode("utf-16"),                      # UTF-16 with its byte-order mark
    bytes(range(256)) * 4,                                # binary
    ("x = " + "[" * 5000 + "]" * 5000).encode(),          # nested deeper than the parser recurses
    b"name = 'x'\n" + b"# padding\n" * 120_000,           # larger than a suite may be
])
def test_a_file_that_is_not_a_suite_is_one_line(content, tmp_path, capsys):
    """Issue 11: UTF-16, binary and deeply nested files gave tracebacks; each is one line, exit 2."""
    path = tmp_path / "suite.toml"
    path.write_bytes(content)
    assert cli.main(["bench", str(path), "--store", str(tmp_path / "s.sqlite")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"error: {path}:")


def test_the_default_store_stays_in_the_working_folder(tmp_path, monkeypatch):
    """Issue 11: `name = "../../x"` wrote the store elsewhere. A name is a plain file name (refused
    above otherwise), and a file's stem standing for a missing name is sanitised."""
    path = tmp_path / "my suite (v2)!.toml"
    path.write_text(GOOD.replace('name = "ok"\n', ""))
    s = suite.load(path)
    assert s.name == "my-suite-v2"
    monkeypatch.chdir(tmp_path)
    assert Path(f"ocp-bench-{s.name}.sqlite").resolve().parent == Path.cwd()
    with pytest.raises(suite.InputError, match="name"):
        suite.Suite("../x", "", 1, 1.0, 1e-6, s.cases, s.methods)


def test_a_large_suite_needs_yes(tmp_path, monkeypatch, capsys):
    """Issue 11: a suite of 10^6 pairs or 10^9 repeats started without a word. Above CONFIRM_RUNS
    solves `ocp bench` asks for --yes (exit 2, nothing created); with it, it runs."""
    path = tmp_path / "big.toml"
    path.write_text(GOOD.replace("kappa = 1.0", f"kappa = {[0.5 + i / 100 for i in range(60)]}")
                    .replace("N = 20", f"N = {list(range(20, 120))}"))
    assert len(suite.load(path).pairs()) == 6000 > CONFIRM_RUNS
    store = tmp_path / "s.sqlite"
    assert cli.main(["bench", str(path), "--store", str(store)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "6000 solves" in err and "--yes" in err and not store.exists()

    def stop(*args):
        raise KeyboardInterrupt
    monkeypatch.setattr(runner, "run", stop)                 # --yes passes the check; the run is not needed here
    assert cli.main(["bench", str(path), "--store", str(store), "--yes"]) == 130


def test_named_suites_are_valid_and_full_needs_yes():
    """The suites shipped (ocp/bench/suites) pass every check; `full` is above the --yes threshold."""
    quick, full = suite.load("quick"), suite.load("full")
    assert len(quick.pairs()) * quick.repeats <= CONFIRM_RUNS < len(full.pairs()) * full.repeats


@pytest.mark.parametrize("argv, words", [
    (["bench", "quick", "--jobs", "9" * 400], "jobs"),
    (["bench", "quick", "--jobs", "100000"], "jobs"),
    (["bench", "../../etc/passwd"], "no suite"),
])
def test_bench_arguments_are_one_line(argv, words, capsys):
    """Issue 11: out-of-range arguments of `ocp bench` are one line, exit 2."""
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err


def test_a_malformed_scheduler_is_one_line(tmp_path, capsys):
    """Issue 11: a malformed --scheduler address gave a traceback of Dask's."""
    pytest.importorskip("distributed")
    path = tmp_path / "ok.toml"
    path.write_text(GOOD)
    for address in ("tcp://", "::::", "foo://bar"):
        assert cli.main(["bench", str(path), "--store", str(tmp_path / "s.sqlite"), "--scheduler", address]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--scheduler" in err and "tcp://host:8786" in err


def test_cases_named_by_instance_or_tag_of_the_reference_set(tmp_path):
    """Issue 20: a suite names instances of the reference set by id or by tag; each becomes the case
    of its problem (its pinned branch too), and the bench's reference of it is the set's, not searched
    again. A name the set does not have is one line naming what is accepted."""
    from ocp.bench import reference as bench_reference
    from ocp.reference import load

    rows = [r for r in load().values() if r["status"] == "solved"]
    plane = next(r for r in rows if r["branch_pinned"] is not None)
    tagged = [r for r in rows if "near-tie" in r["tags"]]
    path = tmp_path / "set.toml"
    path.write_text(f'name = "set"\n[[cases]]\ninstance = ["{plane["id"]}"]\n[[cases]]\ntag = "near-tie"\n'
                    f'[[methods]]\ntranscription = "multiple-shooting"\nN = 20\n')
    cases = suite.load(path).cases
    problems = {(c.kind, c.kappa, c.x0, c.branch) for c in cases}
    assert len(cases) == 1 + len(tagged) and tagged
    assert (plane["kind"], plane["kappa"], tuple(plane["x0"]), plane["branch_pinned"]) in problems
    ref = bench_reference.reference(next(c for c in cases if c.branch is not None))
    assert ref.source.startswith(f"the reference set ({plane['id']}") and ref.T == float(plane["optimum"]["refined"]["T"])
    for bad, says in (('instance = "swing-up/circle/nowhere"', "no solved instance"), ('tag = "easy"', "no solved instance"),
                      ('tag = "tie"\nkind = "damping"', "takes instance or tag")):
        path.write_text(f'name = "set"\n[[cases]]\n{bad}\n[[methods]]\ntranscription = "multiple-shooting"\n')
        with pytest.raises(suite.InputError, match=says):
            suite.load(path)


def test_groups_pair_cases_with_methods_only_where_they_share_one(tmp_path):
    """Tables naming a group meet only tables sharing it; a table without one meets every table; a
    case in two tables takes both; a bad group is one line; the shipped standard suite is designed,
    not a product (issue 21)."""
    path = tmp_path / "groups.toml"
    path.write_text('name = "g"\n[[cases]]\nkind = "swing-up"\nkappa = [1.0, 0.9]\ngroup = "core"\n'
                    '[[cases]]\nkind = "damping"\nkappa = 1.0\ngroup = ["core", "wide"]\n'
                    '[[cases]]\nkind = "swing-up"\nkappa = 0.9\ngroup = "wide"\n'
                    '[[methods]]\nN = 20\ngroup = "core"\n[[methods]]\nN = [30, 40]\ngroup = "wide"\n'
                    '[[methods]]\ntranscription = "extremal-search"\n')
    s = suite.load(path)
    pairs = {(c.kind, c.kappa, m.N) for c, m in s.pairs()}
    assert len(s.cases) == 3 and len(s.methods) == 4 and s.size == len(s.pairs()) == len(pairs) == 10
    assert ("swing-up", 1.0, 30) not in pairs and ("swing-up", 1.0, 20) in pairs and ("swing-up", 1.0, None) in pairs
    assert {("swing-up", 0.9, n) for n in (20, 30, 40, None)} <= pairs     # in "core" and "wide": every method
    for bad, says in (('group = 3', "group = 3"), ('group = ["a b"]', "is not a group")):
        path.write_text(f'name = "g"\n[[cases]]\nkind = "swing-up"\nkappa = 1.0\n{bad}\n[[methods]]\nN = 20\n')
        with pytest.raises(suite.InputError, match=says):
            suite.load(path)
    path.write_text('name = "g"\n[[cases]]\nkind = "swing-up"\nkappa = 1.0\ngroup = "a"\n[[methods]]\nN = 20\n'
                    'group = "b"\n')
    with pytest.raises(suite.InputError, match="no case shares a group"):
        suite.load(path)
    standard = suite.load("standard")
    problems = {c.problem_key for c in standard.cases}
    assert len(problems) >= 40 and len(standard.pairs()) < len(standard.cases) * len(standard.methods)
    assert {c.kind for c in standard.cases} == {"swing-up", "damping"} and {c.branch is None for c in standard.cases} \
        == {True, False}
    assert set(suite.KINDS_OF_METHOD) == {m.transcription for m in standard.methods}
    assert {dict(m.settings).get("integrator", "rk4") for m in standard.methods
            if m.transcription == "multiple-shooting"} == set(INTEGRATORS)
    assert set(configurations.FAIR) <= {m.solver for m in standard.methods if m.configuration == "fair"}
    assert {m.configuration for m in standard.methods} == {"default", "fair"}
    assert min(m.N for m in standard.methods if m.N) == 25 and max(m.N for m in standard.methods if m.N) == 400
