"""Failure maps (issue 15): each cell is the bench's own row (the search's reference, the direct solve,
the outcome class), so a cell agrees with `ocp.solve` with the same direct method; the map is
stored whole and drawn; bad input to `ocp failure-map` is one line, exit 2."""

import json

import numpy as np
import pytest

import ocp
from ocp import cli, direct
from ocp.bench import failure_map, suite
from ocp.synthesis.field import Window

METHOD = suite.Method(settings=(("N", 25),))


@pytest.fixture(scope="module")
def tiny():
    """A 3 x 3 grid of starts at kappa = 1: theta in {-3, 0, 3}, omega in {-2, 0, 2}."""
    return failure_map.grid("swing-up", 1.0, METHOD, Window(-3.0, 3.0, -2.0, 2.0, 3, 3))


@pytest.mark.parametrize("i, j", [(1, 1), (0, 2)])
def test_a_cell_agrees_with_ocp_solve(tiny, i, j):
    start = (float(tiny.axes["theta"][i]), float(tiny.axes["omega"][j]))
    sol = ocp.solve(ocp.swing_up(1.0, start), direct.MultipleShooting(N=25))
    expected = "ok" if sol.direct_class.name == "OPTIMUM" else sol.direct_class.name.lower().replace("_", " ")
    assert failure_map.OUTCOMES[tiny.outcome[i, j]] == expected
    assert tiny.T[i, j] == pytest.approx(sol.direct.T, abs=1e-12) and tiny.T_ref[i, j] == pytest.approx(sol.T, abs=1e-9)
    assert (tiny.reason[i, j] == "") == (expected == "ok")


def test_the_map_is_stored_and_drawn(tiny, tmp_path):
    from ocp.core import plotting
    from ocp.figures.failure_map import draw_grid
    from ocp.synthesis.field import synthesize

    path = failure_map.save(tiny, tmp_path / f"{failure_map.name(tiny)}.npz")
    with np.load(path) as saved:
        assert (saved["outcome"] == tiny.outcome).all() and json.loads(str(saved["meta"]))["method"] == METHOD.to_dict()
    assert sum(tiny.counts().values()) == 9 and failure_map.summary(tiny)["axes"]["theta"] == [-3.0, 3.0, 3]
    s = synthesize("swing-up", 1.0, "circle", Window(-3.0, 3.0, -2.0, 2.0, 61, 41), 8.0)
    with plotting.style():
        assert plotting.save(draw_grid(tiny, s), tmp_path / "map", ("png",))[0].stat().st_size > 0


def test_a_sweep_over_kappa_from_the_command_line(tmp_path, capsys):
    assert cli.main(["failure-map", "swing-up", "--kappa", "0.9", "1.1", "--sweep", "2", "--out", str(tmp_path),
                     "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["axes"] == {"kappa": [0.9, 1.1, 2]} and sum(out["outcomes"].values()) == 2
    assert sorted(p.rsplit(".", 1)[-1] for p in out["files"]) == ["npz", "png"]
    assert all((tmp_path / p.rsplit("/", 1)[-1]).stat().st_size > 0 for p in out["files"])


@pytest.mark.parametrize("argv, words", [
    (["--kappa", "1", "--grid", "1", "5"], "grid = '1'"),
    (["--kappa", "0.5", "1"], "kappa: one value"),
    (["--kappa", "1", "0.5", "--sweep", "5"], "LO < HI"),
    (["--kappa", "1", "--x0", "0", "0"], "--x0 is the start of a sweep"),
    (["--kappa", "1", "--configuration", "tuned"], "configuration = 'tuned'"),
    (["--kappa", "1", "--solver", "alpaqa", "--configuration", "fair"], "no fair configuration"),
    (["--kappa", "1", "--window", "3", "-3", "0", "1"], "window"),
    (["--kappa", "nan"], "kappa"),
])
def test_bad_input_is_one_line_and_exit_2(argv, words, tmp_path, capsys):
    assert cli.main(["failure-map", "swing-up", *argv, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and "Traceback" not in err, err
    assert not any(tmp_path.iterdir())


def test_one_colour_per_meaning_and_the_seam_drawn_once():
    """Issue 21: every outcome has a colour of its own, shared with no switch count of the map under
    it; ok and inaccurate differ in colour and marker; a window spanning 2 pi draws theta = pi (the
    same start as -pi) once, and its legend counts each start once."""
    import math

    import matplotlib.pyplot as plt

    from ocp.bench.outcomes import Outcome
    from ocp.figures import failure_map as figure
    from ocp.figures.synthesis import COUNT_COLOURS

    colours = [o.colour.lower() for o in Outcome]
    assert len(set(colours)) == len(colours) and not set(colours) & {c.lower() for c in COUNT_COLOURS + ["#08306b"]}
    assert Outcome.OK.colour != Outcome.INACCURATE.colour and Outcome.OK.marker != Outcome.INACCURATE.marker
    theta = np.linspace(-math.pi, math.pi, 5)
    assert figure._once(theta) == 4 and figure._once(theta[:-1]) == 4
    outcome = np.array([[0, 0], [3, 3], [0, 3], [3, 0], [0, 0]])          # the last column repeats the first
    fig, ax = plt.subplots()
    x, y = np.meshgrid(theta[:4], [0.0, 1.0], indexing="ij")
    handles, labels = figure._cells(ax, outcome[:figure._once(theta)], x, y)
    plt.close(fig)
    assert labels == [f"{failure_map.OUTCOMES[0]} (4)", f"{failure_map.OUTCOMES[3]} (4)"]
    assert [h.get_marker() for h in handles] == [failure_map.OUTCOMES[0].marker, failure_map.OUTCOMES[3].marker]
