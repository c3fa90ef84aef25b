"""The optimal synthesis maps and the bifurcation values (issue 14).

References: `ocp.solve` (the complete search of extremals from each state, tests/test_search.py)
for the maps; for the bifurcation value, a bracketing by the maps themselves (states with two
switches just below the value, none just above), an independent route to the value that does not
use its equations."""

import json
import math

import numpy as np
import pytest

from ocp.cli import main
from ocp.synthesis import bifurcation, results
from ocp.core.problem import make
from ocp.solving import solve
from ocp.synthesis.field import Window, check, synthesize


@pytest.mark.parametrize("kind, reading, kappa, window", [
    ("swing-up", "circle", 0.79, (-math.pi, math.pi, -3, 3)),
    ("damping", "circle", 0.9, (-math.pi, math.pi, -4, 4)),
    ("swing-up", "plane", 1.0, (-2 * math.pi, 3 * math.pi, -3, 3)),
    ("damping", "plane", 0.7, (-2 * math.pi, 2 * math.pi, -3, 3)),
])
def test_the_map_agrees_with_the_search_at_random_states(kind, reading, kappa, window):
    s = synthesize(kind, kappa, reading, Window(*window, 161, 101), 12.0)
    assert s.covered > 0.5 and s.unresolved == 0
    rows = check(s, count=6, seed=3)
    assert len(rows) == 6
    for theta, omega, V, N, T, n in rows:
        # the map interpolates the field linearly on triangles of a few cells: its error is of
        # the order of the cell size times the speed of the value (measured below 2e-3 here)
        assert abs(V - T) < 5e-3, (theta, omega)
        assert N == n, (theta, omega)


def test_the_value_is_bracketed_by_the_maps():
    """kappa_1 of the swing-up on the circle: the least-gap root (route at CHECK accuracy), and the
    maps just below it (states with two switches near the origin) and just above (none)."""
    kappa, psi, label = bifurcation.root_in_kappa("swing-up", "circle", 2, 0.795, 0.81, 2.47, 2.50,
                                                  accuracy=bifurcation.taylor.CHECK, xtol=1e-8, ktol=1e-9)
    assert label == ((1, -1), 1)
    window = Window(-0.6, 0.6, -0.8, 0.8, 241, 161)
    below = synthesize("swing-up", kappa - 0.004, "circle", window, 8.0)
    above = synthesize("swing-up", kappa + 0.004, "circle", window, 8.0)
    assert np.count_nonzero(below.N == 2) > 0 and np.count_nonzero(above.N >= 2) == 0


def test_the_stored_values_carry_their_provenance():
    rows = results.load(results.__file__.replace("results.py", "data/bifurcation.jsonl"))
    assert {"swing-up/circle/1", "swing-up/circle/2", "damping/circle/1"} <= set(rows)
    for row in rows.values():
        if row["reading"] == "plane":           # no value: the tongues' edges and the search's confirmations
            assert row["kappa"] is None and row["confirmed"] and row["commit"]
            for edge in row["edges"]:
                assert max(edge["routes"].values()) - min(edge["routes"].values()) <= edge["error"] < 0.1
            continue
        assert 0 < row["error"] < 1e-6 and row["commit"] and len(row["routes"]) >= 2
        assert max(row["routes"].values()) - min(row["routes"].values()) <= row["error"]


@pytest.mark.parametrize("argv, says", [
    (["synthesis", "pendulum", "--kappa", "1"], "swing-up, damping"),
    (["synthesis", "swing-up", "--kappa", "0"], "kappa"),
    (["synthesis", "swing-up", "--kappa", "1", "--grid", "5", "5"], "grid"),
    (["synthesis", "swing-up", "--kappa", "1", "--window", "1", "0", "-1", "1"], "window"),
    (["bifurcation", "--case", "swing-up/square/1"], "accepted"),
    (["bifurcation", "--case", "swing-up/circle/1", "--sweep", "s.jsonl"], "damping/circle/2"),
])
def test_bad_input_is_one_line_and_exit_2(argv, says, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err


def test_synthesis_command_writes_a_map_and_says_what_it_holds(tmp_path, capsys):
    argv = ["synthesis", "swing-up", "--kappa", "1", "--grid", "81", "61", "--horizon", "8", "--out", str(tmp_path),
            "--format", "png", "--json"]
    assert main(argv) == 0
    (out,) = json.loads(capsys.readouterr().out)
    assert out["max_switches"] == 1 and out["covered"] > 0.99
    assert all((tmp_path / f.rsplit("/", 1)[-1]).exists() for f in out["files"])


def test_a_strip_that_crosses_the_window_with_its_corners_outside_is_refined():
    """Swing-up, kappa = 0.31, a small window at high energy, horizon 40: the one-switch extremals
    through it span strips whose corners all lie outside it; they were never refined, and the window
    showed the slower extremals behind them (up to 7 switches, values up to 39.7 where ocp.solve
    finds one switch in about 17.8)."""
    s = synthesize("swing-up", 0.31, "circle", Window(1.3, 1.5, 6.1, 6.3, 21, 21), 40.0)
    assert np.all(np.isfinite(s.V)) and set(np.unique(s.N)) <= {0, 1}
    for i, j in [(4, 16), (16, 4)]:
        answer = solve(make("swing-up", 0.31, (float(s.window.theta[i]), float(s.window.omega[j]))))
        assert abs(s.V[i, j] - answer.T) <= 2e-3 and s.N[i, j] == answer.n_switches


def test_the_sweeps_above_the_fold_and_tie_values_are_complete_and_positive():
    # the stored sweeps (ocp bifurcation --case ID --sweep FILE) that make a fold-and-tie value kappa_n:
    # one row at every angle pi (i + 1/2) / angles, at the case's kappa, each crossed switch's gap positive
    swept = [c for c in results.cases() if getattr(c, "above", None) is not None]
    assert {c.id for c in swept} >= {"damping/circle/2", "damping/circle/3", "swing-up/circle/6", "swing-up/circle/7"}
    for case in swept:
        rows = results.sweep_rows(case)
        assert set(rows) == {math.pi * (i + 0.5) / case.angles for i in range(case.angles)}
        crossed = [r for r in rows.values() if r["crossed_and_found"]]
        assert crossed and all(r["kappa"] == case.above and r["G"] > 0 for r in crossed)
        assert all(r["s"] is None or r["s"] <= case.s_max for r in rows.values())


@pytest.mark.parametrize("kind, n, value, label, psi_lo, psi_hi", [
    # the swing-up's kappa_7 = 0.131030664919 +- 2e-12 (ocp bifurcation --case swing-up/circle/7: the fold-and-tie
    # equations at PRECISE and CHECK; docs/bifurcation-limits.md section 2b)
    ("swing-up", 7, 0.131030664919, ((1, -1, 1, -1, 1, -1, 1, -1), 1), 2.40, 2.43),
    # the damping's kappa_3 = 0.329196077600 +- 2e-12 (ocp bifurcation --case damping/circle/3 at commit 9c385af:
    # 0.32919607760035763 at PRECISE, 0.32919607760036423 at CHECK, the row in
    # docs/bifurcation-limits/damping-circle-3-value.jsonl; docs/bifurcation-limits.md section 2)
    ("damping", 3, 0.329196077600, ((1, -1, 1, -1), 1), 2.22, 2.34),
])
def test_a_fold_and_tie_value_ties_at_the_fold_of_its_switching_curve(kind, n, value, label, psi_lo, psi_hi):
    # at 1e-7 either side of kappa_n, at CHECK accuracy, the gap at the fold of the (n + 1)-th switching curve
    # against the competitor changes sign, and the fold is crossed on one side only (psi below it)
    from ocp.core.roots import brent

    signs = []
    for kappa in (value - 1e-7, value + 1e-7):
        fold = brent(lambda p: bifurcation.tangency(kind, kappa, p, n + 1, bifurcation.taylor.CHECK), psi_lo, psi_hi,
                     1e-13)
        signs.append(bifurcation.gap(kind, kappa, "circle", fold, n + 1, label, bifurcation.taylor.CHECK)[0])
        below, above = (math.prod(bifurcation.crossing(kind, kappa, fold + d, n + 1, bifurcation.taylor.CHECK))
                        for d in (-3e-3, 3e-3))
        assert below > 0 > above
    assert signs[0] < 0 < signs[1] and abs(signs[0]) < 1e-3
