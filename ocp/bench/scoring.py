"""A measurement scored against its reference: T - T_ref, the switch-time errors, and the outcome
class (`ocp.bench.outcomes.Outcome`), tried in the order of its `rank`:

    build error      the method could not be built (a plugin that cannot load, an option refused)
    time limit       the answer stopped at the solver's own limit (`Measurement.limits`: its
                     iterations per start, which decide alike on any machine, and the suite's
                     time limit as its CPU seconds where it has such an option; the search's own
                     time limit), or the solver's own CPU time exceeds the suite's limit
    no reference     the search found no optimum for the case
    the search       scored against the reference (Finch's formula where one applies, else its
                     own optimum): ok when |T - T_ref| <= T_error + T_ref_error, inaccurate when
                     it succeeded otherwise, not converged when it did not
    a direct answer  solver error when it raised; otherwise its `ocp.solving.classify` class
                     against the reference's optimum, ties and extremals (the optimum is "ok";
                     the optimum whose control misses the target by more than miss_tol but
                     within the transcription's own accuracy at its N is "discretisation", scored
                     on its T error and miss as "ok" is)
"""

from ..result import DirectClass
from ..solving import classify
from .outcomes import Outcome
from .row import Score


def outcome(m, ref, time_limit_s):
    """The Outcome of the Measurement `m` against the Reference `ref` (module doc)."""
    if m.status == "build_error":
        return Outcome.BUILD_ERROR
    if m.limited or (m.solver_cpu_time_s or 0.0) > time_limit_s:
        return Outcome.TIME_LIMIT
    if ref.T is None:
        return Outcome.NO_REFERENCE
    if m.direct_status is None and m.status != "solver_error":      # the search
        if not m.success:
            return Outcome.NOT_CONVERGED
        bound = (m.T_error or 0.0) + (ref.T_error or 0.0) + 1e-12
        return Outcome.OK if abs(m.T - ref.T) <= bound else Outcome.INACCURATE
    if m.direct_status is None:
        return Outcome.SOLVER_ERROR
    c = classify(m.direct_answer(), ref.answer, ref.ties, ref.extremals, ref.horizon)
    return Outcome.OK if c == DirectClass.OPTIMUM else Outcome[c.name]


def score(m, ref, time_limit_s):
    """The Score of the Measurement `m` against the Reference `ref`: the outcome, T - T_ref, and the
    switch-time errors where both have as many switches."""
    diff = errors = None
    if m.T is not None and ref.T is not None:
        diff = m.T - ref.T
        if len(m.switch_times) == len(ref.switch_times):
            errors = tuple(t - t_ref for t, t_ref in zip(m.switch_times, ref.switch_times))
    return Score(outcome=outcome(m, ref, time_limit_s), T_ref=ref.T, T_ref_error=ref.T_error, ref_source=ref.source,
                 T_minus_ref=diff, switch_time_errors=errors)

