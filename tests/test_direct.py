"""The direct multiple-shooting solve (issue 2) on the paper's cases, and its verification.

References: the values Finch (2015) prints, read from reference/finch2015.toml (key named in each
test), and where the paper prints no T or a wrong one, the exact two-switch solution of its
addendum (`ocp.analytic.two_switch`, checked in tests/test_analytic.py). Tolerances come from the discretisation, h = T/N the grid spacing:
- T: the switch interval's fractional control acts as a located switch, so the error in T is
  O(h^2); measured over N = 25, 50, ..., 800 on the four cases, |dT| / h^2 stays below 0.35, so
  |dT| <= h^2/2.
- one switch: the end constraint fixes the switch time locally, so it is O(h^2) as well (measured
  |dt| / h^2 <= 0.15): h^2/4. Two switches: the switch times move along a direction in which T is
  stationary, so an O(h^2) error in T allows O(h) in them (measured |dt| / h <= 0.53): h, and
  the same for the switch states, whose speed is below 1.4.
- printed values carry their own rounding: half a unit of the last printed digit is added.
"""

import math

import pytest

import ocp
from ocp import analytic, references

N = 100


def printed(key):
    pub = references.load("finch2015")[key]
    return pub.value, 10.0 ** -len(pub.digits.partition(".")[2])


def direct(problem):
    sol = ocp.solve(problem, ocp.MultipleShooting(N=N), refine=False)
    assert sol.success and sol.solver_success and sol.resim_miss < 1e-6
    return sol, sol.T_direct / N


def test_swing_up_kappa_1_one_switch():
    sol, h = direct(ocp.swing_up(1.0))
    T, uT = printed("t_inf_swing_up_kappa_1")
    t1, ut1 = printed("t1_swing_up_kappa_1")
    assert sol.n_switches == 1 and sol.first_u == 1 and sol.branch == 0 and sol.structure.bang_bang
    assert abs(sol.T - T) <= h * h / 2 + uT
    assert abs(sol.switch_times[0] - t1) <= h * h / 4 + ut1
    theta1, omega1 = sol.switch_states[0]
    assert abs(theta1 - (math.pi / 2 + 1)) <= h * h / 4 and abs(omega1 - math.sqrt(math.pi - 2 * math.sin(1))) <= h * h / 4


def test_damping_kappa_1_one_switch():
    sol, h = direct(ocp.damping(1.0))
    T, uT = printed("t_inf_damping_kappa_1")
    t1, ut1 = printed("t1_damping_kappa_1")
    assert sol.n_switches == 1 and sol.first_u == -1 and sol.target == (0.0, 0.0)
    assert abs(sol.T - T) <= h * h / 2 + uT
    assert abs(sol.switch_times[0] - t1) <= h * h / 4 + ut1


def test_swing_up_kappa_half_two_switches():
    sol, h = direct(ocp.swing_up(0.5))
    assert sol.n_switches == 2 and sol.first_u == -1 and sol.branch == 0
    assert abs(sol.T - analytic.two_switch("swing-up", 0.5).T) <= h * h / 2    # Finch prints no T here
    for (theta, omega), (kt, ko) in zip(sol.switch_states, [("figure2_switch1_theta", "figure2_switch1_omega"), ("figure2_switch2_theta", "figure2_switch2_omega")]):
        (pt, ut), (po, uo) = printed(kt), printed(ko)
        assert abs(theta - pt) <= 1.4 * h + ut and abs(omega - po) <= 1.4 * h + uo


def test_swing_up_kappa_three_quarters_prefers_two_switches():
    """Finch prints t_inf,2 = 5.8397 (key t_inf_two_switch_kappa_3_4), a misprint that `ocp verify`
    shows; T is checked against the addendum's exact two-switch time instead."""
    sol, h = direct(ocp.swing_up(0.75))
    T2 = analytic.two_switch("swing-up", 0.75).T
    T1, _ = printed("t_inf_one_switch_kappa_3_4")
    assert sol.n_switches == 2 and sol.first_u == -1
    assert abs(sol.T - T2) <= h * h / 2 and sol.T < T1
    # the default family did meet the one-switch local solution, and it is recorded
    assert any(s["success"] and s["n_switches"] == 1 and abs(s["T"] - T1) < h * h for s in sol.starts)


def test_branch_pinned_and_mirror_symmetry():
    """theta -> -theta, u -> -u maps the swing-up to pi onto the swing-up to -pi: same T."""
    up, _ = direct(ocp.swing_up(1.0))
    mirror, _ = direct(ocp.swing_up(1.0, branch=-1))
    assert mirror.branch == -1 and mirror.target == (-math.pi, 0.0) and mirror.first_u == -1
    assert mirror.T == pytest.approx(up.T, abs=1e-9)


def test_a_coarse_transcription_that_misses_the_target_is_not_a_success():
    """RK4 with one step on 8 intervals: IPOPT converges, the re-simulated control misses."""
    sol = ocp.solve(ocp.swing_up(1.0), ocp.MultipleShooting(N=8, M=1), refine=False)
    assert sol.solver_success and not sol.success and sol.resim_miss > 1e-6
    assert "misses the target" in sol.status


@pytest.mark.parametrize("method", [ocp.MultipleShooting(N=30, integrator="cvodes"),
                                    ocp.MultipleShooting(N=30, integrator="collocation", M=1),
                                    ocp.DirectCollocation(N=30)])
def test_other_integrators_and_transcriptions(method):
    sol = ocp.solve(ocp.swing_up(1.0), method, refine=False)
    h = sol.T / 30
    assert sol.success and sol.n_switches == 1 and abs(sol.T - printed("t_inf_swing_up_kappa_1")[0]) <= h * h / 2


@pytest.mark.parametrize("solver", ["fatrop", "sqpmethod"])
def test_other_nlp_solvers(solver):
    sol = ocp.solve(ocp.swing_up(1.0), ocp.MultipleShooting(N=40), solver=solver, refine=False)
    h = sol.T / 40
    assert sol.success and sol.method["solver"] == solver
    assert abs(sol.T - printed("t_inf_swing_up_kappa_1")[0]) <= h * h / 2


def test_a_solver_that_cannot_run_is_a_recorded_failure():
    """blocksqp needs HSL's ma27, which the CasADi wheel lacks: a failed start, not a crash."""
    sol = ocp.solve(ocp.swing_up(1.0), ocp.MultipleShooting(N=20), solver="blocksqp", refine=False)
    assert sol.success or all(s["status"].startswith("solver error") for s in sol.starts)


def test_a_start_that_returns_no_usable_point_is_a_recorded_failure():
    """bonmin's infeasible exit returns all zeros (T = 0) on one start of kappa = 1/2 at N = 25:
    that start fails with a reason; the solve returns a Solution."""
    sol = ocp.solve(ocp.swing_up(0.5), ocp.MultipleShooting(N=25), solver="bonmin", refine=False)
    assert len(sol.starts) == 3 and sol.T > 0
    assert all(s["success"] or s["status"] for s in sol.starts)
