"""Fuzzing the NLP options of suite files (issue 18, items 5 and 7): every option key the registry
knows (`ocp.direct.solvers.SOLVERS`, nested QP options included), with values of any type, and
random keys, in a suite file read by `ocp bench`. The command ends with exit 2 and one line, or the
suite loads; an accepted option then builds its NLP, or its solver refuses it with an InputError:
never a traceback.

Hypothesis, derandomized and bounded (about 20 s): the same examples on every run.
"""

from hypothesis import given, settings, strategies as st
from test_fuzz import FUZZ, anything, assert_well_ended, call, stopped, toml  # noqa: F401  (stopped: a fixture)

import ocp
from ocp.bench import suite
from ocp.core.errors import InputError
from ocp.direct import solvers
from ocp.direct.nlp import build

AVAILABLE = solvers.available_solvers()
KEYS = sorted({(name, key) for name, entry in solvers.SOLVERS.items() for key in entry.fields}
              | {(name, f"qpsol_options.{key}") for name in ("sqpmethod", "feasiblesqpmethod")
                 for conic in solvers.CONICS.values() for key in conic.fields})


def options_of(key, value):
    """{key: value}, a dotted qpsol_options.KEY nested as its table."""
    head, _, tail = key.partition(".")
    return {head: {tail: value}} if head == "qpsol_options" else {key: value}


def example(solver, key):
    """A value of the declared type of `key` (that the allow-list accepts)."""
    entry = solvers.SOLVERS[solver]
    head, _, tail = key.partition(".")
    if head == "qpsol_options":
        return entry.fields[head].fields({}).get(tail, solvers.Flag()).example()
    return entry.fields[key].example()


option = st.one_of(
    st.sampled_from(KEYS).flatmap(lambda sk: st.tuples(st.just(sk[0]), st.just(sk[1]),
                                                       anything | st.just(example(*sk)))),
    st.tuples(st.sampled_from(sorted(solvers.SOLVERS)), st.text(max_size=12), anything))


@settings(FUZZ, max_examples=300)
@given(chosen=option)
def test_any_option_in_a_suite_file_ends_well(chosen, stopped, tmp_path):  # noqa: F811
    solver, key, value = chosen
    table = {solver: options_of(key, value)}
    path = tmp_path / "suite.toml"
    path.write_text(f'[[cases]]\nkind = "swing-up"\nkappa = 1.0\n\n[[methods]]\nN = 5\nsolver = "{solver}"\n'
                    f"options = {toml(table)}\n")
    code, _, err = call(["bench", str(path), "--store", str(tmp_path / "s.sqlite")])
    assert_well_ended(code, err)
    if code is None and solver in AVAILABLE:            # accepted: it builds, or its solver says no (one line)
        method = suite.load(path).methods[0]
        try:
            build(ocp.MultipleShooting(N=5), solver, method.applied)
        except InputError as err:
            assert "\n" not in str(err)
