"""Benchmark suites as data: cases crossed with methods, read from TOML (`benchmarks/*.toml`).

A suite file holds settings and two lists of tables; in every table a list value means "each of
these" and the table expands to the Cartesian product of its lists:

    name = "quick"
    repeats = 3             # each (case, method) pair is timed this many times; medians are stored
    time_limit_s = 60       # a run longer than this is a "time limit" failure (not interrupted)
    miss_tol = 1e-6         # largest re-simulated miss accepted as success

    [[cases]]
    kind = "swing-up"       # or "damping"
    kappa = [0.5, 1.0]
    x0 = [[0.0, 0.0], [0.3, -0.1]]   # optional (default: the problem's standard start)
    guess = ["default", 1, 2]        # "default": ocp's three starts; an integer: a seeded random Guess

    [[methods]]
    transcription = "multiple-shooting"   # a key of ocp.direct.TRANSCRIPTIONS, "rockit" (the peer),
    integrator = "rk4"                    # or "extremal-search" (ocp.solve's complete search alone)
    N = [25, 50, 100]
    solver = ["ipopt", "fatrop"]
    options = { ipopt = { "ipopt.tol" = 1e-10 } }   # per solver, passed to casadi.nlpsol untouched
                                                    # (options that run a program or touch a file are refused)

Cases and methods are plain frozen data (`Case`, `Method`): they travel to worker processes or a
cluster as they are, and a worker rebuilds the NLP from them.
"""

import itertools
import json
import math
import tomllib
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path

from importlib import resources

from .. import direct
from ..core import problem as problems
from ..core.errors import InputError
from ..direct.options import checked

PEER = "rockit"
SEARCH = "extremal-search"
#: what a method row may be: a direct transcription of ocp, the peer, or the search
KINDS_OF_METHOD = (*direct.TRANSCRIPTIONS, PEER, SEARCH)


def _suites_dir():
    """The named suites: package data ocp/bench/suites/*.toml."""
    return resources.files("ocp.bench") / "suites"


def _key(obj):
    """A canonical text key of plain data (the store's identity of a case or a method)."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"))


@dataclass(frozen=True)
class Case:
    """One problem and one initial guess: `guess` None (ocp's default starts, best of three) or an
    integer seed of a random guess (`ocp.direct.random_guess`)."""

    kind: str
    kappa: float
    x0: tuple | None = None
    guess: int | None = None

    def problem(self):
        return problems.make(self.kind, self.kappa, self.x0)

    def initial_guess(self, N):
        return None if self.guess is None else direct.random_guess(self.problem(), self.guess, N)

    @property
    def problem_key(self):
        """Identity of the problem alone (cases differing only in the guess share a reference)."""
        p = self.problem()
        return _key({"kind": p.kind, "kappa": p.kappa, "x0": list(p.x0)})

    @property
    def key(self):
        return _key(asdict(self))

    @property
    def label(self):
        p = self.problem()
        start = "" if self.x0 is None else f" from ({p.x0[0]:g}, {p.x0[1]:g})"
        return f"{p.kind} kappa={p.kappa:g}{start}" + ("" if self.guess is None else f" guess#{self.guess}")


@dataclass(frozen=True)
class Method:
    """A direct transcription (a key of `ocp.direct.TRANSCRIPTIONS` with its settings), an NLP
    solver with its options; or "rockit", the peer (its own multiple shooting, integrator "rk", M
    steps per interval); or "extremal-search", ocp.solve's complete search of extremals (no N, no
    solver). Only the settings given are stored (`settings`); each must apply."""

    transcription: str = "multiple-shooting"
    settings: tuple = ()
    solver: str = "ipopt"
    options: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.transcription not in KINDS_OF_METHOD:
            raise InputError(f"unknown transcription {self.transcription!r}; accepted: {', '.join(KINDS_OF_METHOD)}")
        if self.transcription == SEARCH and (self.settings or self.options or self.solver != "ipopt"):
            raise InputError("the extremal search takes no transcription settings, solver or options")
        if self.transcription == PEER and set(self.given) - {"N", "M"}:
            raise InputError(f"the rockit peer takes N and M only, not {sorted(set(self.given) - {'N', 'M'})}")
        checked(self.options, where=f"options of {self.transcription} / {self.solver}")
        self.transcription_object()          # validates the settings

    @property
    def given(self):
        return dict(self.settings)

    def __hash__(self):     # options is a dict: the canonical key stands for it
        return hash(self.key)

    def transcription_object(self):
        """The ocp transcription (for rockit: the equivalent multiple shooting), None for the search."""
        if self.transcription == SEARCH:
            return None
        if self.transcription == PEER:
            return direct.MultipleShooting(**self.given)
        return direct.make(self.transcription, **self.given)

    @property
    def N(self):
        t = self.transcription_object()
        return None if t is None else t.N

    def to_dict(self):
        t = self.transcription_object()
        d = {"transcription": self.transcription}
        if t is not None:
            d.update(t.to_dict(), transcription=self.transcription, solver=self.solver, options=self.options)
        return d

    @property
    def key(self):
        return _key(self.to_dict())

    @property
    def family(self):
        """The method without its N: one curve of a work-precision chart."""
        if self.transcription == SEARCH:
            return "extremal search"
        t = self.transcription_object()
        name = f"rockit MS rk M={t.M}" if self.transcription == PEER else t.family()
        name += f" / {self.solver}"
        return name + (f" {_key(self.options)}" if self.options else "")

    @property
    def label(self):
        return self.family if self.N is None else f"{self.family} N={self.N}"


@dataclass(frozen=True)
class Suite:
    name: str
    description: str
    repeats: int
    time_limit_s: float
    miss_tol: float
    cases: tuple
    methods: tuple

    def pairs(self):
        """Every (case, method) pair, cases outermost."""
        return [(c, m) for c in self.cases for m in self.methods]


def _expand(table, what):
    """The Cartesian product of a table's list values (x0: a list of pairs expands, a pair does not)."""
    axes = {}
    for k, v in table.items():
        if k == "x0" and isinstance(v, list) and v and not isinstance(v[0], list):
            v = [v]
        axes[k] = v if isinstance(v, list) else [v]
    try:
        return [dict(zip(axes, combo)) for combo in itertools.product(*axes.values())]
    except TypeError:
        raise InputError(f"a {what} table is not a table of values: {table!r}") from None


def _case(d):
    names = {f.name for f in fields(Case)}
    if set(d) - names:
        raise InputError(f"unknown case field(s) {sorted(set(d) - names)}; accepted: {', '.join(sorted(names))}")
    guess = d.get("guess", "default")
    if guess != "default" and (isinstance(guess, bool) or not isinstance(guess, int)):
        raise InputError(f"guess = {guess!r} must be \"default\" or an integer seed")
    case = Case(d.get("kind"), d.get("kappa"), None if d.get("x0") is None else tuple(d["x0"]),
                None if guess == "default" else guess)
    case.problem()      # validates kind, kappa, x0
    return case


def _method(d):
    names = {"transcription", "solver", "options"} | {f for c in direct.TRANSCRIPTIONS.values() for f in c.__dataclass_fields__}
    if set(d) - names:
        raise InputError(f"unknown method field(s) {sorted(set(d) - names)}; accepted: {', '.join(sorted(names))}")
    options = d.get("options", {})
    if not isinstance(options, dict) or not all(isinstance(v, dict) for v in options.values()):
        raise InputError(f"options = {options!r} must be a table per solver, e.g. options = {{ ipopt = {{ \"ipopt.tol\" = 1e-10 }} }}")
    settings = tuple(sorted((k, v) for k, v in d.items() if k not in ("transcription", "solver", "options")))
    return Method(d.get("transcription", "multiple-shooting"), settings, d.get("solver", "ipopt"),
                  options.get(d.get("solver", "ipopt"), {}))


def load(name_or_path):
    """The Suite named `name_or_path` (a suite of ocp/bench/suites, e.g. "quick") or at that path."""
    path = Path(name_or_path)
    if not path.suffix:
        path = _suites_dir() / f"{name_or_path}.toml"
    if not path.is_file():
        named = sorted(p.name[:-5] for p in _suites_dir().iterdir() if p.name.endswith(".toml"))
        raise InputError(f"no suite {name_or_path!r}; accepted: a TOML file, or one of: {', '.join(named)}")
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"{path}: not valid TOML: {err}") from None
    known = {"name", "description", "repeats", "time_limit_s", "miss_tol", "cases", "methods"}
    if set(data) - known:
        raise InputError(f"{path}: unknown key(s) {sorted(set(data) - known)}; accepted: {', '.join(sorted(known))}")
    try:
        cases = tuple(dict.fromkeys(_case(d) for t in data.get("cases", []) for d in _expand(t, "cases")))
        methods = tuple(dict.fromkeys(_method(d) for t in data.get("methods", []) for d in _expand(t, "methods")))
    except (InputError, TypeError) as err:
        raise InputError(f"{path}: {err}") from None
    repeats = data.get("repeats", 1)
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise InputError(f"{path}: repeats = {repeats!r} must be an integer >= 1")
    if not cases or not methods:
        raise InputError(f"{path}: a suite needs at least one [[cases]] and one [[methods]] table")
    return Suite(data.get("name", path.stem), data.get("description", ""), repeats,
                 float(data.get("time_limit_s", math.inf)), float(data.get("miss_tol", direct.MISS_TOL)),
                 cases, methods)
