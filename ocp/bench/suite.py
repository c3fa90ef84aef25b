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
    transcription = "multiple-shooting"   # or "direct-collocation", or "rockit" (the peer)
    integrator = "rk4"
    N = [25, 50, 100]
    solver = ["ipopt", "fatrop"]
    refine = [false, true]
    options = { ipopt = { "ipopt.tol" = 1e-10 } }   # per solver, passed to casadi.nlpsol untouched

Cases and methods are plain frozen data (`Case`, `Method`): they travel to worker processes or a
cluster as they are, and a worker rebuilds the NLP from them.
"""

import itertools
import json
import math
import tomllib
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path

from .. import direct, problems
from ..errors import InputError
from ..transcription import DirectCollocation, MultipleShooting

#: where the named suites live (the repository's benchmarks/ folder)
SUITES_DIR = Path(__file__).resolve().parents[2] / "benchmarks"
TRANSCRIPTIONS = ("multiple-shooting", "direct-collocation", "rockit")


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
    """A transcription with its settings, an NLP solver with its options, and whether the direct
    answer is refined (`ocp.solve` with refinement and certificate). transcription "rockit" is the
    peer: rockit's own multiple shooting (integrator "rk", M steps per interval)."""

    transcription: str = "multiple-shooting"
    N: int = 100
    integrator: str = "rk4"
    M: int = 4
    tol: float = 1e-10
    degree: int = 3
    solver: str = "ipopt"
    options: dict = field(default_factory=dict)
    refine: bool = False

    def __post_init__(self):
        if self.transcription not in TRANSCRIPTIONS:
            raise InputError(f"unknown transcription {self.transcription!r}; accepted: {', '.join(TRANSCRIPTIONS)}")
        if self.transcription == "rockit" and self.refine:
            raise InputError("the rockit peer has no refinement: refine must be false")
        self.settings()     # validates N, M, degree, integrator

    def __hash__(self):     # options is a dict: the canonical key stands for it
        return hash(self.key)

    def settings(self):
        """The ocp transcription object (for rockit: the equivalent ocp settings, used to validate)."""
        if self.transcription == "direct-collocation":
            return DirectCollocation(self.N, self.degree)
        return MultipleShooting(self.N, "rk4" if self.transcription == "rockit" else self.integrator, self.M, self.tol)

    def to_dict(self):
        """The fields that matter for this transcription (others are left out of keys and labels)."""
        d = asdict(self)
        unused = {"multiple-shooting": {"degree"} | ({"tol"} if self.integrator != "cvodes" else {"M"}),
                  "direct-collocation": {"integrator", "M", "tol"},
                  "rockit": {"integrator", "tol", "degree", "refine"}}[self.transcription]
        return {k: v for k, v in d.items() if k not in unused}

    @property
    def key(self):
        return _key(self.to_dict())

    @property
    def family(self):
        """The method without its N: one curve of a work-precision chart."""
        d = self.to_dict()
        name = {"multiple-shooting": f"MS {self.integrator}", "direct-collocation": f"DC radau{self.degree}",
                "rockit": "rockit MS rk"}[self.transcription]
        name += {"cvodes": f" tol={self.tol:g}", "radau": ""}.get(d.get("integrator"), f" M={self.M}" if "M" in d else "")
        name += f" / {self.solver}" + (" +refine" if self.refine else "")
        return name + (f" {_key(self.options)}" if self.options else "")

    @property
    def label(self):
        return f"{self.family} N={self.N}"


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
    names = {f.name for f in fields(Method)}
    if set(d) - names:
        raise InputError(f"unknown method field(s) {sorted(set(d) - names)}; accepted: {', '.join(sorted(names))}")
    options = d.get("options", {})
    if not isinstance(options, dict) or not all(isinstance(v, dict) for v in options.values()):
        raise InputError(f"options = {options!r} must be a table per solver, e.g. options = {{ ipopt = {{ \"ipopt.tol\" = 1e-10 }} }}")
    return Method(**dict(d, options=options.get(d.get("solver", "ipopt"), {})))


def load(name_or_path):
    """The Suite named `name_or_path` (a file stem in benchmarks/, e.g. "quick") or at that path."""
    path = Path(name_or_path)
    if not path.suffix:
        path = SUITES_DIR / f"{name_or_path}.toml"
    if not path.is_file():
        named = sorted(p.stem for p in SUITES_DIR.glob("*.toml"))
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
