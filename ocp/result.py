"""The result of `ocp.solve`, built once (`ocp.solving.solve`), in the spirit of scipy's
`OptimizeResult` and python-control's `OptimalControlResult`: a status code with a message table,
`success` derived from it, and one `Answer` whichever method produced it.

    Solution.status           SolveStatus: how the answer was obtained and what it proves
    Solution.best             Answer: T, its error, branch, arcs, switches, and its source
    Solution.direct_class     DirectClass: the direct transcription's answer against the search's
    Solution.sample(t)        the trajectory at any times (`ocp.sampling`)
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from .core.errors import InputError
from .core.numbers import digits, order, plus_minus, printed_error
from .core.problem import Problem, angle_text
from .direct.structure import pattern

#: a re-simulation error estimate below this is rounding (a re-simulated miss is ~1e-13 at best) and not printed
RESIM_ROUNDING = 1e-12

if TYPE_CHECKING:                     # the types of the fields, for readers and checkers only
    from .direct import DirectSolution
    from .exact.finch import Crosscheck
    from .indirect import Certificate, Coverage, Extremal


class _Named(enum.IntEnum):
    """An IntEnum that prints its name ("optimal"), not its number, and knows its message."""

    def __str__(self):
        return self.name.lower()

    def __format__(self, spec):
        return format(str(self), spec)

    @property
    def message(self):
        return _MESSAGES[type(self)][self]


class SolveStatus(_Named):
    OPTIMAL = 0
    BEST_FOUND = 1
    DIRECT_ONLY = 2
    STOPPED = 3
    DIRECT_DISCRETISATION = 4
    NO_EXTREMAL = -1
    NOT_VERIFIED = -2
    DIRECT_FAILED = -3
    STOPPED_EMPTY = -4
    UNRESOLVED_EMPTY = -5


STATUS_MESSAGES = {
    SolveStatus.OPTIMAL: "globally optimal: the least time among all extremals that reach the target set before "
                         "the horizon",
    SolveStatus.BEST_FOUND: "the least time among the extremals found; the scan left intervals unresolved, so "
                            "global optimality is not proved",
    SolveStatus.DIRECT_ONLY: "the direct transcription's answer, its control verified by re-simulation; not compared "
                             "with the extremals, so optimality is unknown",
    SolveStatus.STOPPED: "stopped at the time limit: the best extremal found so far, not proven optimal",
    SolveStatus.DIRECT_DISCRETISATION: "the direct transcription's answer within its own discretisation error: its "
                                       "control re-simulated misses the target by more than miss_tol, but no more "
                                       "than miss_tol plus the transcription's estimate of its integration error; "
                                       "not compared with the extremals, so optimality is unknown",
    SolveStatus.NO_EXTREMAL: "no extremal reaches the target set before the largest horizon",
    SolveStatus.NOT_VERIFIED: "the best extremal misses the target when re-simulated independently",
    SolveStatus.DIRECT_FAILED: "the direct transcription found no verified answer (and no search was asked for)",
    SolveStatus.STOPPED_EMPTY: "stopped at the time limit before any extremal reaching the target set was found",
    SolveStatus.UNRESOLVED_EMPTY: "no extremal reaching the target set was found, but the scan left intervals "
                                  "unresolved, so that none reaches it before the largest horizon is not proved",
}


class DirectClass(_Named):
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
    DISCRETISATION = 9


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
    DirectClass.DISCRETISATION: "the optimum at the transcription's accuracy: the structure and branch of an optimal "
                                "extremal, T within its stated bound, the control re-simulated missing the target "
                                "by more than miss_tol but within the transcription's own accuracy at its N",
}
_MESSAGES = {SolveStatus: STATUS_MESSAGES, DirectClass: DIRECT_MESSAGES}


class Source(enum.Enum):
    """Where an Answer comes from."""

    SEARCH = "search"
    DIRECT = "direct transcription"

    def __str__(self):
        return self.value


@dataclass(frozen=True)
class Answer:
    """The answer of a solve, whichever method gave it (times nondimensional, angles in rad).

    T                  the least time found
    T_error            its error: the search's estimate (two integration accuracies, rounding
                       included) or the direct transcription's measured bound h^2/2; None: unknown
    error_source       how T_error was obtained, in words
    branch             the target branch k reached (swing-up: theta = pi + 2 pi k; damping: 2 pi k)
    arc_signs          u = +1 or -1 on each arc, first arc first (() for a start on the target)
    switch_times       t of each switch, increasing
    switch_states      (theta, omega) at each switch
    switch_time_error  the switch times' error: the search's estimate, or the grid step h of a direct
                       answer (its switch located within an interval)
    source             Source.SEARCH (the complete search of extremals) or Source.DIRECT
    method             the method in words (the transcription, its settings and the NLP solver)
    """

    T: float
    T_error: float | None
    error_source: str
    branch: int
    arc_signs: tuple[int, ...]
    switch_times: tuple[float, ...]
    switch_states: tuple[tuple[float, float], ...]
    switch_time_error: float
    source: Source
    method: str

    @property
    def n_switches(self):
        return max(len(self.arc_signs) - 1, 0)

    @property
    def signs(self):
        """arc_signs, by the name of `ocp.indirect.Extremal` (so that code reading an extremal's
        structure, such as `ocp.exact.finch.crosscheck`, reads an Answer too)."""
        return self.arc_signs

    @classmethod
    def of_extremal(cls, e):
        """The Answer of an extremal of the search (`ocp.indirect.Extremal`)."""
        return cls(T=float(e.T), T_error=float(e.T_error),
                   error_source="the change of T between two integration accuracies of the search",
                   branch=e.branch, arc_signs=tuple(e.signs), switch_times=tuple(e.switch_times),
                   switch_states=tuple(tuple(x) for x in e.switch_states), switch_time_error=float(e.switch_time_error),
                   source=Source.SEARCH, method="complete search of extremals")

    @classmethod
    def of_direct(cls, d):
        """The Answer of a verified direct solution (`ocp.direct.DirectSolution`)."""
        s = d.structure
        return cls(T=d.T, T_error=d.T_bound,
                   error_source="the direct transcription's measured bound h^2/2 (none where not measured)",
                   branch=d.branch, arc_signs=tuple(s.arc_signs), switch_times=tuple(s.switch_times),
                   switch_states=tuple(tuple(x) for x in s.switch_states), switch_time_error=s.h,
                   source=Source.DIRECT, method=direct_method(d.method))


@dataclass(frozen=True, kw_only=True)
class Solution:
    """A minimum-time solution and how it was obtained.

    problem        the Problem solved (its `reading`: the circle or the plane)
    status         SolveStatus (`str()` its name, `.message` its text); `success` is status >= 0,
                   `message` its text, `optimal` True, False (never: a worse answer is not returned)
                   or None (unknown)
    best           the Answer (`T`, `T_error`, `branch`, `arc_signs`, `switch_times`, `switch_states`,
                   `switch_time_error` read it), None exactly when the solve failed (nothing claimed)
    answer         the optimal extremal of the search (`ocp.indirect.Extremal`: signs, durations, T,
                   switch times and states, branch, p(0), error estimates), None without a search
    ties           other extremals with the same T within their accuracy (mirror images, other
                   branches): every optimal control
    runner_up      the fastest extremal slower than the optimum (None if none before the horizon, or if
                   the scan for it was cut at its budget: `notes`)
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
    search_time_s, certificate_time_s, direct_time_s, total_time_s   wall-clock seconds of each part
    """

    problem: Problem
    status: SolveStatus
    best: Answer | None
    answer: Extremal | None = None
    ties: tuple[Extremal, ...] = ()
    runner_up: Extremal | None = None
    extremals: tuple[Extremal, ...] = ()
    coverage: Coverage | None = None
    resim_miss: float | None = None
    certificate: Certificate | None = None
    crosscheck: Crosscheck | None = None
    direct: DirectSolution | None = None
    direct_class: DirectClass | None = None
    notes: tuple = ()
    search_time_s: float = 0.0
    certificate_time_s: float = 0.0
    direct_time_s: float = 0.0
    total_time_s: float = 0.0

    def __post_init__(self):
        if (self.best is not None) != self.success:
            raise ValueError(f"a Solution of status {self.status} {'needs' if self.success else 'claims no'} Answer")

    @property
    def success(self):
        return self.status >= 0

    @property
    def message(self):
        return self.status.message

    @property
    def optimal(self):
        return True if self.status == SolveStatus.OPTIMAL else None

    @property
    def from_search(self):
        return self.answer is not None

    # the Answer's numbers (NaN, None or () where the solve failed)
    @property
    def T(self):
        return self.best.T if self.best else math.nan

    @property
    def T_error(self):
        """Error of T: the search's estimate, the direct bound (None where none is stated), or None
        for a failure."""
        return self.best.T_error if self.best else None

    @property
    def branch(self):
        return self.best.branch if self.best else None

    @property
    def target(self):
        return None if self.branch is None else self.problem.target(self.branch)

    @property
    def arc_signs(self):
        return self.best.arc_signs if self.best else ()

    @property
    def n_switches(self):
        return max(len(self.arc_signs) - 1, 0)

    @property
    def switch_times(self):
        return self.best.switch_times if self.best else ()

    @property
    def switch_time_error(self):
        """The search's estimate, or h for a direct answer (its switch located within an interval)."""
        return self.best.switch_time_error if self.best else None

    @property
    def switch_states(self):
        return self.best.switch_states if self.best else ()

    def sample(self, t=None, every=None):
        """The answer's trajectory (`ocp.sampling.Samples`: t, theta, omega, u, p1, p2, their error
        estimates) at the times `t` in [0, T], or every `every` time units with every switch and T
        (give one). From the search: the certified extremal integrated arc by arc from x0, its
        costate from p(0); from a direct answer: its own piecewise-constant control, no costate."""
        if self.best is None:
            raise InputError(f"no answer to sample: {self.message}")
        if self.best.source is Source.SEARCH:
            return sample_extremal(self.problem, self.answer, t, every)
        return sample_direct(self.problem, self.direct, t, every)

    @property
    def certified(self):
        return bool(self.certificate and self.certificate.certified)

    @property
    def verdict(self):
        """What this result is, in one sentence."""
        if not self.success:
            return f"no solution: {self.message}"
        if self.best.source is Source.DIRECT:
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
        elif self.coverage.complete:
            text += "; no other extremal before the horizon"
        else:
            text += "; no other extremal found before the scan ended"
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
                "T": self.T, "T_error": self.T_error, "error_source": self.best.error_source,
                "source": str(self.best.source), "method": self.best.method,
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
        if self.coverage is not None and not self.success:      # what was scanned, found wanting
            out["coverage"] = self.coverage.to_dict()
        x = self.crosscheck if self.success else None
        out["crosscheck"] = None if x is None else {
            "formula": x.formula, "max_deviation": x.max_deviation, "T": x.T, "switch_times": list(x.switch_times),
            "switch_states": [list(v) for v in x.switch_states], "formula_error": x.analytic.error}
        out["direct"] = None if self.direct is None else dict(
            self.direct.to_dict(), classified=None if self.direct_class is None else self.direct_class.name.lower(),
            classification=None if self.direct_class is None else self._classification(),
            T_minus_optimum=None if self.answer is None or not self.success or not self.direct.success
            else self.direct.T - self.answer.T)
        out["notes"] = list(self.notes)
        out.update(search_time_s=self.search_time_s, certificate_time_s=self.certificate_time_s,
                   direct_time_s=self.direct_time_s, total_time_s=self.total_time_s)
        return out

    def _resim_error(self):
        """', to within E (the re-simulation's own accuracy)' where that is above the rounding."""
        error = self.certificate.final_state_error if self.certificate else 0.0
        return f", re-simulated to within {order(error)}" if error > RESIM_ROUNDING else ""

    def summary(self):
        """A few lines a person can read: the failure first if it failed."""
        p = self.problem
        lines = [p.describe()]
        if not self.success:
            line = f"NO SOLUTION: {self.message}"
            if self.status == SolveStatus.NOT_VERIFIED:
                line += f" (by {order(self.resim_miss)}{self._resim_error()}); no time is claimed for it"
            lines.append(line)
            lines += [f"  {n}" for n in self.notes]
            if self.direct is not None:
                lines.append(self._direct_line())
            return "\n".join(lines)
        lines.append(f"reached ({angle_text(self.target[0])}, 0), branch k = {self.branch}")
        if self.best.source is Source.SEARCH:
            lines.append(f"T = {digits(self.T, self.T_error)}   (error estimate {order(printed_error(self.T, self.T_error))}, rounding included; the control "
                         f"re-simulated independently misses the target by {order(self.resim_miss)}{self._resim_error()})")
        else:
            measured = ", error below h^2/2 as measured" if self.T_error else ""
            lines.append(f"T = {self._direct_T()}   (direct transcription{measured}; optimal: unknown)")
        lines.append(f"{self.n_switches} switch{'es' if self.n_switches != 1 else ''}, u = {pattern(self.arc_signs)}")
        e = self.switch_time_error
        shown = digits if self.best.source is Source.SEARCH else plus_minus
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
        head = f"direct: {direct_method(d.method)}: {d.message}"
        n = d.structure.n_switches
        if d.lands_on_target:
            head += (f"; T = {self._direct_T()}, {n} switch{'es' if n != 1 else ''}, re-simulated miss {order(d.resim_miss)}")
        elif d.converged:
            head += f" by {order(d.resim_miss)} (more than {order(d.miss_tol)}): not a transfer, no time is claimed"
        if self.direct_class is not None:
            head += f"\n  classified: {str(self.direct_class).replace('_', ' ')} ({self._classification()})"
        return head

    def _direct_T(self):
        """The direct answer's T with its one accuracy statement: its bound, or that none is measured."""
        d = self.direct
        if d.T_bound:
            return plus_minus(d.T, d.T_bound)
        return f"{d.T:.6g} (accuracy unknown: no error bound is measured for this method)"

    def _classification(self):
        """The direct class in words; an optimum without a stated bound says so, with its distance."""
        if self.direct_class == DirectClass.OPTIMUM and self.direct.T_bound is None:
            return (f"the structure and branch of an optimal extremal; |T - T*| = "
                    f"{order(abs(self.direct.T - self.answer.T))}, no bound stated to compare it with")
        return DIRECT_MESSAGES[self.direct_class]


def sample_extremal(problem, extremal, t=None, every=None):
    """Samples of an extremal of the search (its arcs between its switch times, its costate)."""
    from . import sampling

    knots = (0.0, *extremal.switch_times, extremal.T)
    return sampling.sample(problem.x0, problem.kappa, knots, extremal.signs, _times(knots, t, every),
                           problem.target(extremal.branch), "the extremal of the complete search",
                           p0=tuple(extremal.p0), knot_error=extremal.switch_time_error)


def sample_direct(problem, direct, t=None, every=None):
    """Samples of a direct answer: its piecewise-constant control on its own grid, re-integrated."""
    from . import sampling

    knots, values = sampling.runs(direct.t, direct.u)
    return sampling.sample(problem.x0, problem.kappa, knots, values, _times(knots, t, every),
                           problem.target(direct.branch), f"the direct answer, {direct_method(direct.method)}")


def _times(knots, t, every):
    from . import sampling

    if (t is None) == (every is None):
        raise InputError("sample: give the times t or a spacing every (one of them)")
    return sampling.times(knots, every) if every is not None else t


def direct_method(method):
    """A direct method record in words: the transcription, its settings, the NLP solver."""
    return f"{method['transcription']} {describe_method(method)}, {method['solver']}"


def describe_method(method):
    """The settings of a direct method record, in one parenthesis."""
    skip = {"transcription", "solver", "options"}
    return "(" + ", ".join(f"{k} = {v}" for k, v in method.items() if k not in skip) + ")"
