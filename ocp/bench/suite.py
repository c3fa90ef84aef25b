"""Benchmark suites as data: cases crossed with methods, read from TOML (`benchmarks/*.toml`).

A suite file holds settings and two lists of tables; in every table a list value means "each of
these" and the table expands to the Cartesian product of its lists:

    name = "quick"
    repeats = 3             # each (case, method) pair is timed this many times; medians are stored
    time_limit_s = 60       # the solver's CPU seconds (its own option where it has one, e.g. IPOPT's
                            # max_cpu_time, per start); a row whose solver stops at a limit of its own
                            # (that, or its iterations: ocp.direct.solvers.limits) or spends more CPU
                            # time is a "time limit" failure; the search's own time limit
    miss_tol = 1e-6         # largest re-simulated miss accepted as success (a converged answer within
                            # miss_tol plus its transcription's own accuracy: "discretisation")

    [[cases]]
    kind = "swing-up"       # or "damping"
    kappa = [0.5, 1.0]
    x0 = [[0.0, 0.0], [0.3, -0.1]]   # optional (default: the problem's standard start)
    guess = ["default", 1, 2]        # "default": ocp's three starts; an integer: a seeded random Guess
    branch = 0                       # optional: the plane, the target's branch pinned (default: the circle)

    [[cases]]                        # or instances of the reference set (ocp.reference), by id or tag
    instance = ["swing-up/circle/k0.75/x0=standard"]    # each id (reference/index.csv)
    tag = "near-tie"                 # every solved instance with this tag (with guess, as above)

    [[methods]]
    transcription = "multiple-shooting"   # a key of ocp.direct.TRANSCRIPTIONS, "rockit" or
                                          # "rockit-freegrid" (the peer),
    integrator = "rk4"                    # or "extremal-search" (ocp.solve's complete search alone)
    N = [25, 50, 100]
    solver = ["ipopt", "fatrop"]
    configuration = ["default", "fair"]   # the solver's defaults, or its fair configuration
                                          # (ocp.bench.configurations)
    options = { ipopt = { "ipopt.tol" = 1e-10 } }   # per solver, over the configuration's, passed to
                                                    # casadi.nlpsol if on the solver's allow-list
                                                    # (ocp.direct.solvers), typed

A suite is the product of its cases and methods unless tables name groups: `group = "wide"` (or a
list of names) on a [[cases]] or [[methods]] table, not expanded, pairs its cases (methods) only
with the methods (cases) of a table sharing a group; a table without `group` pairs with every
table. So a few cases can meet a wide matrix of methods while many meet a core few
(suites/standard.toml).

Every value is checked when the file is read (`load`): its type (a string is not a number), its
range, the name (it names the default store, so it cannot leave the working folder), and the size
(MAX_PAIRS, MAX_RUNS; `ocp bench` asks for --yes above `ocp.bench.command.CONFIRM_RUNS` solves); an error names the
file, the table and the field, and what is accepted. A file is data: it cannot run a program or
touch a file (`ocp.direct.options`). The settings that change a row's outcome (repeats, miss_tol,
time_limit_s: `Suite.settings`) are part of the row's key in the store.

Cases and methods are plain frozen data (`Case`, `Method`): they travel to worker processes or a
cluster as they are, and a worker rebuilds the NLP from them.
"""

import itertools
from collections import Counter
import json
import math
import re
import tomllib
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path

from importlib import resources

from .. import direct
from ..core import problem as problems
from ..core.errors import Fault, InputError, finite, integer, short
from ..direct.options import checked
from . import configurations

PEER = "rockit"
PEER_FREE_GRID = "rockit-freegrid"      # the peer on rockit's FreeGrid: each interval's length a variable
PEERS = (PEER, PEER_FREE_GRID)
SEARCH = "extremal-search"
SEARCH_FAMILY = "extremal search"           # its family (`Method.family`): the only one without an N
#: what a method row may be: a direct transcription of ocp, the peer, or the search
KINDS_OF_METHOD = (*direct.TRANSCRIPTIONS, *PEERS, SEARCH)

#: limits of a suite: a file of at most MAX_BYTES, at most MAX_PAIRS cases, methods and pairs, at
#: most MAX_RUNS solves (pairs x repeats)
MAX_BYTES = 1_000_000
MAX_PAIRS = 100_000
MAX_RUNS = 100_000
MAX_REPEATS = 100
MAX_TIME_LIMIT_S = 86_400.0
MAX_SEED = 2**32 - 1
#: a suite's name: it names the default store, ocp-bench-NAME.sqlite, in the working folder
NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}")
NUMBER = (int, float)
NAME_RULE = "letters, digits, '.', '_' and '-' (at most 64, a letter or digit first)"
REPEATS_RULE = f"an integer from 1 to {MAX_REPEATS}"
TIME_RULE = f"a number of seconds from 0.001 to {MAX_TIME_LIMIT_S:g} (leave it out for no limit)"
MISS_RULE = f"a number from {direct.MISS_TOL_RANGE[0]:g} to {direct.MISS_TOL_RANGE[1]:g}"


def _suites_dir():
    """The named suites: package data ocp/bench/suites/*.toml."""
    return resources.files("ocp.bench") / "suites"


def _key(obj):
    """A canonical text key of plain data (the store's identity of a case or a method)."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"))


@dataclass(frozen=True)
class Case:
    """One problem and one initial guess: `guess` None (ocp's default starts, best of three) or an
    integer seed of a random guess (`ocp.direct.random_guess`); `branch` None on the circle, an
    integer pins the target's branch (the plane)."""

    kind: str
    kappa: float
    x0: tuple | None = None
    guess: int | None = None
    branch: int | None = None

    def problem(self):
        return problems.make(self.kind, self.kappa, self.x0, self.branch)

    def initial_guess(self, N):
        return None if self.guess is None else direct.random_guess(self.problem(), self.guess, N)

    @property
    def problem_key(self):
        """Identity of the problem alone (cases differing only in the guess share a reference)."""
        p = self.problem()
        return _key({"kind": p.kind, "kappa": p.kappa, "x0": list(p.x0),
                     **({} if self.branch is None else {"branch": self.branch})})

    @property
    def key(self):
        return _key({k: v for k, v in asdict(self).items() if k != "branch" or v is not None})

    @property
    def label(self):
        p = self.problem()
        start = "" if self.x0 is None else f" from ({p.x0[0]:g}, {p.x0[1]:g})"
        plane = "" if self.branch is None else f" plane branch {self.branch}"
        return f"{p.kind} kappa={p.kappa:g}{start}{plane}" + ("" if self.guess is None else f" guess#{self.guess}")


@dataclass(frozen=True)
class Method:
    """A direct transcription (a key of `ocp.direct.TRANSCRIPTIONS` with its settings), an NLP
    solver in a configuration (`ocp.bench.configurations`) with options over it; or "rockit", the
    peer (its own multiple shooting, integrator "rk", M steps per interval), "rockit-freegrid" (the
    same on rockit's FreeGrid); or "extremal-search", ocp.solve's complete search of extremals (no
    N, no solver). Only the settings given are stored (`settings`); each must apply."""

    transcription: str = "multiple-shooting"
    settings: tuple = ()
    solver: str = "ipopt"
    options: dict = field(default_factory=dict)
    configuration: str = configurations.DEFAULT

    def __post_init__(self):
        checked(self.options, where=f"options of {self.transcription} / {self.solver}", solver=self.solver)
        if self.transcription not in KINDS_OF_METHOD:
            raise InputError(f"unknown transcription {self.transcription!r}; accepted: {', '.join(KINDS_OF_METHOD)}")
        if self.transcription == SEARCH and (self.settings or self.options or self.solver != "ipopt"
                                             or self.configuration != configurations.DEFAULT):
            raise InputError("the extremal search takes no transcription settings, solver, configuration or options")
        if self.transcription in PEERS and set(self.given) - {"N", "M"}:
            raise InputError(f"the rockit peer takes N and M only, not {sorted(set(self.given) - {'N', 'M'})}")
        self.applied                         # validates the configuration
        self.transcription_object()          # validates the settings

    @property
    def applied(self):
        """The options passed to casadi.nlpsol: the configuration's, `options` over them."""
        return configurations.options(self.solver, self.configuration) | self.options

    @property
    def given(self):
        return dict(self.settings)

    def __hash__(self):     # options is a dict: the canonical key stands for it
        return hash(self.key)

    def transcription_object(self):
        """The ocp transcription (for rockit: the equivalent multiple shooting), None for the search."""
        if self.transcription == SEARCH:
            return None
        if self.transcription in PEERS:
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
            d.update(t.to_dict(), transcription=self.transcription, solver=self.solver, options=self.applied)
            if self.configuration != configurations.DEFAULT:     # keys of default rows as before configurations
                d["configuration"] = self.configuration
        return d

    @property
    def key(self):
        return _key(self.to_dict())

    @property
    def family(self):
        """The method without its N: one curve of a work-precision chart."""
        if self.transcription == SEARCH:
            return SEARCH_FAMILY
        t = self.transcription_object()
        name = t.family() if self.transcription not in PEERS else f"rockit MS rk M={t.M}" + (
            " free grid" if self.transcription == PEER_FREE_GRID else "")
        name += f" / {self.solver}"
        name += "" if self.configuration == configurations.DEFAULT else f" [{self.configuration}]"
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
    #: the groups of each case and of each method (aligned with them; empty: every group); () if
    #: no table names a group
    case_groups: tuple = ()
    method_groups: tuple = ()

    def __post_init__(self):
        if not isinstance(self.name, str) or not NAME.fullmatch(self.name):
            raise InputError(f"name = {short(self.name)} is not a suite name; accepted: {NAME_RULE}")

    @property
    def settings(self):
        """The suite settings that change a row's outcome: part of the row's key in the store."""
        return {"repeats": self.repeats, "miss_tol": self.miss_tol,
                "time_limit_s": None if math.isinf(self.time_limit_s) else self.time_limit_s}

    @property
    def settings_key(self):
        return _key(self.settings)

    def _groups(self):
        every = frozenset()
        return self.case_groups or (every,) * len(self.cases), self.method_groups or (every,) * len(self.methods)

    @staticmethod
    def _meet(a, b):
        return not a or not b or bool(a & b)

    def pairs(self):
        """Every (case, method) pair whose groups meet (every pair without groups), cases outermost."""
        cg, mg = self._groups()
        return [(c, m) for c, a in zip(self.cases, cg) for m, b in zip(self.methods, mg) if self._meet(a, b)]

    @property
    def size(self):
        """len(pairs()), counted without listing them."""
        cg, mg = (Counter(g) for g in self._groups())
        return sum(n * k for a, n in cg.items() for b, k in mg.items() if self._meet(a, b))


def _typed(name, value, types, accepted):
    """`value` if it is of `types` (a bool is not a number), else InputError saying what `name` accepts."""
    if isinstance(value, bool) != (bool in types) or not isinstance(value, types):
        raise InputError(f"{name} = {short(value)} is {_toml_type(value)}; {name} accepts {accepted}")
    return value


def _toml_type(value):
    kinds = {bool: "a boolean", str: "a string", int: "an integer", float: "a float", list: "an array", dict: "a table"}
    return next((text for t, text in kinds.items() if isinstance(value, t)), f"a {type(value).__name__}")


def _expand(table, what):
    """The Cartesian product of a table's list values (x0: a list of pairs expands, a pair does not);
    InputError if it would exceed MAX_PAIRS."""
    _typed(what, table, (dict,), f"tables: [[{what}]] with a key = value per line")
    axes = {}
    for k, v in table.items():
        if k == "x0" and isinstance(v, list) and v and not isinstance(v[0], list):
            v = [v]
        axes[k] = v if isinstance(v, list) else [v]
    if math.prod(len(v) for v in axes.values()) > MAX_PAIRS:
        raise InputError(f"a [[{what}]] table expands to {math.prod(len(v) for v in axes.values())} entries; "
                         f"accepted: at most {MAX_PAIRS}")
    return [dict(zip(axes, combo)) for combo in itertools.product(*axes.values())]


def _cases(d):
    """The cases of one expanded [[cases]] table: a problem (kind, kappa, x0), or the instances of
    the reference set named by `instance` (an id) or `tag`."""
    if "instance" in d or "tag" in d:
        return _instances(d)
    return [_case(d)]


def _instances(d):
    from ..reference import load

    if set(d) - {"instance", "tag", "guess"} or len(set(d) & {"instance", "tag"}) != 1:
        raise InputError(f"a case of the reference set takes instance or tag (one of them) and guess; "
                         f"not {', '.join(sorted(set(d) - {'guess'}))}")
    solved = [r for r in load().values() if r["status"] == "solved"]
    if "instance" in d:
        _typed("instance", d["instance"], (str,), "an instance id of the reference set (reference/index.csv)")
        chosen = [r for r in solved if r["id"] == d["instance"]]
        what = f"instance {short(d['instance'])}"
    else:
        _typed("tag", d["tag"], (str,), "a tag of the reference set's instances (reference/index.csv)")
        chosen = [r for r in solved if d["tag"] in r["tags"]]
        what = f"tag {short(d['tag'])}"
    if not chosen:
        tags = sorted({t for r in solved for t in r["tags"]})
        raise InputError(f"{what}: no solved instance of the reference set; accepted: an id of reference/index.csv "
                         f"or a tag ({', '.join(tags)})")
    guess = {"guess": d["guess"]} if "guess" in d else {}
    return [_case({"kind": r["kind"], "kappa": r["kappa"], "x0": list(r["x0"]), **guess,
                   **({} if r["branch_pinned"] is None else {"branch": r["branch_pinned"]})}) for r in chosen]


def _case(d):
    names = {f.name for f in fields(Case)}
    if set(d) - names:
        raise InputError(f"unknown case field(s) {sorted(set(d) - names)}; accepted: "
                         f"{', '.join(sorted(names | {'instance', 'tag'}))}")
    if "kind" not in d or "kappa" not in d:
        raise InputError("a case needs kind and kappa (or instance or tag of the reference set)")
    branch = d.get("branch")
    if branch is not None and (isinstance(branch, bool) or not isinstance(branch, int)):
        raise InputError(f"branch = {short(branch)} must be an integer (the target's pinned branch)")
    _typed("kind", d.get("kind"), (str,), f"one of: {', '.join(problems.KINDS)}")
    _typed("kappa", d.get("kappa"), NUMBER, "a number (the torque bound)")
    x0 = d.get("x0")
    if x0 is not None and not (isinstance(x0, list) and len(x0) == 2 and all(
            isinstance(v, NUMBER) and not isinstance(v, bool) for v in x0)):
        raise InputError(f"x0 = {short(x0)} is not a start; x0 accepts a pair of numbers [theta, omega] "
                         f"or a list of pairs")
    guess = d.get("guess", "default")
    if guess != "default" and (isinstance(guess, bool) or not isinstance(guess, int) or not 0 <= guess <= MAX_SEED):
        raise InputError(f"guess = {short(guess)} must be \"default\" or an integer seed from 0 to {MAX_SEED}")
    case = Case(d["kind"], d["kappa"], None if x0 is None else tuple(x0), None if guess == "default" else guess,
                branch)
    case.problem()      # validates kind, kappa, x0, branch
    return case


def _plain(value, name, depth=0):
    """InputError unless `value` is plain data an NLP option may be (numbers, text, booleans, arrays
    and tables of them, nested at most 4 deep)."""
    if depth > 4:
        raise InputError(f"{name} is nested too deeply for an NLP option")
    if isinstance(value, dict):
        for k, v in value.items():
            _plain(v, f"{name}.{k}", depth + 1)
    elif isinstance(value, list):
        for v in value:
            _plain(v, name, depth + 1)
    elif not isinstance(value, (str, int, float, bool)):
        raise InputError(f"{name} = {short(value)} is {_toml_type(value)}; an NLP option is a number, text, "
                         f"a boolean, or an array or table of them")


def _method(d):
    settings = {f.name: f.type for c in direct.TRANSCRIPTIONS.values() for f in fields(c)}
    names = {"transcription", "solver", "options", "configuration"} | set(settings)
    if set(d) - names:
        raise InputError(f"unknown method field(s) {sorted(set(d) - names)}; accepted: {', '.join(sorted(names))}")
    for key, value in d.items():
        if key in settings:
            kind = settings[key]
            _typed(key, value, NUMBER if kind is float else (kind,), {int: "an integer", float: "a number"}.get(kind, "text"))
    transcription = _typed("transcription", d.get("transcription", "multiple-shooting"), (str,),
                           f"one of: {', '.join(KINDS_OF_METHOD)}")
    solver = _typed("solver", d.get("solver", "ipopt"), (str,), "a casadi.nlpsol plugin name, e.g. ipopt")
    options = d.get("options", {})
    if not isinstance(options, dict) or not all(isinstance(v, dict) for v in options.values()):
        raise InputError(f"options = {short(options)} must be a table per solver, e.g. options = {{ ipopt = {{ \"ipopt.tol\" = 1e-10 }} }}")
    _plain(options, "options")
    configuration = _typed("configuration", d.get("configuration", configurations.DEFAULT), (str,),
                           f"one of: {', '.join(configurations.CONFIGURATIONS)}")
    given = tuple(sorted((k, v) for k, v in d.items() if k in settings))
    return Method(transcription, given, solver, options.get(solver, {}), configuration)


def _read(path):
    """The TOML table of the file at `path` (InputError if it is not a UTF-8 TOML file of at most MAX_BYTES)."""
    try:
        if path.stat().st_size > MAX_BYTES:
            raise InputError(f"{path}: {path.stat().st_size} bytes; a suite file has at most {MAX_BYTES}")
        raw = path.read_bytes()
    except OSError as err:
        raise Fault(f"cannot read the suite {path}: {err.strerror or err}") from None
    try:
        return tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as err:
        raise InputError(f"{path}: not UTF-8 text ({err.reason} at byte {err.start}); a suite is a TOML file "
                         f"in UTF-8") from None
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"{path}: not valid TOML: {err}") from None
    except RecursionError:
        raise InputError(f"{path}: nested too deeply to be a suite") from None


def _setting(data, key, check, default):
    return default if key not in data else check(key, data[key])


def load(name_or_path):
    """The Suite named `name_or_path` (a suite of ocp/bench/suites, e.g. "quick") or at that path;
    every value checked (InputError naming the file and the field, with what it accepts)."""
    path = Path(name_or_path)
    if not path.suffix:
        if not NAME.fullmatch(str(name_or_path)):
            raise InputError(f"no suite {short(str(name_or_path))}; accepted: a TOML file, or one of: {', '.join(_named())}")
        path = _suites_dir() / f"{name_or_path}.toml"
    if not path.is_file():
        raise InputError(f"no suite {short(str(name_or_path))}; accepted: a TOML file, or one of: {', '.join(_named())}")
    data = _read(path)
    known = {"name", "description", "repeats", "time_limit_s", "miss_tol", "cases", "methods"}
    if set(data) - known:
        raise InputError(f"{path}: unknown key(s) {sorted(set(data) - known)}; accepted: {', '.join(sorted(known))}")
    try:
        name = _setting(data, "name", _name, _sanitised(path.stem))
        description = _setting(data, "description", lambda k, v: _typed(k, v, (str,), "text"), "")
        repeats = _setting(data, "repeats", lambda k, v: integer(k, _typed(k, v, (int,), REPEATS_RULE), REPEATS_RULE,
                                                                 1, MAX_REPEATS), 1)
        time_limit = _setting(data, "time_limit_s", lambda k, v: finite(k, _typed(k, v, NUMBER, TIME_RULE), TIME_RULE,
                                                                       1e-3, MAX_TIME_LIMIT_S), math.inf)
        miss_tol = _setting(data, "miss_tol", lambda k, v: finite(k, _typed(k, v, NUMBER, MISS_RULE), MISS_RULE,
                                                                 *direct.MISS_TOL_RANGE), direct.MISS_TOL)
        tables = {what: _typed(what, data.get(what, []), (list,), f"[[{what}]] tables") for what in ("cases", "methods")}
    except InputError as err:
        raise InputError(f"{path}: {err}") from None
    found, groups = {}, {}
    for what, make in (("cases", _cases), ("methods", lambda d: [_method(d)])):
        items = {}
        for i, table in enumerate(tables[what], 1):
            try:
                table = dict(_typed(what, table, (dict,), f"tables: [[{what}]] with a key = value per line"))
                group = _group(table.pop("group", []))
                for item in (item for d in _expand(table, what) for item in make(d)):
                    old = items.get(item)
                    items[item] = group if old is None else old | group if old and group else frozenset()
            except InputError as err:
                raise InputError(f"{path}: [[{what}]] #{i}: {err}") from None
            if len(items) > MAX_PAIRS:
                raise InputError(f"{path}: more than {MAX_PAIRS} {what}; accepted: at most {MAX_PAIRS}")
        found[what], groups[what] = tuple(items), tuple(items.values())
    cases, methods = found["cases"], found["methods"]
    if not cases or not methods:
        raise InputError(f"{path}: a suite needs at least one [[cases]] and one [[methods]] table")
    grouped = any(g for gs in groups.values() for g in gs)
    suite = Suite(name, description, repeats, time_limit, miss_tol, cases, methods,
                  *((groups["cases"], groups["methods"]) if grouped else ()))
    if suite.size * repeats > MAX_RUNS:
        raise InputError(f"{path}: {suite.size} pairs x {repeats} repeats = "
                         f"{suite.size * repeats} solves; accepted: at most {MAX_RUNS}")
    if not suite.size:
        raise InputError(f"{path}: no case shares a group with a method")
    return suite


def _group(value):
    """The groups a table names (`group`: a name or a list of names), InputError otherwise."""
    names = value if isinstance(value, list) else [value]
    for name in names:
        if not isinstance(name, str) or not NAME.fullmatch(name):
            raise InputError(f"group = {short(value)} is not a group; group accepts a name ({NAME_RULE}) or a "
                             f"list of names")
    return frozenset(names)


def _name(key, value):
    if not NAME.fullmatch(_typed(key, value, (str,), NAME_RULE)):
        raise InputError(f"{key} = {short(value)} is not a suite name (it names the store); {key} accepts {NAME_RULE}")
    return value


def _named():
    return sorted(p.name[:-5] for p in _suites_dir().iterdir() if p.name.endswith(".toml"))


def _sanitised(stem):
    """A file's stem as a suite name (NAME): other characters become '-'."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", stem).strip(".-_")[:64] or "suite"
