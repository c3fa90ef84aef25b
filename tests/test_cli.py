"""The command line: one-line errors with exit status 2, JSON for scripts, exit 1 on a failed solve."""

import json
import subprocess
import sys

import pytest

from ocp.cli import main

JSON_KEYS = {"problem", "kappa", "x0", "target", "T", "n_switches", "first_u", "switch_times", "switch_states",
             "success", "status", "solver", "iterations", "solve_time_s", "build_time_s", "resim_miss"}


def run(*args):
    return subprocess.run([sys.executable, "-m", "ocp.cli", *args], capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("args, says", [
    (["solve", "swing-up", "--kappa", "-1"], "kappa"),
    (["solve", "swing-up", "--kappa", "nan"], "not finite"),
    (["solve", "swing-up", "--kappa", "inf"], "not finite"),
    (["solve", "swing-up", "--kappa", "1", "--N", "1"], "N = 1"),
    (["solve", "pendulum", "--kappa", "1"], "swing-up, damping"),
    (["solve", "swing-up", "--kappa", "1", "--solver", "nosuch"], "ipopt"),
    (["solve", "swing-up", "--kappa", "1", "--integrator", "euler"], "rk4, cvodes, collocation"),
    (["solve", "swing-up", "--kappa", "1", "--x0", "1"], "--x0"),
    (["solve", "swing-up", "--kappa", "1", "--x0", "a", "0"], "theta0"),
    (["solve", "swing-up", "--kappa", "1", "--option", "ipopt.nosuch=1"], "nosuch"),
])
def test_bad_input_is_one_line_and_exit_2(args, says, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and says in err and err.startswith("error:")


def test_bad_input_through_the_real_entry_point_has_no_traceback():
    proc = run("solve", "damping", "--kappa", "0")
    assert proc.returncode == 2 and "Traceback" not in proc.stderr and proc.stdout == ""


def test_solve_json_has_the_documented_keys():
    proc = run("solve", "damping", "--kappa", "1", "--json", "--no-refine")
    assert proc.returncode == 0
    out = json.loads(proc.stdout)
    assert JSON_KEYS <= set(out) and out["success"] and out["n_switches"] == 1 and out["first_u"] == -1
    # the direct answer against the one-switch formula: within its stated bounds (T: h^2/2)
    assert out["crosscheck"]["formula"].startswith("one-switch damping")
    assert abs(out["crosscheck"]["T"]) <= out["T_error"]


def test_solve_human_output_with_refinement():
    proc = run("solve", "swing-up", "--kappa", "1")
    assert proc.returncode == 0
    assert "T = 4.03001868" in proc.stdout and "certified extremal" in proc.stdout
    assert "1 switch, u = +1 -1" in proc.stdout


def test_failed_solve_exits_1_and_json_still_says_so():
    proc = run("solve", "swing-up", "--kappa", "1", "--json", "--option", "ipopt.max_iter=2")
    assert proc.returncode == 1
    out = json.loads(proc.stdout)
    assert out["success"] is False and out["status"]
