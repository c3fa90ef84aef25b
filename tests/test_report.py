"""The charts' data and tables of `ocp.bench.report` on synthetic records whose answers are known by
construction: Dolan-More ratios relative to the best family per case, profiles that do not change
when the machine is faster, one colour per family in every chart, local optima labelled as such,
and the reached-optimum rate that does not judge a method stating no accuracy."""

import math
from dataclasses import replace

import pytest

from ocp.bench import profiles, report
from ocp.bench.row import Row, from_dict


def run(case, family, N, time, error, outcome="ok", T_error=1e-3):
    return from_dict(Row, {"case": case, "case_label": case, "problem": case, "family": family, "N": N,
                           "guess": "default", "outcome": outcome, "total_time_s": time, "T_minus_ref": error,
                           "T_ref_error": 1e-14, "T": 4.0 + error, "T_ref": 4.0, "T_error": T_error,
                           "success": outcome in ("ok", "inaccurate"), "status": "verified",
                           "label": f"{family} N={N}", "timing": {"note": "timed alone"}})


RECORDS = [
    run("a", "fast", 25, 0.1, 5e-3), run("a", "fast", 50, 0.2, 1e-3),
    run("a", "slow", 25, 0.4, 4e-3), run("a", "slow", 50, 0.8, 9e-4),
    run("b", "fast", 25, 0.1, 6e-3), run("b", "fast", 50, 0.3, 2e-3, outcome="local optimum"),
    run("b", "slow", 25, 0.2, 5e-3), run("b", "slow", 50, 0.5, 1.5e-3),
    run("a", "extremal search", None, 0.05, 1e-15), run("b", "extremal search", None, 0.05, 1e-15),
]


def test_ratios_are_relative_to_the_best_family_on_each_case():
    """Time to reach 2e-3: case a: fast 0.2 s, slow 0.8 s; case b: fast never (its N = 50 answer is
    a local optimum), slow 0.5 s. Ratios: fast (1, inf), slow (4, 1)."""
    costs = profiles.profile_costs(RECORDS, accuracies=(2e-3,), budgets=())[("time", 2e-3)]
    assert costs["fast"] == {"a": 0.2, "b": math.inf} and costs["slow"] == {"a": 0.8, "b": 0.5}
    ratios = profiles.performance_profile({f: costs[f] for f in ("fast", "slow")})
    assert ratios == {"fast": [1.0, math.inf], "slow": [1.0, 4.0]}


def test_a_case_nobody_solves_ranks_nobody():
    ratios = profiles.performance_profile({"x": {"a": 1.0, "b": math.inf}, "y": {"a": 2.0, "b": math.inf}})
    assert ratios == {"x": [1.0], "y": [2.0]}


def test_the_accuracy_profile_uses_a_budget_relative_to_the_fastest_answer():
    """Budget 2 x the fastest direct answer (0.1 s on both cases): within 0.2 s, case a: fast 1e-3,
    slow none; case b: fast 6e-3, slow 5e-3."""
    data = report.profiles(RECORDS, accuracies=(), budgets=(2.0,))
    (beta, ratios), = data["error"]
    assert beta == 2.0
    assert ratios["fast"] == [1.0, pytest.approx(6e-3 / 5e-3)] and ratios["slow"] == [1.0, math.inf]
    assert "extremal search" not in ratios                 # the reference, not a competitor


def test_the_profiles_do_not_depend_on_the_machines_speed():
    faster = [replace(r, total_time_s=r.total_time_s / 7.3) for r in RECORDS]
    for kind in ("time", "error"):
        assert report.profiles(faster)[kind] == report.profiles(RECORDS)[kind]


def test_one_colour_per_family_whatever_else_is_in_the_store():
    shipped = report._shipped_families()
    alone = report.family_style({"MS rk4 M=4 / fatrop"})
    crowded = report.family_style(set(shipped) | {"zz custom", "aa custom", "extremal search"})
    assert alone["MS rk4 M=4 / fatrop"] == crowded["MS rk4 M=4 / fatrop"]
    assert crowded["extremal search"][0] == "#000000"
    colours = [crowded[f] for f in shipped]
    assert len(set(colours)) == len(colours)                # the shipped families are told apart
    assert report.family_style({"zz custom", "aa custom"})["aa custom"] == crowded["aa custom"]


def test_work_precision_labels_points_with_N_and_local_optima_as_such():
    points = report.work_precision_points(RECORDS)
    assert [p[3] for p in points["a"]["fast"]["curve"]] == ["N=25", "N=50"]
    assert points["b"]["fast"]["another"] == [(50, 0.3, 2e-3, "N=50 (local optimum)", "local optimum")]
    assert points["a"]["extremal search"]["curve"][0][3] == "search"
    assert points["a"]["extremal search"]["curve"][0][2] == 1e-14    # not below the reference's accuracy


def test_reached_optimum_is_not_judged_without_a_stated_accuracy():
    records = [run("a", "DC", 25, 0.1, 1e-3, T_error=None), run("a", "MS", 25, 0.1, 1e-3, T_error=2e-3),
               run("a", "MS", 50, 0.1, 1e-3, T_error=1e-4)]
    rows = {r["method"]: r for r in report.method_table(records, {"a": 4.0})}
    assert rows["DC"]["reached optimum"] == "- (+1 right structure, no stated accuracy)"
    assert rows["MS"]["reached optimum"] == "1/2"
