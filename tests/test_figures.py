"""`ocp figures`: the data behind every figure, and the files (written, not empty, same bytes twice)."""

import json
import math
import re
from fractions import Fraction

import matplotlib.pyplot as plt
import numpy as np
import pytest

from ocp import cli, figures
from ocp.core import model, plotting
from ocp.papers import references, verify
from ocp.bench.store import Store
from ocp.figures import FIGURES, batista, finch, ticks, vibrating_pivot, write
from ocp.scenes import falling, kapitza

PRINTED = references.load("finch2015")


def _agrees(key, value, accuracy):
    """The printed (truncated) number `key` of Finch 2015 is what `value` +- `accuracy` shows."""
    return verify.compare(PRINTED[key], value, accuracy)[2] == "agrees"


@pytest.fixture(scope="module")
def portraits():
    return {"finch-fig1": finch.figure1(), "finch-fig2": finch.figure2(), "finch-kappa-3-4": finch.three_quarters()}


@pytest.fixture(scope="module")
def data(portraits):
    """The data of every paper figure (the chart at a coarse resolution, to keep the tests fast)."""
    return {**portraits, "batista-fig1": batista.figure1(), "pivot-histories": vibrating_pivot.histories(),
            "pivot-chart": vibrating_pivot.stability_chart(n=12, n_upper=6)}


def _ends(traj):
    return traj.arcs[0][1][0], traj.arcs[-1][1][-1]


@pytest.mark.parametrize("name, kappa, structures, index", [
    ("finch-fig1", 1.0, [(1, -1)], 0), ("finch-fig2", 0.5, [(-1, 1, -1)], 0),
    ("finch-kappa-3-4", 0.75, [(-1, 1, -1), (1, -1)], 0), ("finch-kappa-3-4", 0.75, [(-1, 1, -1), (1, -1)], 1)])
def test_portrait_trajectories(portraits, name, kappa, structures, index):
    """Certified extremals from (0, 0) to (pi, 0), re-simulated; switch markers at Finch's formulas
    to the certified accuracy; T as the formulas give it, within the search's error estimate plus
    the formula's bound (nothing added: the estimates must cover the difference)."""
    d = portraits[name]
    assert d["kappa"] == kappa
    assert [t.signs for t in d["trajectories"]] == structures
    traj = d["trajectories"][index]
    assert traj.certified
    start, end = _ends(traj)
    assert np.allclose(start, (0, 0), atol=0) and np.allclose(end, (math.pi, 0), atol=1e-8)
    for (u, a), (_, b) in zip(traj.arcs, traj.arcs[1:]):
        assert np.allclose(a[-1], b[0], atol=0)                  # arcs join at the switches
    assert np.allclose([a[-1] for _, a in traj.arcs[:-1]], traj.switch_states, atol=1e-8)
    assert 0 < traj.state_error < 1e-8
    bb = traj.analytic
    assert np.max(np.abs(np.array(bb.switch_states) - traj.switch_states)) <= traj.state_error + bb.error
    assert abs(traj.T - bb.T) <= traj.T_error + bb.error


def test_portrait_markers_against_the_captions(portraits):
    """The switch markers show the points printed in the captions of Finch's Figures 1 and 2."""
    fig1 = portraits["finch-fig1"]["trajectories"][0]
    (s,) = fig1.switch_states
    e = fig1.state_error
    assert _agrees("figure1_switch_theta", s[0], e) and _agrees("figure1_switch_omega", s[1], e)
    fig2 = portraits["finch-fig2"]["trajectories"][0]
    (s1, s2), e = fig2.switch_states, fig2.state_error
    assert _agrees("figure2_switch1_theta", s1[0], e) and _agrees("figure2_switch1_omega", s1[1], e)
    assert _agrees("figure2_switch2_theta", s2[0], e) and _agrees("figure2_switch2_omega", s2[1], e)
    two, one = portraits["finch-kappa-3-4"]["trajectories"]
    assert _agrees("t_inf_one_switch_kappa_3_4", one.T, one.T_error)
    assert _agrees("two_switch_3_4_theta1", two.switch_states[0][0], two.state_error)
    assert _agrees("two_switch_3_4_theta2", two.switch_states[1][0], two.state_error)


@pytest.mark.parametrize("name", ["finch-fig1", "finch-fig2", "finch-kappa-3-4"])
def test_portrait_context(portraits, name):
    """Separatrix omega = 2 cos(theta/2) (through (0, 2) and (pi, 0)); the arcs into the target
    end at (pi, 0) from the right sides and keep their arc invariant; equilibria at 0 and pi."""
    d = portraits[name]
    theta, omega = d["separatrix"]
    assert np.allclose(omega, 2 * np.abs(np.cos(theta / 2)), atol=1e-7)
    assert theta[0] == finch.XLIM[0] and theta[-1] == finch.XLIM[1]
    for u, side in ((-1, -1), (+1, 1)):
        th, om = d["target_arcs"][u]
        end = 0 if side > 0 else -1
        assert th[end] == pytest.approx(math.pi) and om[end] == pytest.approx(0, abs=1e-7)
        assert np.all(side * (th - math.pi) >= 0) and np.all(-side * om >= 0)
        invariant = model.arc_invariant((th, om), u, d["kappa"])
        assert np.allclose(invariant, model.arc_invariant((math.pi, 0.0), u, d["kappa"]), atol=1e-12)
    assert d["equilibria"] == {"stable": [(0.0, 0.0)], "unstable": [(-math.pi, 0.0), (math.pi, 0.0)]}


def test_labels_print_only_defended_digits():
    assert finch._fmt(2.5707963267954494, 1e-10) == "2.5708"
    assert finch._fmt(-0.39469300797734286, 3e-3) == "−0.395"      # down to the error's leading digit
    assert [ticks.pi_label(Fraction(k, 2)) for k in (-2, -1, 0, 1, 3, 4)] == ["−π", "−π/2", "0", "π/2", "3π/2", "2π"]
    assert ticks.pi_label(Fraction(3, 8)) == "3π/8"


def test_batista_figure1(data):
    d = data["batista-fig1"]
    assert d["theta0"][0] > 0 and d["theta0"][-1] == falling.GROUND
    # I(pi/2) = 0; the float pi/2 lies 6.1e-17 below pi/2, where I = 2 sqrt(6.1e-17) = 1.565e-8
    assert d["I"][-1] == pytest.approx(1.565e-8, rel=1e-3)
    assert np.all(np.diff(d["I"]) < 0)                                    # I falls from inf to 0
    assert abs(d["I"][0] - d["asymptotic18"][0]) < 1e-4 * d["I"][0]       # (18) is its asymptote
    computed = np.interp(np.log(d["table2_theta0"]), np.log(d["small"]), d["relative_error"])
    assert np.allclose(computed, d["table2_relative_error"], rtol=0.05)   # Table 2 on the curve


def test_pivot_histories(data):
    """Weinstein's Fig. 4 is captioned stable and is unstable in both readings; it falls."""
    d = data["pivot-histories"]
    assert set(d) == {"tam_fig3", "weinstein_fig4_rad_s", "weinstein_fig4_2pi", "weinstein_fig5_rad_s",
                      "weinstein_fig5_2pi"}
    for name, case in d.items():
        assert case["t"][0] == 0 and case["t"][-1] == pytest.approx(2.0) and case["theta"][0] == 0.1
        falls = np.max(np.abs(case["theta"])) > math.pi / 2
        assert falls == (case["floquet"] < 0) and (case["max_abs_mu"] > 1 + 1e-6) == falls
    assert [d[f"weinstein_fig4_{r}"]["printed"] for r in kapitza.READINGS] == [1, 1]
    assert [d[f"weinstein_fig4_{r}"]["floquet"] for r in kapitza.READINGS] == [-1, -1]
    assert d["tam_fig3"]["floquet"] == 1 and d["weinstein_fig5_rad_s"]["printed"] == -1


def test_pivot_chart(data):
    d = data["pivot-chart"]
    assert np.all(d["floquet_lower"] > d["tam"])                          # Tam's criterion is far too lenient
    small = d["A"] / d["l"] < 0.01
    assert np.allclose(d["floquet_lower"][small], d["kapitza"][small], rtol=1e-3)   # Kapitza: the small-A limit
    assert np.all(np.isinf(d["upper"][:1])) and np.all(np.isfinite(d["upper"][1:]))
    omegas = sorted(p["omega"] for p in d["points"].values())
    assert omegas == pytest.approx([20, 40 * math.pi, 200, 400 * math.pi, 2000])
    assert all(p["floquet"] == kapitza.stability(kapitza.A, p["omega"]) for p in d["points"].values())


#: the figures of the papers (the synthesis maps are drawn and checked in tests/test_synthesis.py, the
#: failure maps in tests/test_failure_map.py)
PAPER_FIGURES = [n for n, f in FIGURES.items() if not f.from_store and not n.startswith(("synthesis-", "failure-map-"))]


def test_files_written_and_reproducible(data, tmp_path):
    """Each paper figure as PNG and PDF, not empty, the same bytes when drawn again."""
    assert set(PAPER_FIGURES) == set(data)
    for name in PAPER_FIGURES:
        first = FIGURES[name].write(data[name], tmp_path / "a" / name, ("png", "pdf"))
        again = FIGURES[name].write(data[name], tmp_path / "b" / name, ("png", "pdf"))
        assert [p.suffix for p in first] == [".png", ".pdf"]
        for p, q in zip(first, again):
            assert p.stat().st_size > 1000 and p.read_bytes() == q.read_bytes(), p


def _store(path):
    """A tiny synthetic results store: two cases, two method families at two N."""
    store = Store(path)
    session = store.open_session("tiny", "test", {})
    for case in ("swing-up kappa=1", "damping kappa=1"):
        for family, speed in (("MS rk4 M=4 / ipopt", 1.0), ("DC radau3 / ipopt", 2.0)):
            for N in (25, 50):
                record = {"case": case, "case_label": case, "problem": case, "family": family, "label": family,
                          "N": N, "guess": "default", "outcome": "ok", "status": "verified", "success": True,
                          "T": 4.0 + 10.0 / N**2, "T_error": None, "T_ref": 4.0, "T_ref_error": None,
                          "total_time_s": speed * N / 100, "T_minus_ref": 10.0 / N**2, "timing": {"note": "timed alone"}}
                store.add_result(case, json.dumps([family, N]), session, record)
    store.close()
    return path


def test_command_line(tmp_path, capsys):
    """`ocp figures`: same bytes on a re-run, the store figures from a store (skipped without one),
    one-line errors with exit status 2."""
    store = _store(tmp_path / "tiny.sqlite")
    args = ["figures", "--only", "batista-fig1", "--only", "work-precision", "--only", "profiles", "--store", str(store)]
    assert cli.main(args + ["--out", str(tmp_path / "a")]) == 0
    progress = [line for line in capsys.readouterr().err.splitlines()   # a line per figure, its time when done
                if not re.fullmatch(r"\[\d/3\] [a-z0-9-]+: running: \d+ s", line)]   # (and the heartbeat of a slow one)
    assert [re.fullmatch(r"\[(\d)/3\] ([a-z0-9-]+): \d+\.\d s", line).group(2) for line in progress] == \
        ["batista-fig1", "work-precision", "profiles"]
    assert cli.main(args + ["--out", str(tmp_path / "b")]) == 0
    files = sorted(p.name for p in (tmp_path / "a").iterdir())
    assert "batista-fig1.png" in files and "profile_time.pdf" in files and "profile_accuracy.png" in files
    assert sum(name.startswith("work_precision_") for name in files) == 4          # 2 cases, png + pdf
    for name in files:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name
    capsys.readouterr()
    for bad, accepted in ((["--only", "fig9"], "finch-fig1"), (["--only", "batista-fig1", "--format", "gif"], "svg"),
                          (["--only", "profiles", "--store", str(tmp_path / "none.sqlite")], "ocp bench")):
        assert cli.main(["figures", "--out", str(tmp_path / "c")] + bad) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and accepted in err and "Traceback" not in err


def test_store_figures_skipped_without_a_store(tmp_path, monkeypatch):
    """Without --only, the figures that need a store are skipped, with the reason, when there is none."""
    monkeypatch.setattr(figures, "FIGURES", {n: f for n, f in FIGURES.items() if n == "batista-fig1" or f.from_store})
    out = write(tmp_path, None, ("png",), store=tmp_path / "none.sqlite")
    assert [p.name for p in out["batista-fig1"]] == ["batista-fig1.png"]
    assert out["work-precision"].startswith("skipped: no results store") and out["profiles"].startswith("skipped")


@pytest.fixture(scope="module")
def near_kappa_1():
    """Maps of a small window around where kappa_1 = 0.800028 (swing-up, circle) gives birth to two
    switches (its stored attaining state (0.142, 0.396) and the mirror image), just below and above."""
    from ocp.synthesis.field import Window, synthesize
    window = Window(-0.6, 0.6, -0.8, 0.8, 241, 161)
    return {k: synthesize("swing-up", k, "circle", window, 8.0) for k in (0.79, 0.81)}


def test_a_region_born_at_a_bifurcation_value_is_found_and_said(near_kappa_1):
    """Below kappa_1 the two-switch region near the state is found (its cells inside the zoom, their
    number the map's own count near the state); above it there is none, and the zoom says so."""
    from ocp.figures.synthesis import born_regions, draw_map
    below, above = (born_regions(near_kappa_1[k]) for k in (0.79, 0.81))
    assert len(below) == len(above) == 1 and below[0].switches == above[0].switches == 2
    b, s = below[0], near_kappa_1[0.79]
    theta, omega = np.meshgrid(s.window.theta, s.window.omega, indexing="ij")
    zoomed = (theta >= b.zoom[0]) & (theta <= b.zoom[1]) & (omega >= b.zoom[2]) & (omega <= b.zoom[3])
    assert 0 < b.cells <= np.count_nonzero((s.N == 2) & zoomed) and b.area > 0
    assert b.zoom[0] <= b.state[0] <= b.zoom[1] and b.zoom[2] <= b.state[1] <= b.zoom[3]
    assert above[0].cells == 0 and "no cell with N = 2 at the state" in above[0].describe()
    titles = []
    with plotting.style():
        for k in (0.79, 0.81):
            fig = draw_map(near_kappa_1[k])
            titles.append(fig.axes[-1].get_title())
            plt.close(fig)
    assert "below κ_1" in titles[0] and f"{b.cells} cells" in titles[0]
    assert "above κ_1" in titles[1] and "no cell" in titles[1]
    # the zoom drawn from its own finer synthesis (as `map_data` gives it): the same region, more cells
    from ocp.figures.synthesis import ZOOM_GRID
    from ocp.synthesis.field import Window, synthesize
    fine = synthesize("swing-up", 0.79, "circle", Window(*b.zoom, *ZOOM_GRID), 8.0)
    with plotting.style():
        fig = draw_map(s, (fine,))
        title = fig.axes[-1].get_title()
        plt.close(fig)
    cells = int(re.search(r"N = 2 at the state: (\d+) cells", title).group(1))
    assert cells > b.cells and cells * np.prod(fine.window.steps) == pytest.approx(b.area, rel=0.5)
