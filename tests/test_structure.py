"""Reading the switching structure off a piecewise-constant control (synthetic controls whose exact
reading is known by construction)."""

import numpy as np
import pytest

from ocp.core import simulate
from ocp.direct import structure

KAPPA = 1.0


def _read(u, T=1.0):
    t = np.linspace(0.0, T, len(u) + 1)
    x = simulate.piecewise((0.0, 0.0), t, u, KAPPA)
    return structure.read(t, x, u, KAPPA), t


def test_switch_inside_an_interval_is_located_by_the_control_average():
    # +1 for 4 intervals, then 0.5 (three quarters of the interval at +1), then -1
    s, t = _read(np.array([1, 1, 1, 1, 0.5, -1, -1, -1.0]))
    h = t[1]
    assert s.n_switches == 1 and s.first_u == 1 and s.arc_signs == (1, -1) and s.bang_bang
    assert s.switch_times[0] == pytest.approx(4 * h + 0.75 * h, abs=1e-15)
    # the state at the switch is that of the bang-bang reading: +1 from the start until the switch
    exact = simulate.flow((0.0, 0.0), 1.0, 4.75 * h, KAPPA)
    assert np.allclose(s.switch_states[0], exact, atol=1e-11)


def test_switch_on_a_node_and_two_switches():
    s, t = _read(np.array([-1, -1, 1, 1, 1, -1.0]))
    assert s.n_switches == 2 and s.first_u == -1 and s.arc_signs == (-1, 1, -1)
    assert s.switch_times == pytest.approx((t[2], t[5]), abs=1e-15)


def test_pulse_between_arcs_of_one_sign_counts_two_switches():
    s, t = _read(np.array([1, 1, 0.0, 1, 1.0]))
    h = t[1]
    assert s.arc_signs == (1, -1, 1)
    assert s.switch_times == pytest.approx((2.25 * h, 2.75 * h), abs=1e-15)


def test_interior_run_is_not_bang_bang():
    s, _ = _read(np.array([1, 0.2, -0.3, 0.1, -1.0]))
    assert not s.bang_bang and s.longest_interior_run == 3


def test_leading_interior_interval_is_a_switch_near_the_start():
    s, t = _read(np.array([0.0, -1, -1, -1.0]))
    assert s.arc_signs == (1, -1) and s.switch_times[0] == pytest.approx(0.5 * t[1], abs=1e-15)
