"""`ocp score`: a solution from any tool against its reference instance.

Accepted files (the format is in reference/README.md):

    bang-bang answer   JSON {"instance": ID, "arc_signs": [+1/-1, ...], "switch_times": [...], "T": ...}
                       (numbers or decimal text)
    sampled control    CSV with a header t,u and rows t_k, u_k (t ascending from 0 to T); comment lines
                       "# instance: ID" and "# interpolation: constant" (u_k on [t_k, t_k+1), the default)
                       or "# interpolation: linear"
    ocp's own JSON     the output of `ocp solve --json` (the instance found from its problem)

The control is re-simulated from x0 by scipy's DOP853 at RTOL and again at CHECK_RTOL (their
difference is the accuracy of the final state), restarted at every switch or sample. Its class, the
first that applies (`Class`):

    misses the target   x(T) is more than MISS_TOL from every allowed target state
    optimum             the arc signs and branch of the optimum or a tie
    local optimum       those of another extremal of the instance that is a local optimum
    wrong structure     anything else (a saddle extremal, a structure no extremal has, a control
                        that is not bang-bang)
"""

import csv
import enum
import io
import json
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from ..core import model
from ..core.errors import InputError
from . import data

RTOL = 1e-13
CHECK_RTOL = 1e-11
#: the largest distance of x(T) from the target accepted, in (theta, omega)
MISS_TOL = 1e-6
#: |u| may exceed 1 by this much (an interior-point solver relaxes its bounds by about 1e-8), then is clipped
BOUND_TOL = 1e-6
MAX_BYTES = 20_000_000
#: the longest control re-simulated (every optimum of the set takes less than 100)
MAX_T = 1000.0
MAX_ROWS = 1_000_000


class Class(enum.IntEnum):
    OPTIMUM = 0
    LOCAL_OPTIMUM = 1
    WRONG_STRUCTURE = 2
    MISSES_TARGET = 3


MESSAGES = {
    Class.OPTIMUM: "the optimum: the arc signs and branch of a globally optimal extremal",
    Class.LOCAL_OPTIMUM: "a local optimum: another extremal of the instance, slower than the optimum",
    Class.WRONG_STRUCTURE: "a structure that is no locally optimal extremal of the instance",
    Class.MISSES_TARGET: f"the control, re-simulated, misses the target by more than {MISS_TOL:g}",
}


@dataclass(frozen=True)
class Control:
    """A control read from a file: piecewise constant or linear on nodes t (u at the nodes), or bang-bang
    (arc signs and switch times); T; the instance id it names (or None)."""

    kind: str
    T: Decimal
    t: tuple = ()
    u: tuple = ()
    arc_signs: tuple = ()
    switch_times: tuple = ()
    instance: str | None = None
    source: str = ""


@dataclass(frozen=True)
class Score:
    """The score of a control against an instance: its class, T - T* (and relative), the miss at T with
    the re-simulation's accuracy, the structure read, the extremal matched (and how much slower)."""

    instance: str
    format: str
    cls: Class
    T: float
    T_ref: str
    T_ref_error: str
    T_minus_ref: float
    miss: float
    miss_accuracy: float
    final_state: tuple
    branch: int
    arc_signs: tuple
    switch_times: tuple
    bang_bang: bool
    matched: dict | None
    switch_time_errors: tuple | None
    notes: tuple = field(default=())

    @property
    def message(self):
        return MESSAGES[self.cls]

    def to_dict(self):
        return {"instance": self.instance, "format": self.format, "class": self.cls.name.lower().replace("_", " "),
                "message": self.message, "T": self.T, "T_ref": self.T_ref, "T_ref_error": self.T_ref_error,
                "T_minus_ref": self.T_minus_ref, "relative_T_minus_ref": self.T_minus_ref / float(self.T_ref),
                "miss": self.miss, "miss_accuracy": self.miss_accuracy, "final_state": list(self.final_state),
                "branch": self.branch, "arc_signs": list(self.arc_signs), "switch_times": list(self.switch_times),
                "bang_bang": self.bang_bang, "matched": self.matched,
                "switch_time_errors": None if self.switch_time_errors is None else list(self.switch_time_errors),
                "notes": list(self.notes)}

    def summary(self):
        from ..core.numbers import order
        from ..direct.structure import pattern

        lines = [f"{self.instance} ({self.format}): {self.cls.name.lower().replace('_', ' ')}: {self.message}",
                 f"T = {self.T!r}, T* = {self.T_ref} (error {self.T_ref_error}), T - T* = {self.T_minus_ref:.3e} "
                 f"({100 * self.T_minus_ref / float(self.T_ref):.3g} %)",
                 f"re-simulated: x(T) = ({self.final_state[0]:.12g}, {self.final_state[1]:.12g}), miss {self.miss:.2e} "
                 f"(accuracy {order(self.miss_accuracy)}) from branch {self.branch}",
                 f"structure: u = {pattern(self.arc_signs)}{'' if self.bang_bang else ' (not resolved as bang-bang)'}"]
        if self.matched:
            m = self.matched
            lines.append(f"matches the {m['which']}: u = {pattern(m['arc_signs'])} to branch {m['branch']}, "
                         f"T = {m['T']!r} ({m['slower_by']:.3e} slower than the optimum)")
        if self.switch_time_errors:
            lines.append("switch times - reference: " + ", ".join(f"{e:.2e}" for e in self.switch_time_errors))
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)


def _number(name, value):
    """A Decimal of a JSON number or decimal text (finite), or InputError."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise InputError(f"{name} = {str(value)[:40]!r} is not a number; accepted: a number or decimal text")
    try:
        number = Decimal(str(value).strip())
    except InvalidOperation:
        raise InputError(f"{name} = {str(value)[:40]!r} is not a number; accepted: a number or decimal text") from None
    if not number.is_finite():
        raise InputError(f"{name} = {str(value)[:40]!r} is not finite")
    return number


ANSWER_KEYS = {"instance", "arc_signs", "switch_times", "T", "tool", "note"}


def _answer(obj, source):
    """The Control of a bang-bang answer."""
    extra = set(obj) - ANSWER_KEYS
    if extra:
        raise InputError(f"{source}: unknown key {sorted(extra)[0]!r}; a bang-bang answer has {', '.join(sorted(ANSWER_KEYS))}")
    for key in ("arc_signs", "switch_times", "T"):
        if key not in obj:
            raise InputError(f"{source}: the key {key!r} is missing; a bang-bang answer has instance, arc_signs, "
                             f"switch_times, T")
    signs, times = obj["arc_signs"], obj["switch_times"]
    if not isinstance(signs, list) or not signs or any(s not in (1, -1) or isinstance(s, bool) for s in signs):
        raise InputError(f"{source}: arc_signs must be a non-empty list of +1 and -1")
    if any(a == b for a, b in zip(signs, signs[1:])):
        raise InputError(f"{source}: arc_signs must alternate (+1, -1, ...): neighbours of one sign are one arc")
    if not isinstance(times, list) or len(times) != len(signs) - 1:
        raise InputError(f"{source}: switch_times must be a list of {len(signs) - 1} numbers (one fewer than arc_signs)")
    times = tuple(_number("switch_times", t) for t in times)
    T = _number("T", obj["T"])
    if not all(a < b for a, b in zip((Decimal(0),) + times, times + (T,))):
        raise InputError(f"{source}: need 0 < switch_times[0] < ... < T")
    instance = obj.get("instance")
    if instance is not None and not isinstance(instance, str):
        raise InputError(f"{source}: instance must be an id (text) of the reference set")
    return Control("bang-bang", T, arc_signs=tuple(signs), switch_times=times, instance=instance, source="bang-bang answer")


def _ocp_json(obj, source):
    """The Control and instance id of `ocp solve --json` output."""
    from ..core.problem import make

    try:
        problem = make(obj["problem"], obj["kappa"], obj["x0"], obj["branch_pinned"])
    except (KeyError, TypeError):
        raise InputError(f"{source}: not the output of ocp solve --json (problem, kappa, x0, branch_pinned)") from None
    row = data.lookup(problem)
    if row is None:
        raise InputError(f"{source}: its problem ({problem.describe()}) is not an instance of the reference set")
    if not obj.get("success"):
        raise InputError(f"{source}: ocp solve found no solution there (success is false): nothing to score")
    answer = {"instance": row["id"], "arc_signs": obj.get("arc_signs"), "switch_times": obj.get("switch_times"),
              "T": obj.get("T")}
    control = _answer(answer, source)
    return Control(**{**control.__dict__, "source": "ocp solve --json"})


def _csv(text, source, instance):
    """The Control of a sampled control (CSV)."""
    options, rows = {}, []
    for line in text.splitlines():
        if line.lstrip().startswith("#"):
            key, sep, value = line.lstrip()[1:].partition(":")
            if sep and key.strip() in ("instance", "interpolation"):
                options[key.strip()] = value.strip()
            continue
        if line.strip():
            rows.append(line)
    if not rows:
        raise InputError(f"{source}: no rows; a sampled control is a CSV with a header t,u")
    reader = list(csv.reader(io.StringIO("\n".join(rows))))
    if [h.strip().lower() for h in reader[0]] != ["t", "u"]:
        raise InputError(f"{source}: the header must be t,u (got {','.join(reader[0])[:40]!r})")
    if len(reader) < 3 or len(reader) > MAX_ROWS:
        raise InputError(f"{source}: a sampled control needs 2 to {MAX_ROWS} rows after the header")
    try:
        t, u = zip(*((float(a), float(b)) for a, b in reader[1:]))
    except ValueError:
        raise InputError(f"{source}: every row must be two numbers t,u") from None
    t, u = np.array(t), np.array(u)
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(u))):
        raise InputError(f"{source}: t and u must be finite numbers")
    if t[0] != 0 or np.any(np.diff(t) <= 0):
        raise InputError(f"{source}: t must start at 0 and increase")
    if np.max(np.abs(u)) > 1 + BOUND_TOL:
        raise InputError(f"{source}: |u| exceeds 1 (by {np.max(np.abs(u)) - 1:.1e}): the control bound is |u| <= 1")
    mode = options.get("interpolation", "constant")
    if mode not in ("constant", "linear"):
        raise InputError(f"{source}: interpolation {mode[:20]!r}; accepted: constant, linear")
    return Control(mode, Decimal(repr(float(t[-1]))), t=tuple(t), u=tuple(np.clip(u, -1, 1)),
                   instance=instance or options.get("instance"), source=f"sampled control ({mode})")


def read(path, instance=None):
    """The Control in the file at `path` (the instance `instance` if given, else the one it names)."""
    path = Path(path)
    try:
        if path.stat().st_size > MAX_BYTES:
            raise InputError(f"{path}: larger than {MAX_BYTES // 1_000_000} MB")
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as err:
        raise InputError(f"{path}: cannot be read as UTF-8 text ({type(err).__name__})") from None
    if text.lstrip().startswith("{"):
        try:
            obj = json.loads(text)
        except (json.JSONDecodeError, RecursionError):
            raise InputError(f"{path}: not valid JSON") from None
        control = _ocp_json(obj, path) if "problem" in obj else _answer(obj, path)
        return Control(**{**control.__dict__, "instance": instance or control.instance})
    return _csv(text, path, instance)


def _flow(x, u, h, kappa, rtol):
    """x after time h under u: a constant, or (u_a, u_b) linear over the interval."""
    if h <= 0:
        return np.asarray(x, float)
    f = (lambda s, y: model.rhs(y, u, kappa)) if np.isscalar(u) else \
        (lambda s, y: model.rhs(y, u[0] + (u[1] - u[0]) * s / h, kappa))
    sol = solve_ivp(f, (0.0, h), np.asarray(x, float), method="DOP853", rtol=rtol, atol=rtol)
    return sol.y[:, -1]


def _simulate(control, x0, k, rtol):
    """x(T) of the control, and its bang-bang reading (signs, switch times, bang_bang)."""
    from ..direct.structure import read as structure

    if control.kind == "bang-bang":
        ends = [float(v) for v in control.switch_times] + [float(control.T)]
        x, start = np.asarray(x0, float), 0.0
        for s, end in zip(control.arc_signs, ends):
            x, start = _flow(x, float(s), end - start, k, rtol), end
        return x, control.arc_signs, tuple(float(v) for v in control.switch_times), True
    t, u = np.array(control.t), np.array(control.u)
    nodes = [np.asarray(x0, float)]
    for i in range(len(t) - 1):
        piece = u[i] if control.kind == "constant" else (u[i], u[i + 1])
        nodes.append(_flow(nodes[-1], piece, t[i + 1] - t[i], k, rtol))
    means = u[:-1] if control.kind == "constant" else 0.5 * (u[:-1] + u[1:])
    s = structure(t, np.array(nodes), means, k)
    return nodes[-1], s.arc_signs, s.switch_times, s.bang_bang


def score(source, instance=None, path=None):
    """The Score of the solution in the file `source` (or a bang-bang answer as a dict) against its
    instance of the reference set (`instance` overrides the id the file names)."""
    control = _answer(source, "the answer") if isinstance(source, dict) else read(source, instance)
    if isinstance(source, dict) and instance:
        control = Control(**{**control.__dict__, "instance": instance})
    if not control.instance:
        raise InputError(f"{source}: no instance id: give --instance ID or name it in the file")
    if not 0 < control.T <= Decimal(MAX_T):
        raise InputError(f"T = {float(control.T):g}: accepted 0 < T <= {MAX_T:g}")
    row = data.instance(control.instance, path)
    from ..core.problem import make

    problem = make(row["kind"], row["kappa"], row["x0"], row["branch_pinned"])
    x, signs, times, bang = _simulate(control, problem.x0, problem.kappa, RTOL)
    x_check, *_ = _simulate(control, problem.x0, problem.kappa, CHECK_RTOL)
    branch = problem.nearest_branch(x[0]) if problem.branch is None else problem.branch
    miss = float(np.hypot(*(x - problem.target(branch))))
    accuracy = float(np.hypot(*(x - x_check)))
    o = row["optimum"]
    T_ref = Decimal(o["refined"]["T"])
    dT = float(control.T - T_ref)
    candidates = [dict(e, optimal=True, which="optimum" if e is o else "tie") for e in [o] + row["ties"]]
    candidates += [dict(e, optimal=False, which=f"extremal {n + 1} of {len(row['extremals'])} (fastest first)")
                   for n, e in enumerate(row["extremals"])
                   if not any(e["arc_signs"] == c["arc_signs"] and e["branch"] == c["branch"] and
                              abs(e["T"] - c["T"]) <= 10 * (e["T_error"] + c["T_error"]) for c in candidates)]
    same = [c for c in candidates if bang and tuple(c["arc_signs"]) == tuple(signs) and c["branch"] == branch]
    matched, switch_errors, notes = None, None, []
    if miss > MISS_TOL:
        cls = Class.MISSES_TARGET
    elif not same:
        cls = Class.WRONG_STRUCTURE
        notes.append("not bang-bang: a run of interior values of u" if not bang else
                     f"no extremal of the instance has this structure (the set lists every extremal faster than "
                     f"{row['coverage']['horizon']:.4g})")
    else:
        e = min(same, key=lambda c: abs(c["T"] - float(control.T)))
        cls = Class.OPTIMUM if e["optimal"] else (Class.LOCAL_OPTIMUM if e["local_optimum"] else Class.WRONG_STRUCTURE)
        if cls == Class.WRONG_STRUCTURE:
            notes.append("an extremal that is not a local optimum (its second-order condition fails)")
        exact = e["refined"]["switch_times"] if e["optimal"] else e["switch_times"]
        matched = {"which": e["which"], "arc_signs": e["arc_signs"], "branch": e["branch"], "T": e["T"],
                   "slower_by": 0.0 if e["optimal"] else e["T"] - float(T_ref), "local_optimum": True if e["optimal"]
                   else e["local_optimum"]}
        given = control.switch_times or tuple(Decimal(repr(t)) for t in times)
        switch_errors = tuple(float(a - Decimal(str(b))) for a, b in zip(given, exact))
    return Score(row["id"], control.source, cls, float(control.T), o["refined"]["T"], o["refined"]["T_error"], dT, miss,
                 accuracy, (float(x[0]), float(x[1])), branch, tuple(signs), tuple(float(t) for t in times), bang,
                 matched, switch_errors, tuple(notes))
