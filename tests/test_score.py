"""`ocp score`: hand-made solutions that are optimal, locally optimal, wrongly structured and missing
the target, in each accepted format, classified against the reference set; bad files get one line and
exit 2; the outside-tool examples' files are classified."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ocp.cli import main
from ocp.reference import data
from ocp.reference.score import Class, score

ROOT = Path(__file__).resolve().parents[1]
ID = "swing-up/circle/k0.7702/x0=standard"
ROW = data.load()[ID]


def answer(e, **change):
    """A bang-bang answer of the extremal record e (its refined digits where it has them)."""
    values = e.get("refined", e)
    return dict({"instance": ID, "arc_signs": e["arc_signs"], "switch_times": values["switch_times"], "T": values["T"]},
                **change)


def test_the_optimum_and_its_tie_are_the_optimum():
    for e in [ROW["optimum"], *ROW["ties"]]:
        s = score(answer(e))
        assert s.cls == Class.OPTIMUM and s.miss < 1e-10 and s.T_minus_ref == 0.0
        assert s.matched["branch"] == e["branch"]


def test_a_slower_local_optimum_is_named_with_how_much_slower():
    e = next(e for e in ROW["extremals"] if e["local_optimum"] and e["T"] > ROW["optimum"]["T"] * (1 + 1e-6))
    s = score(answer(e))
    assert s.cls == Class.LOCAL_OPTIMUM
    assert s.matched["slower_by"] == pytest.approx(e["T"] - ROW["optimum"]["T"], abs=1e-12) and s.T_minus_ref > 0


def test_an_extremal_that_is_not_a_local_optimum_is_a_wrong_structure():
    e = next(e for e in ROW["extremals"] if not e["local_optimum"])
    s = score(answer(e))
    assert s.cls == Class.WRONG_STRUCTURE and "not a local optimum" in s.notes[0]


def test_a_control_that_misses_the_target():
    o = ROW["optimum"]["refined"]
    s = score(answer(ROW["optimum"], switch_times=[float(o["switch_times"][0]) + 1e-3, o["switch_times"][1]]))
    assert s.cls == Class.MISSES_TARGET and s.miss > 1e-4


def _sampled(tmp_path, mode, N=400, signs=None, times=None, T=None):
    """The optimum (or `signs` switched at `times`) sampled on a uniform grid of N intervals with a node
    at each switch (constant), or with nodes 1e-9 either side of each switch (linear: a ramp there)."""
    o = ROW["optimum"]
    signs = signs or o["arc_signs"]
    times = times or [float(t) for t in o["refined"]["switch_times"]]
    T = T or float(o["refined"]["T"])
    extra = times if mode == "constant" else [t + d for t in times for d in (-1e-9, 1e-9)]
    t = np.unique(np.concatenate([np.linspace(0, T, N + 1), extra]))
    u = [signs[int(np.searchsorted(times, a + (1e-10 if mode == "constant" else 0), side="right"))] for a in t]
    if mode == "linear":
        u = [signs[int(np.searchsorted(times, a))] for a in t]
    path = tmp_path / f"{mode}.csv"
    path.write_text(f"# instance: {ID}\n# interpolation: {mode}\nt,u\n" +
                    "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(t, u)))
    return path


def test_a_sampled_control_of_the_optimum(tmp_path):
    s = score(_sampled(tmp_path, "constant"))
    assert s.cls == Class.OPTIMUM and s.miss < 1e-9 and s.bang_bang
    assert max(map(abs, s.switch_time_errors)) < 1e-9


def test_a_sampled_linear_control_with_a_wrong_structure(tmp_path):
    e = next(e for e in ROW["extremals"] if not e["local_optimum"])
    s = score(_sampled(tmp_path, "linear", signs=e["arc_signs"], times=e["switch_times"], T=e["T"]))
    assert s.cls == Class.WRONG_STRUCTURE and s.miss < 1e-8


def test_ocp_solve_json_is_scored(tmp_path):
    import ocp
    from ocp.core.problem import make

    r = next(r for r in data.load().values() if r["status"] == "solved" and r["kappa"] >= 5)
    path = tmp_path / "ocp.json"
    path.write_text(json.dumps(ocp.solve(make(r["kind"], r["kappa"], r["x0"], r["branch_pinned"])).to_dict()))
    s = score(path)
    assert s.instance == r["id"] and s.cls == Class.OPTIMUM and abs(s.T_minus_ref) < 1e-12


def test_the_command_prints_json(tmp_path, capsys):
    path = tmp_path / "a.json"
    path.write_text(json.dumps(answer(ROW["optimum"])))
    assert main(["score", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["class"] == "optimum"


BAD = {
    "not-json.json": "{not json",
    "keys.json": json.dumps({"instance": ID, "arc_signs": [1, -1], "switch_times": [1.0], "T": 2.0, "extra": 1}),
    "unknown.json": json.dumps({"instance": "swing-up/circle/k9.99/x0=standard", "arc_signs": [1, -1],
                                "switch_times": [1.0], "T": 2.0}),
    "signs.json": json.dumps({"instance": ID, "arc_signs": [1, 1], "switch_times": [1.0], "T": 2.0}),
    "count.json": json.dumps({"instance": ID, "arc_signs": [1, -1], "switch_times": [], "T": 2.0}),
    "order.json": json.dumps({"instance": ID, "arc_signs": [1, -1], "switch_times": [3.0], "T": 2.0}),
    "long.json": json.dumps({"instance": ID, "arc_signs": [1, -1], "switch_times": [1.0], "T": 1e6}),
    "header.csv": f"# instance: {ID}\ntime,control\n0,1\n1,1\n",
    "bound.csv": f"# instance: {ID}\nt,u\n0,1.5\n1,1\n2,1\n",
    "order.csv": f"# instance: {ID}\nt,u\n0,1\n2,1\n1,1\n",
    "noid.csv": "t,u\n0,1\n1,1\n2,1\n",
    "text.csv": f"# instance: {ID}\nt,u\n0,one\n1,1\n2,1\n",
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_a_bad_file_gets_one_line_and_exit_2(tmp_path, capsys, name):
    path = tmp_path / name
    path.write_text(BAD[name])
    assert main(["score", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1


def _example(tmp_path, script, *outputs):
    done = subprocess.run([sys.executable, str(ROOT / "examples" / script), *map(str, outputs)], capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]


def test_the_casadi_opti_example_is_the_optimum(tmp_path):
    _example(tmp_path, "casadi_opti.py", tmp_path / "opti.csv")
    s = score(tmp_path / "opti.csv")
    assert s.cls == Class.OPTIMUM and 0 < s.T_minus_ref < 1e-3


def test_the_scipy_example_finds_the_optimum_and_a_local_optimum(tmp_path):
    _example(tmp_path, "scipy_switching_times.py", tmp_path)
    assert score(tmp_path / "scipy-three-arcs.json").cls == Class.OPTIMUM
    local = score(tmp_path / "scipy-two-arcs.json")
    assert local.cls == Class.LOCAL_OPTIMUM and local.matched["slower_by"] > 0.1


def test_the_rockit_example_is_the_optimum(tmp_path):
    pytest.importorskip("rockit")
    _example(tmp_path, "rockit_damping.py", tmp_path / "rockit.csv")
    s = score(tmp_path / "rockit.csv")
    assert s.cls == Class.OPTIMUM and 0 < s.T_minus_ref < 1e-2
