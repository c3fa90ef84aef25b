"""Issue 18, item 1: no input makes ocp load a library of the user's folders.

A shared library whose constructor appends to a marker file is compiled with `cc` and placed, under
every name CasADi or IPOPT could look for (a plugin `libcasadi_<kind>_<name>.so` for an unknown name
and for the plugins shipped that cannot load from CasADi's folder, HSL's and Pardiso's libraries),
in the working folder and beside a suite file. Every loading path through ocp's public surfaces is
tried: `ocp.solve`, `python -m ocp.cli solve --direct`, suite files (solver, qpsol, linsol, hsllib,
pardisolib, linear_solver, options that name a file), and the defaults that name an unloadable
plugin (blockSQP's linear solver MA27). Each is refused with exit 2 and one line, or runs, and the
marker never appears. How CasADi searches: `ocp.direct.solvers` (its module docstring).
"""

import shutil
import subprocess
import sys

import pytest

import ocp
from ocp import cli
from ocp.bench import configurations, suite
from ocp.core.errors import InputError
from ocp.direct import options, solvers

MARKING = r"""
#include <stdio.h>
__attribute__((constructor)) static void mark(void) {
    FILE *f = fopen(MARKER, "a");
    if (f) { fputs("loaded\n", f); fclose(f); }
}
"""
#: every library name a hostile folder could hold for CasADi or IPOPT to find
NAMES = ([f"libcasadi_{kind}_evil.so" for kind in ("nlpsol", "conic", "linsol", "integrator", "rootfinder")]
         + ["libcasadi_linsol_ma27.so", "libcasadi_nlpsol_knitro.so", "libcasadi_nlpsol_snopt.so",
            "libcasadi_nlpsol_worhp.so", "libcasadi_nlpsol_madnlp.so", "libcasadi_conic_gurobi.so",
            "libhsl.so", "libcoinhsl.so", "libpardiso.so", "libmkl_rt.so", "libspral.so", "evil.so"])
SUITE = """
[[cases]]
kind = "swing-up"
kappa = 1.0

[[methods]]
N = 10
{method}
"""
#: suite-file methods that name a plugin or a file
HOSTILE_METHODS = {
    "solver evil": 'solver = "evil"',
    "qpsol evil": 'solver = "sqpmethod"\noptions = { sqpmethod = { qpsol = "evil" } }',
    "linsol evil": 'solver = "blocksqp"\noptions = { blocksqp = { linsol = "evil" } }',
    "linsol ma27": 'solver = "blocksqp"\noptions = { blocksqp = { linsol = "ma27" } }',
    "hsllib": 'options = { ipopt = { "ipopt.linear_solver" = "ma27", "ipopt.hsllib" = "./evil.so" } }',
    "pardisolib": 'options = { ipopt = { "ipopt.linear_solver" = "pardiso", "ipopt.pardisolib" = "./evil.so" } }',
    "linear_solver ma57": 'options = { ipopt = { "ipopt.linear_solver" = "ma57" } }',
    "output_file": 'options = { ipopt = { "ipopt.output_file" = "x.txt" } }',
    "option_file_name": 'options = { ipopt = { "ipopt.option_file_name" = "./evil.so" } }',
    "nested ipopt table": 'options = { ipopt = { ipopt = { hsllib = "./evil.so" } } }',
    "qpsol_options naming a file": 'solver = "sqpmethod"\noptions = { sqpmethod = { qpsol_options = { dump_in = true } } }',
    "jit": 'options = { ipopt = { jit = true, compiler = "shell" } }',
    "integrator evil": 'integrator = "evil"',
}
#: command lines that name a plugin or a file
HOSTILE_ARGS = {
    "--solver evil": ["--solver", "evil"],
    "--solver knitro (shipped, cannot load)": ["--solver", "knitro"],
    "hsllib": ["--option", "ipopt.linear_solver=ma27", "--option", "ipopt.hsllib=./evil.so"],
    "pardisolib": ["--option", "ipopt.linear_solver=pardiso", "--option", "ipopt.pardisolib=./evil.so"],
    "qpsol evil": ["--solver", "sqpmethod", "--option", "qpsol=evil"],
    "linsol evil": ["--solver", "blocksqp", "--option", "linsol=evil"],
    "output_file": ["--option", "ipopt.output_file=x.txt"],
    "integrator evil": ["--integrator", "evil"],
}


@pytest.fixture
def hostile(tmp_path, monkeypatch):
    """(working folder, suite folder, marker): the marking library under every name of NAMES in both
    folders, the working folder entered."""
    if shutil.which("cc") is None:
        pytest.skip("no C compiler (cc) to build the marking library")
    marker = tmp_path / "MARKER"
    source = tmp_path / "mark.c"
    source.write_text(MARKING)
    library = tmp_path / "mark.so"
    subprocess.run(["cc", "-shared", "-fPIC", f'-DMARKER="{marker}"', "-o", str(library), str(source)], check=True)
    folders = tmp_path / "cwd", tmp_path / "suites"
    for folder in folders:
        folder.mkdir()
        for name in NAMES:
            shutil.copy(library, folder / name)
    monkeypatch.chdir(folders[0])
    return folders[0], folders[1], marker


def test_the_marking_library_marks(hostile):
    """The probe itself works: opened by path, the library writes the marker."""
    import ctypes

    cwd, _, marker = hostile
    ctypes.CDLL(str(cwd / "libcasadi_nlpsol_evil.so"))
    assert marker.read_text() == "loaded\n"


@pytest.mark.parametrize("solver, opts", [
    ("evil", {}), ("knitro", {}), ("sqpmethod", {"qpsol": "evil"}), ("blocksqp", {"linsol": "evil"}),
    ("blocksqp", {"linsol": "ma27"}), ("ipopt", {"ipopt.linear_solver": "ma27", "ipopt.hsllib": "./evil.so"}),
    ("ipopt", {"ipopt.linear_solver": "pardiso", "ipopt.pardisolib": "./evil.so"}),
    ("ipopt", {"ipopt.linear_solver": "ma57"}), ("ipopt", {"ipopt.output_file": "x.txt"}),
])
def test_ocp_solve_refuses_before_loading(hostile, solver, opts):
    _, _, marker = hostile
    with pytest.raises(InputError):
        ocp.solve(ocp.swing_up(1.0), ocp.MultipleShooting(N=10), solver=solver, options=opts, search=False)
    assert not marker.exists()


def test_a_default_that_names_an_unloadable_plugin_never_searches_the_working_folder(hostile):
    """blockSQP's default linear solver is HSL's MA27, shipped as a plugin that cannot load (no
    libhsl): CasADi's search falls through to "./libcasadi_linsol_ma27.so", here the marking
    library. Inside `solvers.loading` the working folder is ocp's private empty one: every start is
    a solver error saying MA27 is missing, as without the hostile folder, and nothing is loaded."""
    cwd, _, marker = hostile
    sol = ocp.solve(ocp.swing_up(1.0), ocp.MultipleShooting(N=10), solver="blocksqp", search=False)
    assert sol.direct.starts and all("ma27" in s.solver_message for s in sol.direct.starts)
    assert not marker.exists()
    import os
    assert os.getcwd() == str(cwd)                      # the working folder is restored


@pytest.mark.parametrize("name", list(HOSTILE_METHODS))
def test_a_hostile_suite_file_is_one_line_and_loads_nothing(hostile, name, capsys):
    _, folder, marker = hostile
    path = folder / "hostile.toml"
    path.write_text(SUITE.format(method=HOSTILE_METHODS[name]))
    assert cli.main(["bench", str(path), "--store", str(folder / "s.sqlite"), "--yes"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error:"), err
    assert not marker.exists()


@pytest.mark.parametrize("name", list(HOSTILE_ARGS))
def test_a_hostile_command_line_is_one_line_and_loads_nothing(hostile, name, capsys):
    _, _, marker = hostile
    argv = ["solve", "swing-up", "--kappa", "1", "--direct", "--N", "10", "--no-refine", *HOSTILE_ARGS[name]]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error:"), err
    assert not marker.exists()


def test_python_m_ocp_cli_solve_with_an_evil_solver_loads_nothing(hostile):
    """The command line as a user runs it, in the hostile working folder: exit 2, one line."""
    _, _, marker = hostile
    proc = subprocess.run([sys.executable, "-m", "ocp.cli", "solve", "swing-up", "--kappa", "1", "--direct",
                           "--solver", "evil"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and proc.stderr.startswith("error:"), proc.stderr
    assert not marker.exists()


def test_every_option_the_fair_configurations_and_the_suites_use_is_on_the_allow_list():
    for solver, (opts, _) in configurations.FAIR.items():
        assert options.checked(opts, solver=solver) == opts
    for name in suite._named():
        assert suite.load(name).pairs()           # every method's options checked on loading


def test_integer_options_take_integers_and_numbers_are_finite():
    for value in (1.5, True, "3", float("nan")):
        with pytest.raises(InputError, match="ipopt.max_iter"):
            options.checked({"ipopt.max_iter": value})
    for value in (float("inf"), float("nan"), 0.0, -1e-8, "1e-8", False):
        with pytest.raises(InputError, match="ipopt.tol"):
            options.checked({"ipopt.tol": value})
    assert options.checked({"ipopt.max_iter": 3, "ipopt.tol": 1}) == {"ipopt.max_iter": 3, "ipopt.tol": 1.0}
    assert options.checked({"ipopt.hsllib": "x"}, trusted=True) == {"ipopt.hsllib": "x"}     # --allow-unsafe-options


def test_plugin_names_come_from_casadis_own_folder():
    """What the allow-lists offer is shipped in CasADi's folder and loads from there; the plugins
    shipped that need a missing library (MA27's libhsl, KNITRO's...) are not offered."""
    import os

    for kind, names in solvers.PLUGINS.items():
        for name in names:
            if solvers.available(kind, name):
                assert os.path.isfile(os.path.join(solvers.folder(), f"libcasadi_{kind}_{name}.so"))
    assert not solvers.available("linsol", "ma27") and not solvers.available("nlpsol", "evil")
    assert {"ipopt", "fatrop", "sqpmethod", "blocksqp"} <= set(solvers.available_solvers())


def test_the_plugins_a_solver_loads_by_default_are_loadable_but_one():
    """The defaults of `uses` all load from CasADi's folder, except blockSQP's MA27 (libhsl is not
    shipped): the one default that `solvers.loading` alone keeps from the working folder
    (test_a_default_that_names_an_unloadable_plugin_never_searches_the_working_folder)."""
    missing = {(name, kind, plugin) for name, entry in solvers.SOLVERS.items() if solvers.available("nlpsol", name)
               for kind, plugin in entry.uses.items() if not solvers.available(kind, plugin)}
    assert missing == {("blocksqp", "linsol", "ma27")}


@pytest.mark.parametrize("solver", solvers.available_solvers())
def test_every_allowed_option_is_one_its_solver_accepts(solver):
    """Each option on the allow-list, at a sample value of its type, builds (casadi.nlpsol rejects
    an option it does not know): the lists name real options."""
    from ocp.direct.nlp import build

    entry = solvers.SOLVERS[solver]
    sample = {key: kind.example() for key, kind in entry.options.items()}
    if solver == "scpgen":                       # its build fails on this NLP whatever the options
        pytest.skip("scpgen cannot build this NLP (CasADi: its own error), whatever the options")
    build(ocp.MultipleShooting(N=5), solver, options.checked(sample, solver=solver))


def test_a_solver_the_wheel_ships_is_one_entry(monkeypatch, capsys):
    """Uno is shipped (libcasadi_nlpsol_uno.so) but not declared: refused; one entry of SOLVERS
    makes it a solver of ocp (available, named in the command line's help, its options checked,
    its NLP built)."""
    from ocp.cli import main
    from ocp.direct.nlp import build

    with pytest.raises(InputError, match="not an NLP solver ocp knows"):
        options.checked({}, solver="uno")
    monkeypatch.setitem(solvers.SOLVERS, "uno", solvers.Solver())
    assert "uno" in solvers.available_solvers()
    for command in (["solve", "--help"], ["failure-map", "--help"]):
        assert main(command) == 0 and "uno" in " ".join(capsys.readouterr().out.split())
    with pytest.raises(InputError, match="expand"):
        options.checked({"expand": 1}, solver="uno")
    assert build(ocp.MultipleShooting(N=5), "uno", options.checked({"expand": True}, solver="uno")).n_w > 0


@pytest.mark.parametrize("qp", [name for name in solvers.CONICS if solvers.available("conic", name)])
def test_every_allowed_qp_option_is_one_its_qp_solver_accepts(qp):
    """As above for the QP solvers of sqpmethod: each one's options, at sample values, build."""
    from ocp.direct.nlp import build

    sample = {"qpsol": qp, "qpsol_options": solvers.Table(solvers.CONICS[qp].fields).example()}
    build(ocp.MultipleShooting(N=5), "sqpmethod", options.checked(sample, solver="sqpmethod"))
