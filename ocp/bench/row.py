"""The values of the bench, typed: an extremal and a reference (the search's optimum of a problem), a
measurement (one pair solved), and the row stored for a pair (the measurement scored against the
reference, with the pair and how it was timed). Each is a frozen dataclass, written to the store
as plain JSON (`to_dict`) and validated field by field when read back (`from_dict`: ValueError
naming the field, in one line). A new metric is one field of `Measurement` (with a default, so that
rows without it still read).

Times in seconds, memory in MiB; T, T_error and the switch times in the problem's time unit
(`ocp.core.model`); a branch is the integer k of the target reached, (base + 2 pi k, 0)
(`ocp.core.problem`).
"""

import dataclasses
import math
import types
import typing
from dataclasses import dataclass, field

from ..core.output import plain
from .outcomes import GOOD, Outcome
from .suite import SEARCH_FAMILY

#: the longest text a stored field holds (labels, messages): a longer one is not a row of ocp bench
MAX_TEXT = 10_000


@dataclass(frozen=True, kw_only=True)
class Extremal:
    """An extremal found by the search, as `ocp.solving.classify` compares it: arc signs, branch, T."""

    signs: tuple[int, ...]
    branch: int | None
    T: float


@dataclass(frozen=True, kw_only=True)
class Reference:
    """The reference of one problem: the search's optimum T (None where there is none, `source`
    says why), its error, structure and ties, every extremal found before `horizon`."""

    problem: str
    T: float | None
    T_error: float | None
    source: str
    time_s: float = 0.0
    arc_signs: tuple[int, ...] = ()
    switch_times: tuple[float, ...] = ()
    branch: int | None = None
    optimal: bool | None = None
    ties: tuple[Extremal, ...] = ()
    extremals: tuple[Extremal, ...] = ()
    horizon: float | None = None

    @property
    def answer(self):
        """The optimum as an Extremal (what `classify` compares a direct answer with)."""
        return Extremal(signs=self.arc_signs, branch=self.branch, T=self.T)


@dataclass(frozen=True, kw_only=True)
class Repeat:
    """The times of one cold repeat of a pair (wall clock; `cpu_time_s`: the worker process's CPU time,
    every thread, build, solve and checking together; `solver_cpu_time_s`: the solver's own, build
    and solves), and the worker's peak resident set during it."""

    build_time_s: float
    solve_time_s: float
    total_time_s: float
    cpu_time_s: float | None = None
    solver_cpu_time_s: float | None = None
    peak_rss_mib: float | None = None


@dataclass(frozen=True, kw_only=True)
class StartRecord:
    """One initial guess of a direct solve (`ocp.direct.solve.Start`): its label, how it ended
    (`DirectStatus` name) and why (`message`, with the numbers that decided it), the solver's own
    return status, whether it stopped at the solver's limit, T, iterations, the re-simulated miss
    and the largest accepted as a discretisation result, and the solver's own wall and CPU time."""

    guess: str
    status: str
    solver_message: str
    T: float | None
    iterations: int | None
    solve_time_s: float
    message: str = ""
    limited: bool | None = None
    resim_miss: float | None = None
    miss_bound: float | None = None
    cpu_time_s: float | None = None


@dataclass(frozen=True, kw_only=True)
class Structure:
    """The control's structure as `ocp.solving.classify` reads it."""

    arc_signs: tuple[int, ...]
    bang_bang: bool


@dataclass(frozen=True, kw_only=True)
class DirectAnswer:
    """A direct answer of a measurement in the shape `ocp.solving.classify` reads
    (`Measurement.direct_answer`)."""

    status: int
    T: float | None
    T_bound: float | None
    branch: int | None
    structure: Structure


@dataclass(frozen=True, kw_only=True)
class Measurement:
    """One pair solved `repeats` times, each cold: the fields of the first solve, the median of each
    time and of the peak resident set over the repeats (`times`), and the spread of T across them.
    The solver's own times (`build_time_s`, `solve_time_s`: its NLP solves of every start, wall;
    `solver_cpu_time_s`: the same in CPU time) are apart from the suite's checking (`check_time_s`
    = total - build - solve: the independent re-simulation of every start and the reading of its
    structure); `total_time_s` holds both. The time limit is the solver's own (`limits`: its
    options and their values; `limited`: the answer stopped at one). `miss_bound`: the largest
    miss of a discretisation result (miss_tol plus the transcription's own estimate of its
    integration error). `every_start`: each initial guess, how it ended and why.
    `direct_status` is the `ocp.direct.DirectStatus` of a direct answer (None for the search and for
    a failure before any answer); `status` its name, or the search's, or "build_error" /
    "solver_error"."""

    success: bool
    status: str
    message: str = ""
    solver_message: str | None = None
    direct_status: int | None = None
    converged: bool | None = None
    iterations: int | None = None
    T: float | None = None
    T_error: float | None = None
    branch: int | None = None
    n_switches: int | None = None
    arc_signs: tuple[int, ...] = ()
    switch_times: tuple[float, ...] = ()
    bang_bang: bool | None = None
    longest_interior_run: int | None = None
    resim_miss: float | None = None
    miss_bound: float | None = None
    limited: bool | None = None
    limits: dict = field(default_factory=dict)
    extremals_integrated: int | None = None
    starts: int = 0
    n_w: int = 0
    n_g: int = 0
    T_spread: float | None = None
    build_time_s: float = 0.0
    solve_time_s: float = 0.0
    total_time_s: float = 0.0
    check_time_s: float | None = None
    cpu_time_s: float | None = None
    solver_cpu_time_s: float | None = None
    peak_rss_mib: float | None = None
    peak_rss_scope: str | None = None
    times: tuple[Repeat, ...] = ()
    every_start: tuple[StartRecord, ...] = ()

    @property
    def solver_time_s(self):
        """The solver's own wall time, build and NLP solves of every start (for the search, its
        total): what the charts and profiles put on their time axis, apart from the suite's checking."""
        return self.build_time_s + self.solve_time_s

    def direct_answer(self):
        """The direct answer measured, as `ocp.solving.classify` reads it."""
        return DirectAnswer(status=self.direct_status, T=self.T, T_bound=self.T_error, branch=self.branch,
                            structure=Structure(arc_signs=self.arc_signs, bang_bang=bool(self.bang_bang)))


@dataclass(frozen=True, kw_only=True)
class Timing:
    """How a row was timed (`ocp.core.parallel.timing_note`)."""

    note: str
    executor: str | None = None
    workers: int | None = None
    parallel: bool | None = None
    concurrent_sessions: tuple[int, ...] = ()


@dataclass(frozen=True, kw_only=True)
class Score:
    """A measurement against its reference (`ocp.bench.scoring.score`): the outcome, the reference's
    T, error and source, T - T_ref, and the switch-time errors (None where the counts differ)."""

    outcome: Outcome
    T_ref: float | None
    T_ref_error: float | None
    T_minus_ref: float | None
    ref_source: str = ""
    switch_time_errors: tuple[float, ...] | None = None


@dataclass(frozen=True, kw_only=True)
class Row(Score, Measurement):
    """The stored row of one (case, method) pair: its Measurement and its Score, the pair (keys and
    labels), the suite settings it ran with, and how it was timed. `N` is None exactly for the
    extremal search."""

    case: str
    case_label: str
    problem: str
    family: str
    label: str
    guess: str | int
    N: int | None
    suite: str | None = None
    method: str | None = None
    configuration: str | None = None
    options: dict = field(default_factory=dict)
    repeats: int | None = None
    miss_tol: float | None = None
    time_limit_s: float | None = None
    timing: Timing

    @classmethod
    def of(cls, measurement, score, **pair):
        """The row of a Measurement and its Score, with the pair's fields `pair`."""
        return cls(**_fields(measurement), **_fields(score), **pair)

    def __post_init__(self):
        if self.total_time_s < 0:
            raise ValueError(f"total_time_s = {self.total_time_s!r} is negative")
        if (self.N is None) != (self.family == SEARCH_FAMILY):
            raise ValueError(f"N = {self.N!r} for the family {self.family[:40]!r}")
        if self.outcome in GOOD:
            if self.T is None or self.T_minus_ref is None:
                raise ValueError(f"outcome {self.outcome} without T or T - T_ref")
            if not self.total_time_s > 0:
                raise ValueError(f"outcome {self.outcome} in total_time_s = {self.total_time_s!r} (an answer takes time)")


def _fields(value):
    return {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}


def to_dict(value):
    """A value of this module as plain JSON data (tuples as lists, the outcome as its label)."""
    return plain({f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)})


def _plain(v):
    if dataclasses.is_dataclass(v):
        return to_dict(v)
    if isinstance(v, (tuple, list)):
        return [_plain(x) for x in v]
    return str(v) if isinstance(v, Outcome) else v


def from_dict(cls, data):
    """`cls` (a dataclass of this module) from plain data, every field checked against its type;
    ValueError saying which field is wrong. Keys that are not fields are ignored."""
    if not isinstance(data, dict):
        raise ValueError(f"is a {type(data).__name__}, not a record")
    hints = typing.get_type_hints(cls)
    values = {}
    for f in dataclasses.fields(cls):
        if f.name not in data:
            if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
                raise ValueError(f"has no {f.name!r}")
            continue
        try:
            values[f.name] = _typed(data[f.name], hints[f.name])
        except ValueError as err:
            raise ValueError(f"has {f.name} = {_short(data[f.name])}: {err}") from None
    try:
        return cls(**values)
    except ValueError as err:
        raise ValueError(f"has {err}") from None


def _typed(value, kind):
    """`value` as the type `kind` (a type of this module's fields), or ValueError."""
    options = typing.get_args(kind) if isinstance(kind, types.UnionType) else (kind,)
    if value is None:
        if type(None) in options:
            return None
        raise ValueError("missing")
    error = None
    for option in (o for o in options if o is not type(None)):
        try:
            return _one(value, option)
        except ValueError as err:
            error = err
    raise error


def _one(value, kind):
    origin = typing.get_origin(kind)
    if origin is tuple:
        if not isinstance(value, list):
            raise ValueError("not a list")
        return tuple(_typed(v, typing.get_args(kind)[0]) for v in value)
    if dataclasses.is_dataclass(kind):
        return from_dict(kind, value)
    if kind is Outcome:
        if not isinstance(value, str) or value not in set(Outcome):
            raise ValueError(f"not an outcome ({', '.join(Outcome)})")
        return Outcome(value)
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError("not a finite number")
        return float(value)
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError("not an integer")
        return value
    if kind is str and isinstance(value, str) and len(value) > MAX_TEXT:
        raise ValueError(f"a text of {len(value)} characters, more than ocp bench writes ({MAX_TEXT})")
    if kind is bool or kind is str or kind is dict:
        if not isinstance(value, kind):
            raise ValueError(f"not a {kind.__name__}")
        return value
    raise ValueError(f"not of the type ocp bench writes ({kind})")


def _short(value):
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
