"""The result of `ocp.solve`, built once (`ocp.solving.solve`), in the spirit of scipy's
`OptimizeResult`: a status code with a message table, `success` derived from it.

    Solution.status           SolveStatus: how the answer was obtained and what it proves
    Solution.direct_class     DirectClass: the direct transcription's answer against the search's
"""

import enum
import math
from dataclasses import dataclass

from .core.numbers import digits, order, plus_minus, printed_error
from .core.problem import Problem, angle_text
from .direct.structure import pattern


class SolveStatus(enum.IntEnum):
    OPTIMAL = 0
    BEST_FOUND = 1
    DIRECT_ONLY = 2
    NO_EXTREMAL = -1
    NOT_VERIFIED = -2
    DIRECT_FAILED = -3


STATUS_MESSAGES = {
    SolveStatus.OPTIMAL: "globally optimal: the least time among all extremals that reach the target set before "
                         "the horizon",
    SolveStatus.BEST_FOUND: "the least time among the extremals found; the scan left intervals unresolved, so "
                            "global optimality is not proved",
    SolveStatus.DIRECT_ONLY: "the direct transcription's answer, its control verified by re-simulation; not compared "
                             "with the extremals, so optimality is unknown",
    SolveStatus.NO_EXTREMAL: "no extremal reaches the target set before the largest horizon",
    SolveStatus.NOT_VERIFIED: "the best extremal misses the target when re-simulated independently",
    SolveStatus.DIRECT_FAILED: "the direct transcription found no verified answer (and no search was asked for)",
}


class DirectClass(enum.IntEnum):
    """The direct answer against the search's: the first class that applies."""

    OPTIMUM = 0
    INACCURATE = 1
    LOCAL_OPTIMUM = 2
    WRONG_STRUCTURE = 3
    BEYOND_HORIZON = 4
    CHATTERING = 5
    MISSES_TARGET = 6
    NOT_CONVERGED = 7
    SOLVER_ERROR = 8


DIRECT_MESSAGES = {
    DirectClass.OPTIMUM: "the optimum: the structure and branch of an optimal extremal, T within its stated bound",
    DirectClass.INACCURATE: "the optimal structure, but T outside its stated bound",
    DirectClass.LOCAL_OPTIMUM: "another extremal, slower than the optimum: a local optimum",
    DirectClass.WRONG_STRUCTURE: "a structure that no extremal found by the search has",
    DirectClass.BEYOND_HORIZON: "slower than the horizon of the search: not an optimum, not classified further",
    DirectClass.CHATTERING: "the control is not resolved as bang-bang (chattering or an interior run)",
    DirectClass.MISSES_TARGET: "the solver converged, but its control misses the target when re-simulated",
    DirectClass.NOT_CONVERGED: "the NLP solver did not converge",
    DirectClass.SOLVER_ERROR: "the NLP solver raised an error or returned no usable point",
}


@dataclass(frozen=True)
class Solution:
    """A minimum-time solution and how it was obtained.

    problem        the Problem solved (its `reading`: the circle or the plane)
    status         SolveStatus; `success` is status >= 0, `message` its text, `optimal` True,
                   False (never: a worse answer is not returned) or None (unknown)
    answer         the optimal extremal (`ocp.indirect.Extremal`: signs, durations, T, switch times
                   and states, branch, p(0), error estimates), None without a search
    ties           other extremals with the same T within their accuracy (mirror images, other
                   branches): every optimal control
    runner_up      the fastest extremal slower than the optimum (None if none before the horizon)
    extremals      every extremal the search solved, fastest first
    coverage       what the scan covered (`ocp.indirect.Coverage`)
    resim_miss     the distance from the target in (theta, omega) of the answer's control
                   re-simulated independently (the certificate's CVODES integration, 1e-14; for a
                   direct answer, its own re-simulation by scipy's DOP853)
    certificate    first- and second-order conditions checked independently (`ocp.indirect.Certificate`)
    crosscheck     the answer against Finch's formula of its structure, where one applies
    direct         the direct transcription's answer (`ocp.direct.DirectSolution`), if one was asked for
    direct_class   DirectClass of it against the search, None without both
    notes          what the search said on its way (horizons tried)
    search_time_s, certificate_time_s, direct_time_s, total_time_s
    """

    problem: Problem
    status: SolveStatus
    answer: object
    ties: tuple
    runner_up: object
    extremals: tuple
    coverage: object
    resim_miss: float | None
    certificate: object
    crosscheck: object
    direct: object
    direct_class: DirectClass | None
    notes: tuple
    search_time_s: float
    certificate_time_s: float
    direct_time_s: float
    total_time_s: float

    @property
    def success(self):
        return self.status >= 0

    @property
    def message(self):
        return STATUS_MESSAGES[self.status]

    @property
    def optimal(self):
        return True if self.status == SolveStatus.OPTIMAL else None

    @property
    def from_search(self):
        return self.answer is not None

    # the answer's numbers: from the search where there is one, else from the direct solve
    @property
    def T(self):
        return self.answer.T if self.answer else (self.direct.T if self.direct else math.nan)

    @property
    def T_error(self):
        """Error estimate of T (the search's two tolerances), the direct bound (None where none is
        stated), or None for a failure."""
        if not self.success:
            return None
        return self.answer.T_error if self.answer else self.direct.T_bound

    @property
    def branch(self):
        return self.answer.branch if self.answer else (self.direct.branch if self.direct else None)

    @property
    def target(self):
        return None if self.branch is None else self.problem.target(self.branch)

    @property
    def arc_signs(self):
        return tuple(self.answer.signs) if self.answer else (self.direct.structure.arc_signs if self.direct else ())

    @property
    def n_switches(self):
        return max(len(self.arc_signs) - 1, 0)

    @property
    def switch_times(self):
        return tuple(self.answer.switch_times) if self.answer else (
            tuple(self.direct.structure.switch_times) if self.direct else ())

    @property
    def switch_time_error(self):
        """The search's estimate, or h for a direct answer (its switch located within an interval)."""
        if not self.success:
            return None
        return self.answer.switch_time_error if self.answer else self.direct.structure.h

    @property
    def switch_states(self):
        return tuple(self.answer.switch_states) if self.answer else (
            tuple(self.direct.structure.switch_states) if self.direct else ())

    @property
    def certified(self):
        return bool(self.certificate and self.certificate.certified)

    @property
    def verdict(self):
        """What this result is, in one sentence."""
        if not self.success:
            return f"no solution: {self.message}"
        if self.answer is None:
            return self.message
        if self.answer.solved == "exact":
            return "the start is on the target: T = 0, no control needed"
        text = self.message + f" ({self.coverage.describe()})"
        if self.ties:
            text += f"; {len(self.ties) + 1} optimal controls tie"
        if self.runner_up is not None:
            gap = self.runner_up.T - self.answer.T
            text += (f"; the runner-up extremal takes {digits(self.runner_up.T, self.runner_up.T_error)} "
                     f"({100 * gap / self.answer.T:.3g} % slower)")
        else:
            text += "; no other extremal before the horizon"
        return text

    def to_dict(self):
        """Plain JSON-ready data: the keys of `ocp solve --json`."""
        p = self.problem
        out = {
            "problem": p.kind, "kappa": p.kappa, "x0": list(p.x0), "reading": p.reading,
            "branch_pinned": p.branch, "success": self.success, "status": self.status.name.lower(),
            "message": self.message, "optimal": "unknown" if self.optimal is None else self.optimal,
            "verdict": self.verdict,
        }
        if self.success:
            out.update({
                "T": self.T, "T_error": self.T_error,
                "error_source": ("the change of T between two integration accuracies of the search" if self.answer
                                 else "the direct transcription's measured bound h^2/2 (none where not measured)"),
                "branch": self.branch, "target": list(self.target), "n_switches": self.n_switches,
                "arc_signs": list(self.arc_signs), "switch_times": list(self.switch_times),
                "switch_time_error": self.switch_time_error,
                "switch_states": [list(x) for x in self.switch_states], "resim_miss": self.resim_miss,
            })
        elif self.status == SolveStatus.NOT_VERIFIED:
            # the evidence of the failure; the extremal that misses gets no T and no error estimate
            out.update({"resim_miss": self.resim_miss,
                        "unverified": {"arc_signs": list(self.answer.signs), "branch": self.answer.branch}})
        if self.answer is not None and self.success:
            out.update({
                "ties": [t.to_dict() for t in self.ties],
                "runner_up": None if self.runner_up is None else self.runner_up.to_dict(),
                "extremals": [e.to_dict() for e in self.extremals],
                "coverage": None if self.coverage is None else self.coverage.to_dict(),
                "certificate": None if self.certificate is None else self.certificate.to_dict(),
            })
        if self.answer is not None and not self.success:
            out["coverage"] = None if self.coverage is None else self.coverage.to_dict()
        x = self.crosscheck if self.success else None
        out["crosscheck"] = None if x is None else {
            "formula": x.formula, "max_deviation": x.max_deviation, "T": x.T, "switch_times": list(x.switch_times),
            "switch_states": [list(v) for v in x.switch_states], "formula_error": x.analytic.error}
        out["direct"] = None if self.direct is None else dict(
            self.direct.to_dict(), classified=None if self.direct_class is None else self.direct_class.name.lower(),
            classification=None if self.direct_class is None else DIRECT_MESSAGES[self.direct_class],
            T_minus_optimum=None if self.answer is None or not self.success or not self.direct.success
            else self.direct.T - self.answer.T)
        out["notes"] = list(self.notes)
        out.update(search_time_s=self.search_time_s, certificate_time_s=self.certificate_time_s,
                   direct_time_s=self.direct_time_s, total_time_s=self.total_time_s)
        return out

    def summary(self):
        """A few lines a person can read: the failure first if it failed."""
        p = self.problem
        lines = [p.describe()]
        if not self.success:
            line = f"NO SOLUTION: {self.message}"
            if self.status == SolveStatus.NOT_VERIFIED:
                line += f" (by {order(self.resim_miss)}); no time is claimed for it"
            lines.append(line)
            lines += [f"  {n}" for n in self.notes]
            if self.direct is not None:
                lines.append(self._direct_line())
            return "\n".join(lines)
        lines.append(f"reached ({angle_text(self.target[0])}, 0), branch k = {self.branch}")
        if self.answer is not None:
            lines.append(f"T = {digits(self.T, self.T_error)}   (error estimate {order(printed_error(self.T, self.T_error))}, rounding included; the control "
                         f"re-simulated independently misses the target by {order(self.resim_miss)})")
        else:
            bound = self.direct.T_bound
            lines.append(f"T = {plus_minus(self.T, bound) if bound else digits(self.T, None)}   (direct transcription, "
                         f"{'error below h^2/2 as measured' if bound else 'no error bound measured for this method'}; "
                         f"optimal: unknown)")
        lines.append(f"{self.n_switches} switch{'es' if self.n_switches != 1 else ''}, u = {pattern(self.arc_signs)}")
        e = self.switch_time_error
        shown = digits if self.answer is not None else plus_minus
        for i, (tau, (th, om)) in enumerate(zip(self.switch_times, self.switch_states), 1):
            # a state at a switch moves at most |omega| + kappa + 1 per unit of switch-time error
            es = e * (abs(om) + p.kappa + 1)
            lines.append(f"  switch {i}: t = {shown(tau, e)}  at (theta, omega) = ({shown(th, es)}, {shown(om, es)})")
        lines.append(self.verdict)
        for t in self.ties:
            lines.append(f"  tie: u = {pattern(t.signs)} to branch {t.branch}, T = {digits(t.T, t.T_error)}")
        if self.crosscheck:
            lines.append(f"  cross-check: {self.crosscheck.formula}: largest deviation "
                         f"{order(self.crosscheck.max_deviation)} (formula error {order(self.crosscheck.analytic.error)})")
        if self.certificate:
            c = self.certificate
            eig = ", ".join(digits(v, c.eigenvalue_error) for v in c.reduced_hessian_eigenvalues) or "none (one switch)"
            lines.append(f"  certificate ({'holds' if c.certified else 'FAILS'}): p2 at switches {order(c.switch_residual)}, "
                         f"|H| <= {order(c.hamiltonian_deviation)}, u = sign(p2) everywhere: "
                         f"{c.sign_violation == 0 and c.extra_zeros == 0}, reduced Hessian eigenvalues: {eig}")
        for x in self.extremals[:6]:
            lines.append(f"  extremal u = {pattern(x.signs):<18} branch {x.branch:+d}  T = {digits(x.T, x.T_error)}")
        if len(self.extremals) > 6:
            lines.append(f"  ... {len(self.extremals) - 6} more extremals (--json lists them)")
        if self.direct is not None:
            lines.append(self._direct_line())
        lines.append(f"time: search {self.search_time_s:.3f} s, certificate {self.certificate_time_s:.3f} s, "
                     f"direct {self.direct_time_s:.3f} s, total {self.total_time_s:.3f} s")
        return "\n".join(lines)

    def _direct_line(self):
        d = self.direct
        head = f"direct: {d.method['transcription']} {describe_method(d.method)}, {d.method['solver']}: {d.message}"
        n = d.structure.n_switches
        if d.success:
            T = plus_minus(d.T, d.T_bound) if d.T_bound else digits(d.T, None) + ", no error bound measured"
            head += (f"; T = {T}, {n} switch{'es' if n != 1 else ''}, re-simulated miss {order(d.resim_miss)}")
        elif d.converged:
            head += f" by {order(d.resim_miss)} (more than {order(d.miss_tol)}): not a transfer, no time is claimed"
        if self.direct_class is not None:
            head += f"\n  classified: {self.direct_class.name.lower().replace('_', ' ')} ({DIRECT_MESSAGES[self.direct_class]})"
        return head


def describe_method(method):
    """The settings of a direct method record, in one parenthesis."""
    skip = {"transcription", "solver", "options"}
    return "(" + ", ".join(f"{k} = {v}" for k, v in method.items() if k not in skip) + ")"
