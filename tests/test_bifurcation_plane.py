"""The plane at high energy (ocp.synthesis.limit, issue 23): the zero of the one-switch candidate's
switching function p_omega against two independent computations: the times of the candidate and of
the candidate preceded by a short push (u = +1 for eps: its time is T + 2 kappa p_omega eps, so
the push pays exactly upstream of the zero; trajectory times only, no costate), and the complete
search (`ocp.solve`) on either side of the zero; the limit problem against its stationary-phase
estimate.
"""

import math

import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import ocp
from ocp.core.errors import InputError
from ocp.core.problem import KINDS
from ocp.synthesis import limit, results

KAPPA, TURN = 5.0, 2 * math.pi * 10 + math.pi / 4


def _flow(x, u, kappa, t_max, event):
    sol = solve_ivp(lambda t, y: (y[1], kappa * u - math.sin(y[0])), (0.0, t_max), x, "DOP853", rtol=1e-12,
                    atol=1e-12, events=event)
    return sol.t_events[0][0], sol.y_events[0][0]


def candidate_time(kind, kappa, x0):
    """u = -1 from x0 (beyond the target, moving away) until the braking curve into the target
    (E - kappa theta = -cos theta_T - kappa theta_T, omega < 0), then u = +1 until omega = 0."""
    theta_t = KINDS[kind].target_base
    level_t = -math.cos(theta_t) - kappa * theta_t

    def meet(t, y):
        return 0.5 * y[1] ** 2 - math.cos(y[0]) - kappa * y[0] - level_t if y[1] < 0 else -1.0
    meet.terminal, meet.direction = True, 1

    def stop(t, y):
        return y[1]
    stop.terminal, stop.direction = True, 1
    t1, x1 = _flow(list(x0), -1.0, kappa, 100.0, meet)
    t2, x2 = _flow(list(x1), 1.0, kappa, 100.0, stop)
    assert abs(x2[0] - theta_t) < 1e-7               # it ends at the pinned target
    return t1 + t2


def push_gain(kind, kappa, x0, eps=1e-5):
    """(T with a first push of u = +1 for eps) - T, divided by eps: 2 kappa p_omega(x0)."""
    sol = solve_ivp(lambda t, y: (y[1], kappa - math.sin(y[0])), (0.0, eps), list(x0), "DOP853", rtol=1e-13,
                    atol=1e-13)
    return (eps + candidate_time(kind, kappa, sol.y[:, -1]) - candidate_time(kind, kappa, x0)) / eps


@pytest.mark.parametrize("kind", ["swing-up", "damping"])
def test_the_zero_is_where_a_first_push_starts_to_pay(kind):
    c = limit.candidate(kind, KAPPA, TURN)
    assert c.zero is not None
    before = limit.upstream(KAPPA, c.zero, 0.05)
    after = limit.upstream(KAPPA, c.zero, -0.05)
    assert push_gain(kind, KAPPA, before) < 0 < push_gain(kind, KAPPA, after)
    root = brentq(lambda dt: push_gain(kind, KAPPA, limit.upstream(KAPPA, c.zero, dt)), -0.05, 0.05, xtol=1e-6)
    assert abs(root) < 1e-3


def test_the_search_needs_two_switches_exactly_upstream_of_the_zero():
    c = limit.candidate("damping", KAPPA, TURN)
    counts = [ocp.solve(ocp.damping(KAPPA, limit.upstream(KAPPA, c.zero, dt), branch=0)).n_switches
              for dt in (-0.2, 0.2)]
    assert counts == [1, 2]


def test_the_limit_problem_meets_its_stationary_phase_estimate():
    # the kick estimate a^(3/2)/sqrt(2 pi) is the leading term in 1/kappa; at kappa = 12 the two agree to 1 %
    kappa = 12.0
    near, far = (limit.edge_speed(kappa, math.pi / 4, w * kappa ** 1.5) for w in (2, 4))
    assert abs(near - far) < 1e-3 * far
    assert abs(far / limit.kick_edge(kappa) - 1) < 0.01
    assert limit.edge_speed(kappa, math.pi / 4 + math.pi) == math.inf      # the opposite phase: no kick back


def test_bad_input_is_refused():
    with pytest.raises(InputError, match="kappa > 1"):
        limit.candidate("damping", 0.9, TURN)
    with pytest.raises(InputError, match="beyond the target"):
        limit.candidate("swing-up", KAPPA, 1.0)
    with pytest.raises(InputError, match="accepted"):
        limit.candidate("swing", KAPPA, TURN)


def test_the_approach_fit_recovers_a_power_law_and_the_table_prints_a_missing_value():
    # rows whose ratios follow 1 - ratio = 0.2 n^-1.5 exactly: the fits return a = 0.2, p = 1.5 and c = 0.2, e = 0
    rows = [{"case": f"swing-up/circle/{n}", "kind": "swing-up", "reading": "circle", "n": n,
             "kappa": (1 - 0.2 * n ** -1.5) * 0.9 / n, "asymptote": 0.9 / n} for n in range(1, 6)]
    f = results.approach(rows)["swing-up"]
    assert f.ns == (2, 3, 4, 5) and abs(f.a - 0.2) < 1e-12 and abs(f.p - 1.5) < 1e-12 and f.residual < 1e-14
    assert abs(f.c - 0.2) < 1e-12 and abs(f.e) < 1e-11 and f.residual_32 < 1e-14
    plane = {"case": "damping/plane/1", "kind": "damping", "reading": "plane", "n": 1, "kappa": None,
             "mechanism": "kappa_1 does not exist on the plane", "commit": "c"}
    full = [dict(r, error=1e-13, published=None, state=[0.0, 0.0], mechanism="m", time_to_go=1.0, commit="c")
            for r in rows]
    bound = dict(full[1], case="damping/circle/2", kind="damping", bound="lower")
    table = results.format_table(full + [bound, plane])
    assert "none (N >= 2 always)" in table and "a = 0.2" in table and "p = 1.5" in table
    assert ">= " + results.plus_minus(bound["kappa"], 1e-13) in table
    # a sequence above its asymptote (the damping's): 1 - ratio = -0.1 n^-0.5 for n = 1..4 gives a = -0.1, p = 0.5,
    # local exponents 0.5; with two values of n >= 2 the table says why there is no fit
    above = [dict(r, case=f"damping/circle/{r['n']}", kind="damping", kappa=(1 + 0.1 * r["n"] ** -0.5) * 0.9 / r["n"])
             for r in full[:4]]
    f = results.approach(above)["damping"]
    assert abs(f.a + 0.1) < 1e-12 and abs(f.p - 0.5) < 1e-12 and f.residual < 1e-14
    assert all(abs(p - 0.5) < 1e-12 for *_, p in results.local_exponents(results.departures(above)["damping"]))
    assert "damping" not in results.approach(above[:3])
    assert "no fit (three values of one sign with n >= 2 needed)" in results.format_table(above[:3])


def test_the_least_time_to_go_of_the_dampings_band_is_a_minimum():
    # the band of three switches at kappa = 0.5 (README: omega of 10 to 12): its least time-to-go over psi
    from ocp.synthesis.bifurcation import switch_point

    s, psi = limit.least_time_to_go("damping", 0.5, 3, 2.2, 2.3, samples=11)
    assert 20 < s < 25 and 2.2 < psi < 2.3
    for d in (-1e-3, 1e-3):
        assert switch_point("damping", 0.5, psi + d, 3).s > s
    assert abs(switch_point("damping", 0.5, psi, 3).x[1]) > 9


def test_the_dampings_band_runs_off_to_infinite_energy_where_its_third_switch_leaves():
    # limit.runaway extrapolates 1/s_3 to 0; the field's extremals themselves (switch_point, followed to a
    # time-to-go of 400) switch a third time just below the extrapolated kappa and not just above it
    from ocp.synthesis.bifurcation import switch_point

    kappa, error, rows = limit.runaway("damping", 3, (0.51, 0.515, 0.52), 2.18, 2.26, samples=12)
    assert 0.525 < kappa < 0.535 and error < 1e-3 and rows[0][1] < rows[1][1] < rows[2][1]
    psis = [2.18 + 0.01 * i for i in range(9)]
    assert any(switch_point("damping", kappa - 0.003, p, 3, s_max=400.0) for p in psis)
    assert not any(switch_point("damping", kappa + 0.005, p, 3, s_max=400.0) for p in psis)
