"""The reference set (reference/): its size and fields, its digits against an independent quadrature,
a random sample rebuilt from scratch, the lookup and the bench's use of it."""

import json
import math
import random
from pathlib import Path

import mpmath
import pytest

from ocp.core.problem import make
from ocp.reference import data, generate, instances, multiprecision

ROOT = Path(__file__).resolve().parents[1]
ROWS = data.read(ROOT / "reference" / "instances.jsonl")
SOLVED = [r for r in ROWS.values() if r["status"] == "solved"]


def significant(text):
    return len(text.lstrip("-").replace(".", "").lstrip("0"))


def test_the_set_has_200_solved_instances_with_20_digits_agreeing_with_the_search():
    assert len(SOLVED) >= 200
    assert set(ROWS) <= {i.id for i in instances.all_instances()}
    for r in SOLVED:
        optimal = [r["optimum"], *r["ties"]]
        for s in optimal:
            ref = s["refined"]
            assert significant(ref["T"]) >= 20 and all(significant(t) >= 20 for t in ref["switch_times"])
            assert float(ref["T_error"]) < 1e-20 * float(ref["T"])
            assert ref["inputs"] == generate.INPUTS
            # the double-precision search within its own stated error of the 40-digit value; where it is
            # not, the defect is the search's: a tie refined to the same digits (its mirror image) agrees
            if ref["agreement"] > 1.0:
                assert ref["agreement"] < 2.0 and any(
                    o["refined"]["T"] == ref["T"] and o["refined"]["agreement"] <= 1.0 for o in optimal), r["id"]
        assert r["optimum"]["certificate"]["certified"]


def test_every_row_has_the_fields_of_the_schema():
    schema = json.loads((ROOT / "reference" / "schema.json").read_text())
    solution = schema["$defs"]["solution"]["required"] + schema["$defs"]["extremal"]["required"]
    for r in ROWS.values():
        assert set(schema["required"]) <= set(r)
        branch = schema["then"] if r["status"] == "solved" else schema["else"]
        assert set(branch["required"]) <= set(r)
        if r["status"] == "solved":
            assert set(solution) <= set(r["optimum"])
            assert set(schema["$defs"]["solution"]["properties"]["refined"]["required"]) <= set(r["optimum"]["refined"])


def test_the_index_lists_every_row():
    lines = (ROOT / "reference" / "index.csv").read_text().splitlines()
    assert lines[0] == ",".join(data.INDEX_COLUMNS) and len(lines) == len(ROWS) + 1


def _one_switch_time(kappa):
    """T of the one-switch swing-up from rest, u = +1 then -1 (Finch 2015, the one-switch formula), and
    the switch angle theta_s = pi/2 + 1/kappa where the two arcs meet, by mpmath's tanh-sinh quadrature
    of dtheta / omega at 40 digits. On the first arc omega^2 = 2 theta (kappa - g(theta)), on the second
    omega^2 = 2 phi (kappa + g(phi)) with phi = pi - theta, g(x) = 2 sin^2(x/2) / x; the substitutions
    theta = theta_s v^2 and phi = (pi - theta_s) v^2 remove the square-root singularities at the ends
    (the integrands in theta lose 17 digits there)."""
    with mpmath.workdps(40):
        k = mpmath.mpf(repr(kappa))
        s = mpmath.pi / 2 + 1 / k
        r = mpmath.pi - s
        g = lambda x: x / 2 * mpmath.sinc(x / 2) ** 2
        first = mpmath.quad(lambda v: 2 * s / mpmath.sqrt(2 * s * (k - g(s * v**2))), [0, 1])
        second = mpmath.quad(lambda v: 2 * r / mpmath.sqrt(2 * r * (k + g(r * v**2))), [0, 1])
        return first + second, s


def test_one_switch_swing_ups_agree_with_a_quadrature_to_their_stated_error():
    rows = [r for r in SOLVED if r["kind"] == "swing-up" and r["x0"] == [0.0, 0.0] and r["optimum"]["arc_signs"] == [1, -1]
            and r["optimum"]["branch"] == 0]
    assert len(rows) >= 5
    for r in rows:
        T, s = _one_switch_time(r["kappa"])
        ref = r["optimum"]["refined"]
        with mpmath.workdps(40):
            assert abs(mpmath.mpf(ref["T"]) - T) <= mpmath.mpf(ref["T_error"]) + mpmath.mpf("1e-33"), r["id"]
            assert abs(mpmath.mpf(ref["switch_states"][0][0]) - s) <= mpmath.mpf(ref["switch_state_errors"][0][0]), r["id"]


def test_the_refinement_converges_from_a_perturbed_guess_to_the_same_digits():
    r = next(r for r in SOLVED if r["id"] == "swing-up/circle/k1.526/x0=standard")
    o = r["optimum"]
    times = (0.0, *o["switch_times"], o["T"])
    durations = [b - a + 1e-7 for a, b in zip(times, times[1:])]
    got = multiprecision.refine(r["x0"], r["kappa"], o["arc_signs"], 1 + 2 * o["branch"], o["costate_angle"] + 1e-7,
                                durations)
    with mpmath.workdps(40):
        assert abs(got.T - mpmath.mpf(o["refined"]["T"])) <= 2 * mpmath.mpf(o["refined"]["T_error"])


def test_a_random_sample_rebuilt_from_scratch_agrees():
    """Two instances drawn at random among those computed in under 3 s, searched and refined again
    (swing-up/circle/k2.48/x0=(-1.0097,-3.5296): stored to horizon 2.484, listing one arrival; rebuilt at
    1405d57 to 2.755, where it lists also branch -2 at 2.679)."""
    cheap = [r for r in SOLVED if r["provenance"]["time_s"] < 3]
    sample = random.Random().sample(cheap, 2)
    for old in sample:
        new = generate.compute(instances.find(old["id"]))
        assert new["status"] == "solved", old["id"]
        a, b = old["optimum"], new["optimum"]
        assert (a["arc_signs"], a["branch"], len(old["ties"])) == (b["arc_signs"], b["branch"], len(new["ties"])), old["id"]
        with mpmath.workdps(40):
            bound = mpmath.mpf(a["refined"]["T_error"]) + mpmath.mpf(b["refined"]["T_error"])
            assert abs(mpmath.mpf(a["refined"]["T"]) - mpmath.mpf(b["refined"]["T"])) <= bound, old["id"]
            for s, t, e in zip(a["refined"]["switch_times"], b["refined"]["switch_times"],
                               a["refined"]["switch_time_errors"]):
                assert abs(mpmath.mpf(s) - mpmath.mpf(t)) <= 2 * mpmath.mpf(e), old["id"]
        # every arrival before each record's coverage horizon is listed: before the lesser of the two
        # the lists agree (past it, what one lists depends on where its horizon schedule ended)
        horizon = min(old["coverage"]["horizon"], new["coverage"]["horizon"])
        assert (sorted(e["branch"] for e in old["extremals"] if e["T"] <= horizon)
                == sorted(e["branch"] for e in new["extremals"] if e["T"] <= horizon)), old["id"]


def test_lookup_finds_a_problem_of_the_set_and_nothing_else():
    r = SOLVED[0]
    assert data.lookup(make(r["kind"], r["kappa"], r["x0"], r["branch_pinned"]))["id"] == r["id"]
    assert data.lookup(make("swing-up", 0.123456, (0.1, 0.2))) is None


def test_the_bench_reads_a_reference_of_the_set_without_searching(monkeypatch):
    from ocp.bench import reference as bench_reference
    from ocp.bench.suite import Case

    r = next(r for r in SOLVED if r["reading"] == "circle")
    monkeypatch.setattr(bench_reference, "solve", lambda *a, **k: pytest.fail("the reference was searched again"))
    ref = bench_reference.reference(Case(r["kind"], r["kappa"], tuple(r["x0"])))
    assert ref.source.startswith("the reference set") and ref.T == float(r["optimum"]["refined"]["T"])
    assert list(ref.arc_signs) == r["optimum"]["arc_signs"] and len(ref.extremals) == len(r["extremals"])


def test_ids_are_stable_and_name_their_numbers():
    every = instances.all_instances()
    assert len({i.id for i in every}) == len(every) >= 200
    for i in every:
        kind, reading, kappa, start = i.id.split("/", 3)
        assert kind == i.kind and reading == ("circle" if i.branch is None else f"plane-b{i.branch}")
        if not kappa.startswith("k="):
            assert float(kappa[1:]) == i.kappa
        if start.startswith("x0=(") and "pi" not in start:
            assert tuple(float(v) for v in start[4:-1].split(",")) == i.x0
    assert math.isclose(instances.find("damping/circle/k=kappa1/x0=attaining-1").kappa, 1.0393937840392842)


def test_the_command_generates_resumes_and_shows(tmp_path, capsys):
    from ocp.cli import main

    cheap = min((r for r in SOLVED if r["reading"] == "plane"), key=lambda r: r["provenance"]["time_s"])
    assert main(["reference", "generate", "--out", str(tmp_path), "--only", cheap["id"]]) == 0
    assert "1 solved, 0 skipped" in capsys.readouterr().out
    assert main(["reference", "generate", "--out", str(tmp_path), "--only", cheap["id"]]) == 0
    assert "1 of 1 instances already" in capsys.readouterr().err
    rows = data.read(tmp_path / "instances.jsonl")
    assert list(rows) == [cheap["id"]] and (tmp_path / "index.csv").read_text().count("\n") == 2
    assert main(["reference", "show", cheap["id"]]) == 0 and cheap["optimum"]["refined"]["T"] in capsys.readouterr().out
    assert main(["reference", "show", "swing-up/circle/k3/x0=nowhere"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
