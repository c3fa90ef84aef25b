"""The result of a solve, in the spirit of `scipy.optimize.OptimizeResult`."""

import math
from dataclasses import dataclass, field

import numpy as np

from .problems import Problem
from .verify import defended
from .structure import Structure, pattern


@dataclass
class Solution:
    """A minimum-time solution and how it was obtained.

    The direct solution: T_direct, the time grid t (N+1), node states x (N+1, 2), the piecewise-
    constant control u (N), its `structure`, and `branch` (the k of the target reached). success:
    the NLP solver converged AND the control re-simulated by an independent tight integrator
    (scipy DOP853, rtol = atol = 1e-12) lands within `miss_tol` of the target (`resim_miss`, the
    Euclidean distance in (theta, omega)); a transcription can report a time below the optimum
    with a control that misses the target, and that is a failure. starts: every initial guess
    tried, with its outcome.

    After `ocp.solve` with refinement: `refined` (an `ocp.refine.Refined`, the best candidate),
    `certificate` (`ocp.certificate.Certificate`), `candidates` (every structure examined),
    `refined_resim_miss` (the refined arcs re-simulated by the same independent integrator). T,
    n_switches, first_u, switch_times and switch_states are then the refined values. `crosscheck`:
    the answer against the analytic formula of its structure, where one applies
    (`ocp.analytic.Crosscheck`), else None.
    """

    problem: Problem
    method: dict
    T_direct: float
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
    refined: object = None
    refined_branch: int | None = None
    refined_resim_miss: float | None = None
    certificate: object = None
    candidates: list = field(default_factory=list)
    refine_time_s: float = 0.0
    direct_success: bool | None = None
    crosscheck: object = None

    def __post_init__(self):
        if self.direct_success is None:
            self.direct_success = self.success

    @property
    def T(self):
        return self.refined.T if self.refined else self.T_direct

    @property
    def answer_branch(self):
        """The branch k of the answer: the refined one's where refined, else the direct one's."""
        return self.refined_branch if self.refined else self.branch

    @property
    def target(self):
        return self.problem.target(self.answer_branch)

    @property
    def T_error(self):
        """Error bound of T: the refinement's estimate, or the direct bound h^2/2 (observed)."""
        return self.refined.T_error if self.refined else direct_T_accuracy(self.structure.h)

    @property
    def switch_time_error(self):
        """Error bound of the switch times: the refinement's estimate, or h for a direct answer (O(h^2)
        for one switch, O(h) for more; observed <= 0.53 h, tests/test_direct.py)."""
        return self.refined.switch_time_error if self.refined else self.structure.h

    @property
    def n_switches(self):
        return self.refined.n_switches if self.refined else self.structure.n_switches

    @property
    def first_u(self):
        return self.refined.first_u if self.refined else self.structure.first_u

    @property
    def switch_times(self):
        return list(self.refined.switch_times if self.refined else self.structure.switch_times)

    @property
    def switch_states(self):
        return [tuple(s) for s in (self.refined.switch_states if self.refined else self.structure.switch_states)]

    @property
    def arc_signs(self):
        return tuple(self.refined.signs if self.refined else self.structure.arc_signs)

    @property
    def certified(self):
        return bool(self.certificate and self.certificate.certified)

    @property
    def verdict(self):
        """What this result is, in one sentence."""
        if not self.success:
            return f"no solution: {self.status}"
        if self.refined is None:
            return ("direct solution, not refined" if not self.candidates
                    else "direct solution; no candidate structure could be refined")
        valid = sum(c.valid for c in self.candidates)
        best = f"best of {valid} extremal{'s' if valid != 1 else ''} among {len(self.candidates)} candidate structures"
        if self.certified:
            return f"certified extremal (Pontryagin first- and second-order conditions hold), {best}; global optimality not proved"
        c = self.certificate
        failed = [name for name, ok in (("first-order", c.first_order), ("strict bang-bang", c.strict_bang_bang),
                                        ("second-order", c.second_order)) if not ok]
        return f"refined, NOT certified ({', '.join(failed)} check failed), {best}"

    def to_dict(self):
        """Plain JSON-ready data: the keys of `ocp solve --json`."""
        p, s = self.problem, self.structure
        out = {
            "problem": p.kind,
            "kappa": p.kappa,
            "x0": list(p.x0),
            "target": list(self.target),
            "branch": self.answer_branch,
            "branch_pinned": p.branch is not None,
            "T": self.T,
            "T_error": self.T_error,
            "error_source": "refinement: the change between two integrator tolerances" if self.refined
                            else "direct transcription: observed bounds h^2/2 (T) and h (switch times)",
            "n_switches": self.n_switches,
            "first_u": self.first_u,
            "arc_signs": list(self.arc_signs),
            "switch_times": self.switch_times,
            "switch_time_error": self.switch_time_error,
            "switch_states": [list(x) for x in self.switch_states],
            "success": self.success,
            "status": self.status,
            "refined": self.refined is not None,
            "certified": self.certified,
            "verdict": self.verdict,
            "solver": self.method["solver"],
            "method": self.method,
            "iterations": self.iterations,
            "build_time_s": self.build_time_s,
            "solve_time_s": self.solve_time_s,
            "refine_time_s": self.refine_time_s,
            "total_time_s": self.total_time_s,
            "resim_miss": self.refined_resim_miss if self.refined else self.resim_miss,
            "miss_tol": self.miss_tol,
            "direct": {"success": self.direct_success, "T": self.T_direct, "branch": self.branch, "structure": s.to_dict(), "resim_miss": self.resim_miss,
                       "guess": self.guess, "starts": self.starts},
        }
        if self.refined is not None:
            out["refinement"] = self.refined.to_dict()
            out["certificate"] = self.certificate.to_dict()
        out["candidates"] = [c.to_dict() for c in self.candidates]
        x = self.crosscheck
        out["crosscheck"] = None if x is None else {
            "formula": x.formula, "max_deviation": x.max_deviation, "T": x.T, "switch_times": list(x.switch_times),
            "switch_states": [list(v) for v in x.switch_states], "formula_error": x.analytic.error}
        return out

    def summary(self):
        """A few lines a person can read."""
        p, s, m = self.problem, self.structure, self.method
        lines = [f"{p.kind}, kappa = {p.kappa:g}, from (theta, omega) = ({p.x0[0]:.6g}, {p.x0[1]:.6g}) "
                 f"to ({_angle(self.target[0])}, 0)  [branch k = {self.answer_branch}"
                 f"{', pinned' if p.branch is not None else ''}]"]
        if self.refined:
            lines.append(f"T = {defended(self.T, self.T_error)}   (refined; error estimate {self.T_error:.0e}; "
                         f"independent re-simulation misses the target by {self.refined_resim_miss:.0e})")
        else:
            lines.append(f"T = {defended(self.T, self.T_error)}   (direct transcription: error below h^2/2 observed, "
                         f"h = {s.h:.2g}; switch times within h; not refined)")
        # a state at a switch moves at most |omega| + kappa + 1 per unit of switch-time error
        state_error = lambda x: self.switch_time_error * (abs(x[1]) + p.kappa + 1)
        shown = (lambda v, e: defended(v, e)) if self.refined else _plus_minus
        signs = pattern(self.arc_signs)
        lines.append(f"{self.n_switches} switch{'es' if self.n_switches != 1 else ''}, u = {signs}"
                     + ("" if s.bang_bang else f"   (direct control NOT resolved as bang-bang: "
                                                f"{s.longest_interior_run} interior intervals in a row)"))
        for i, (tau, (th, om)) in enumerate(zip(self.switch_times, self.switch_states), 1):
            e = state_error((th, om))
            lines.append(f"  switch {i}: t = {shown(tau, self.switch_time_error)}  at (theta, omega) = "
                         f"({shown(th, e)}, {shown(om, e)})")
        lines.append(self.verdict)
        if self.crosscheck:
            lines.append(f"  cross-check: {self.crosscheck.formula}: largest deviation "
                         f"{self.crosscheck.max_deviation:.0e} (formula error {self.crosscheck.analytic.error:.0e})")
        if self.certificate:
            c = self.certificate
            lines.append(f"  residuals: p2 at switches {c.switch_residual:.0e}, |H| <= {c.hamiltonian_deviation:.0e}, "
                         f"sign(p2) = u everywhere: {c.sign_violation == 0 and c.extra_zeros == 0}, "
                         f"reduced Hessian eigenvalues {[float(f'{e:.3g}') for e in c.reduced_hessian_eigenvalues]}")
        for c in self.candidates:
            T = "-" if c.T is None else f"{c.T:.10f}"
            lines.append(f"  candidate {pattern(c.signs):<18} branch {c.branch:+d}  T = {T:<14} {c.status}  [{c.label}]")
        lines.append(f"direct: {'success' if self.direct_success else 'FAILED'}; "
                     f"T = {defended(self.T_direct, direct_T_accuracy(s.h))}; "
                     f"{m['solver']} {self.iterations} iterations; re-simulated miss {self.resim_miss:.1e} "
                     f"(tolerance {self.miss_tol:.0e})")
        lines.append(f"method: {m['transcription']}, N = {m['N']}, integrator {m['integrator']}"
                     + {"cvodes": f" (tol {m.get('tol', 0):g})", "radau": f" (degree {m.get('degree')})"}.get(
                         m["integrator"], f" (M = {m.get('M')})")
                     + f"; guess {self.guess} (best of {len(self.starts)} starts)"
                     f"; build {self.build_time_s:.2f} s, solve {self.solve_time_s:.2f} s, "
                     f"refine {self.refine_time_s:.2f} s, total {self.total_time_s:.2f} s")
        return "\n".join(lines)


def _angle(theta):
    k = theta / math.pi
    return f"{round(k)}*pi" if abs(k - round(k)) < 1e-12 and round(k) not in (0, 1) else (
        "pi" if abs(k - 1) < 1e-12 else "0" if k == 0 else f"{theta:.6g}")


def direct_T_accuracy(h):
    """The error bound of a direct T on grid spacing h: h^2/2. The switch interval's fractional
    control acts as a located switch, so the error is O(h^2); measured over N = 25..800 on the
    paper's four cases, |T - T*| / h^2 stays below 0.35 (tests/test_direct.py). Observed, not proved."""
    return h * h / 2


def _plus_minus(value, error):
    """value +- error, the value to the decimal of the error's first digit."""
    decimals = max(0, math.ceil(-math.log10(error)))
    return f"{value:.{decimals}f} +- {error:.1g}"
