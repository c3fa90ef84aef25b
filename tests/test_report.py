"""The charts' data and tables of `ocp.bench.report` on synthetic records whose answers are known by
construction: Dolan-More ratios relative to the best family per case, every case counted, profiles
on the solver's time that do not change when the machine is faster or the checking slower, one
colour per family in every chart, identical curves merged, labels that do not overprint, local
optima labelled as such, and the reached-optimum rate that does not judge a method stating no
accuracy."""

import math
from dataclasses import replace

import pytest

from ocp.bench import profiles, report
from ocp.bench.row import Row, from_dict


def run(case, family, N, time, error, outcome="ok", T_error=1e-3):
    return from_dict(Row, {"case": case, "case_label": case, "problem": case, "family": family, "N": N,
                           "guess": "default", "outcome": outcome, "build_time_s": 0.0, "solve_time_s": time,
                           "total_time_s": time + 5.0, "T_minus_ref": error,
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


def test_a_case_nobody_solves_is_counted_as_such():
    costs = {"x": {"a": 1.0, "b": math.inf}, "y": {"a": 2.0, "b": math.inf}}
    assert profiles.performance_profile(costs) == {"x": [1.0, math.inf], "y": [2.0, math.inf]}
    assert profiles.unreached(costs) == 1


def test_a_family_is_profiled_over_the_cases_it_ran():
    """A designed suite (groups): "wide" ran case a only; it is ranked on a against the best there."""
    costs = {"core": {"a": 2.0, "b": 1.0}, "wide": {"a": 1.0}}
    assert profiles.performance_profile(costs) == {"core": [1.0, 2.0], "wide": [1.0]}
    assert profiles.unreached({"core": {"a": math.inf, "b": 1.0}, "wide": {"a": math.inf}}) == 1


def test_the_accuracy_profile_uses_a_budget_relative_to_the_fastest_answer():
    """Budget 2 x the fastest direct answer (0.1 s on both cases): within 0.2 s, case a: fast 1e-3,
    slow none; case b: fast 6e-3, slow 5e-3."""
    data = report.profiles(RECORDS, accuracies=(), budgets=(2.0,))
    (beta, ratios, unreached), = data["error"]
    assert beta == 2.0 and unreached == 0
    assert ratios["fast"] == [1.0, pytest.approx(6e-3 / 5e-3)] and ratios["slow"] == [1.0, math.inf]
    assert "extremal search" not in ratios                 # the reference, not a competitor


def test_the_profiles_do_not_depend_on_the_machines_speed_nor_on_the_checking():
    faster = [replace(r, solve_time_s=r.solve_time_s / 7.3) for r in RECORDS]
    checked_slowly = [replace(r, total_time_s=r.total_time_s * (1 + 10 * i)) for i, r in enumerate(RECORDS)]
    for kind in ("time", "error"):
        assert report.profiles(faster)[kind] == report.profiles(RECORDS)[kind]
        assert report.profiles(checked_slowly)[kind] == report.profiles(RECORDS)[kind]


def test_identical_curves_are_drawn_once_and_named_together():
    styles = report.family_style({"a", "b", "c", "d"})
    curves = report.merged_curves({"a": [1.0, 2.0], "b": [1.0, 3.0], "c": [1.0, 2.0], "d": [math.inf]}, styles)
    assert curves == [(["a", "c"], [1.0, 2.0]), (["b"], [1.0, 3.0])]       # d never gets there: not a curve


def test_labels_never_overprint_each_other_or_a_point():
    """Three points 2 pt apart: the labels go to different offsets, none overlapping another or a point."""
    candidates = [(100.0, 100.0, "N=25"), (100.0, 102.0, "N=50"), (101.0, 101.0, "N=100"), (300.0, 300.0, "x")]
    placed = report.place_labels(candidates, [(x, y) for x, y, _ in candidates], 6)
    boxes = []
    for i, ((dx, dy), ha) in placed.items():
        x, y, text = candidates[i]
        w = 0.65 * 6 * len(text) + 1
        x0 = x + dx if ha == "left" else x + dx - w
        boxes.append((x0, y + dy, x0 + w, y + dy + 6))
    assert 3 in placed and len(placed) >= 3
    overlap = lambda a, b: a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
    assert not any(overlap(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
    assert not any(overlap(b, (x - 3, y - 3, x + 3, y + 3)) for b in boxes for x, y, _ in candidates)


def test_a_work_precision_chart_with_a_method_that_never_answers(tmp_path):
    records = RECORDS + [run("a", "broken", 25, 0.1, 0.0, outcome="solver error")]
    points = report.work_precision_points(records)
    assert points["a"]["broken"] == {"curve": [], "another": [], "failed": 1, "outcomes": {"solver error": 1}}
    paths = report.work_precision(records, tmp_path, ("png",))
    assert sorted(p.name for p in paths) == ["work_precision_a.png", "work_precision_b.png"]


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
