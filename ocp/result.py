"""The result of a solve, in the spirit of `scipy.optimize.OptimizeResult`."""

import math
from dataclasses import dataclass, field

import numpy as np

from .problems import Problem
from .structure import Structure


@dataclass
class Solution:
    """A minimum-time solution and how it was obtained.

    T: final time (nondimensional); t, x, u: time grid (N+1), node states (N+1, 2) and the
    piecewise-constant control (N). branch: the k of the target reached. success: the NLP solver
    converged AND the re-simulated control reaches the target within `miss_tol` (a transcription
    can report a time below the true optimum with a control that misses the target: that is a
    failure). resim_miss: Euclidean distance in (theta, omega) from the target of the control
    re-simulated by an independent tight integrator (scipy DOP853, rtol = atol = 1e-12).
    starts: every initial guess tried, with its outcome (failures are kept as data).
    """

    problem: Problem
    method: dict
    T: float
    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    branch: int
    success: bool
    status: str
    solver_success: bool
    iterations: int
    structure: Structure
    resim_miss: float
    miss_tol: float
    build_time_s: float
    solve_time_s: float
    total_time_s: float
    guess: str
    starts: list = field(default_factory=list)

    @property
    def target(self):
        return self.problem.target(self.branch)

    @property
    def n_switches(self):
        return self.structure.n_switches

    @property
    def first_u(self):
        return self.structure.first_u

    @property
    def switch_times(self):
        return list(self.structure.switch_times)

    @property
    def switch_states(self):
        return [tuple(s) for s in self.structure.switch_states]

    def to_dict(self):
        """Plain JSON-ready data: the keys of `ocp solve --json`."""
        p = self.problem
        return {
            "problem": p.kind,
            "kappa": p.kappa,
            "x0": list(p.x0),
            "target": list(self.target),
            "branch": self.branch,
            "branch_pinned": p.branch is not None,
            "T": self.T,
            "n_switches": self.n_switches,
            "first_u": self.first_u,
            "switch_times": self.switch_times,
            "switch_states": [list(s) for s in self.switch_states],
            "structure": self.structure.to_dict(),
            "success": self.success,
            "status": self.status,
            "solver_success": self.solver_success,
            "solver": self.method["solver"],
            "method": self.method,
            "iterations": self.iterations,
            "build_time_s": self.build_time_s,
            "solve_time_s": self.solve_time_s,
            "total_time_s": self.total_time_s,
            "resim_miss": self.resim_miss,
            "miss_tol": self.miss_tol,
            "guess": self.guess,
            "starts": self.starts,
        }

    def summary(self):
        """A few lines a person can read."""
        p, s, m = self.problem, self.structure, self.method
        lines = [f"{p.kind}, kappa = {p.kappa:g}, from (theta, omega) = ({p.x0[0]:.6g}, {p.x0[1]:.6g}) "
                 f"to ({_angle(self.target[0])}, 0)  [branch k = {self.branch}{', pinned' if p.branch is not None else ''}]"]
        lines.append(f"T = {self.T:.{_decimals(s.h)}f}   (direct transcription: switch times within "
                     f"a grid spacing h = {s.h:.2g}; not refined)")
        signs = " ".join("+1" if v > 0 else "-1" for v in s.arc_signs)
        lines.append(f"{s.n_switches} switch{'es' if s.n_switches != 1 else ''}, u = {signs}"
                     + ("" if s.bang_bang else f"   (NOT resolved as bang-bang: {s.longest_interior_run} interior intervals in a row)"))
        for i, (tau, (th, om)) in enumerate(zip(s.switch_times, s.switch_states), 1):
            lines.append(f"  switch {i}: t = {tau:.4f}  at (theta, omega) = ({th:.4f}, {om:.4f})")
        lines.append(f"{'success' if self.success else 'FAILED'}: {self.status}; {m['solver']} "
                     f"{self.iterations} iterations; re-simulated miss {self.resim_miss:.1e} (tolerance {self.miss_tol:.0e})")
        lines.append(f"method: multiple shooting, N = {m['N']}, integrator {m['integrator']}"
                     + (f" (M = {m['M']})" if m["integrator"] != "cvodes" else f" (tol {m['tol']:g})")
                     + f"; guess {self.guess} (best of {len(self.starts)} starts)"
                     f"; build {self.build_time_s:.3f} s, solve {self.solve_time_s:.3f} s, total {self.total_time_s:.3f} s")
        return "\n".join(lines)


def _angle(theta):
    k = theta / math.pi
    return f"{round(k)}*pi" if abs(k - round(k)) < 1e-12 and round(k) not in (0, 1) else (
        "pi" if abs(k - 1) < 1e-12 else "0" if k == 0 else f"{theta:.6g}")


def _decimals(h):
    """Decimals of T worth printing for a direct solution on spacing h (its error is O(h^2))."""
    return max(2, min(8, math.ceil(-2 * math.log10(h))))
