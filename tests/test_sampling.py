"""`Solution.sample` and `ocp solve --sample/--csv/--plot`: the trajectory of the answer at any times,
checked against what the search computed independently (its switch states, from the Taylor
integration), against the maximum principle (p2 = 0 at the switches, H = 0 along the arcs), and
the CSV re-simulated from its own control column by an integrator the sampling does not use
(scipy's Radau)."""

import csv
import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import ocp
from ocp.cli import main
from ocp.core import model
from ocp.core.errors import InputError
from ocp.core.simulate import piecewise
from ocp.result import Source, sample_direct


@pytest.fixture(scope="module")
def sol():
    return ocp.solve(ocp.swing_up(0.75), ocp.MultipleShooting(N=60))


def test_the_samples_pass_through_the_switch_states_of_the_search(sol):
    """The search's switch states come from its Taylor integration; the samples from DOP853 arc by arc."""
    s = sol.sample(t=sol.switch_times)
    found = np.array(sol.best.switch_states)
    assert np.abs(np.c_[s.theta, s.omega] - found).max() <= s.state_error
    assert s.state_error < 1e-9 and s.miss < 1e-10 and sol.best.source is Source.SEARCH


def test_the_costate_obeys_the_maximum_principle(sol):
    s = sol.sample(every=0.05)
    H = [model.hamiltonian((th, om), (p1, p2), u, sol.problem.kappa)
         for th, om, u, p1, p2 in zip(s.theta, s.omega, s.u, s.p1, s.p2)]
    assert max(map(abs, H)) <= 10 * s.costate_error                 # H = p . f - 1 = 0 (free final time)
    at = sol.sample(t=sol.switch_times)
    assert np.abs(at.p2).max() <= 10 * at.costate_error             # the switching function vanishes
    inside = ~np.isin(s.t, sol.switch_times)
    assert np.all(s.u[inside] * s.p2[inside] > 0)                  # u = sign(p2) on every arc


def test_samples_at_any_times_in_any_order(sol):
    t = np.array([sol.T, 0.0, 1.5, sol.switch_times[0]])
    s = sol.sample(t)
    assert list(s.t) == list(t) and (s.theta[1], s.omega[1]) == sol.problem.x0
    assert np.hypot(s.theta[0] - math.pi, s.omega[0]) <= s.miss + s.state_error
    assert s.u[3] == sol.best.arc_signs[1]                        # right-continuous at a switch
    for bad in (dict(t=[-0.1]), dict(t=[sol.T + 1e-3]), dict(), dict(t=[1.0], every=0.1), dict(every=0.0)):
        with pytest.raises(InputError):
            sol.sample(**bad)


def test_a_direct_answer_is_sampled_on_its_own_grid(sol):
    """At the nodes: the direct control re-simulated node by node (`ocp.core.simulate`), no costate."""
    d = sol.direct
    s = sample_direct(sol.problem, d, t=d.t)
    nodes = piecewise(sol.problem.x0, d.t, d.u, sol.problem.kappa)
    assert np.abs(np.c_[s.theta, s.omega] - nodes).max() < 1e-9
    assert s.p1 is None and s.p2 is None and s.costate_error is None
    assert s.miss == pytest.approx(d.resim_miss, rel=1e-3, abs=1e-12)
    alone = ocp.solve(ocp.swing_up(0.75), ocp.MultipleShooting(N=60), search=False)
    assert alone.best.source is Source.DIRECT and alone.sample(every=0.5).p1 is None


def test_a_failed_solve_has_nothing_to_sample():
    failed = ocp.solve(ocp.swing_up(1.0), ocp.MultipleShooting(N=8, M=1), options={"ipopt.max_iter": 1}, search=False)
    with pytest.raises(InputError, match="no answer"):
        failed.sample(every=0.1)


def _resimulated(rows, kappa):
    """The end state of the CSV's control (each row's u held until the next row's t) from its first
    state, by Radau, runs of equal u merged into arcs."""
    t = np.array([float(r["t"]) for r in rows])
    u = np.array([float(r["u"]) for r in rows])
    x = np.array([float(rows[0]["theta"]), float(rows[0]["omega"])])
    starts = [k for k in range(len(rows) - 1) if k == 0 or u[k] != u[k - 1]] + [len(rows) - 1]
    for a, b in zip(starts[:-1], starts[1:]):
        x = solve_ivp(lambda _, y, v=u[a]: [y[1], kappa * v - math.sin(y[0])], (t[a], t[b]), x, method="Radau",
                      rtol=1e-13, atol=1e-13).y[:, -1]
    return x


def test_the_csv_resimulated_from_its_control_lands_on_the_target(tmp_path, capsys):
    """The issue's acceptance: `ocp solve swing-up --kappa 0.75 --sample 0.01 --csv out.csv --plot
    out.png` writes both; the CSV's control lands on (pi, 0) within the accuracy the samples state."""
    out, png = tmp_path / "out.csv", tmp_path / "out.png"
    code = main(["solve", "swing-up", "--kappa", "0.75", "--sample", "0.01", "--csv", str(out), "--plot", str(png),
                 "--json"])
    assert code == 0
    stated = json.loads(capsys.readouterr().out)["samples"]
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["t", "theta", "omega", "u", "p1", "p2"] and len(rows) == len(stated["t"])
    assert float(rows[-1]["t"]) == stated["t"][-1] and len(rows) >= 5.8 / 0.01
    end = _resimulated(rows, 0.75)
    assert math.hypot(end[0] - math.pi, end[1]) <= stated["miss"] + stated["state_error"]


def test_the_export_flags_go_together(capsys):
    for args, says in ((["--csv", "x.csv"], "--sample"), (["--sample", "0.01"], "--csv"),
                       (["--plot", "x.jpeg"], ".png"), (["--sample", "0", "--json"], "sample")):
        assert main(["solve", "swing-up", "--kappa", "1", *args]) == 2
        assert says in capsys.readouterr().err


def test_statuses_print_their_names(sol):
    assert str(sol.status) == "optimal" and f"{sol.status}" == "optimal" and sol.status == 0
    assert sol.status.message == sol.message and str(sol.direct_class) == "optimum"
