"""The NLP solvers, declared once (SOLVERS), and the CasADi plugins they may load.

Each `Solver` names its `casadi.nlpsol` plugin, its quiet options (printing off, under the user's),
its fair configuration for the bench and why, the QP and linear solver plugins it loads by default
(`uses`), and the allow-list of options a user may set, each typed (`Number`, `Integer`, `Flag`,
`Choice`, `Plugin`, `Table`, `PluginOptions`). Options are data: none on a list names a file, a
library, a program or a callback (`ocp.direct.options` refuses everything else). A new solver the
CasADi wheel ships is one entry of SOLVERS; a QP solver one entry of CONICS.

How CasADi finds a plugin (casadi/core/casadi_os.cpp, `get_search_paths` and
`open_shared_library`; traced with strace on the wheel installed here, 3.8.2): for
`libcasadi_<kind>_<name>.so` it tries dlopen in each of CASADI_PLUGIN_SEARCH_PATH, the casadipath
of GlobalOptions (the Python package sets it to its own folder), CASADIPATH, the bare name
(dlopen's own search: RPATH $ORIGIN of libcasadi, LD_LIBRARY_PATH, the system folders), and last
"." - the working folder - taking the first that loads. A library's constructor runs when it is
opened, so a name tried there runs the code of ./libcasadi_nlpsol_<name>.so even when CasADi then
refuses it; so does a plugin that is shipped but cannot load from CasADi's folder (its dependency
missing: HSL's MA27 for blockSQP's default linear solver, the KNITRO, SNOPT, WORHP and MadNLP
libraries): the search falls through to the working folder. `casadi.has_nlpsol(name)` searches
the same way. IPOPT's own loading of HSL and Pardiso (`linear_solver` ma27..., pardiso) uses
dlopen's search (no working folder) unless `hsllib` or `pardisolib` name a path; its MA97 crashes
the process. The "." cannot be removed by any setting of CasADi's.

So ocp (i) checks every plugin name it hands to CasADi - the solver, a QP or linear solver option,
an integrator - against those declared here and shipped in CasADi's folder, and loadable from there
by their absolute path (`available`), before CasADi sees the name; and (ii) makes every CasADi call
that may load a plugin (building, solving, integrators) run with the working folder set to a
private empty folder of its own (`loading`), so that CasADi's last search path "." holds nothing,
whatever the options (a default of a plugin included).
"""

import atexit
import contextlib
import ctypes
import math
import os
import tempfile
import threading
from dataclasses import dataclass, field

from ..core.cache import cached
from ..core.errors import Fault, InputError, short

TOL = 1e-8


# --- typed options -------------------------------------------------------------------------------

@dataclass(frozen=True)
class Number:
    """A finite real in [low, high] (low excluded where `above`); an integer is taken as a float."""

    low: float = -math.inf
    high: float = math.inf
    above: bool = False

    def check(self, name, value, _siblings=None):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise _refused(name, value, f"not a number; it takes {self.accepted()}")
        number = float(value)
        if not math.isfinite(number):
            raise _refused(name, value, f"not finite; it takes {self.accepted()}")
        if number < self.low or (self.above and number == self.low) or number > self.high:
            raise _refused(name, value, f"out of range; it takes {self.accepted()}")
        return number

    def accepted(self):
        bounds = [f"> {self.low:g}" if self.above else f">= {self.low:g}"] if self.low > -math.inf else []
        bounds += [f"<= {self.high:g}"] if self.high < math.inf else []
        return " ".join(["a finite number", " and ".join(bounds)]).strip()

    def example(self):
        return min(self.high, self.low + 1.0) if self.low > -math.inf else 1.0


@dataclass(frozen=True)
class Integer:
    """An integer (not a boolean, not a float) in [low, high]."""

    low: int = 0
    high: int = 2 ** 31 - 1

    def check(self, name, value, _siblings=None):
        if isinstance(value, bool) or not isinstance(value, int):
            raise _refused(name, value, f"not an integer; it takes {self.accepted()}")
        if not self.low <= value <= self.high:
            raise _refused(name, value, f"out of range; it takes {self.accepted()}")
        return value

    def accepted(self):
        return f"an integer from {self.low} to {self.high}"

    def example(self):
        return min(self.high, self.low + 1)


@dataclass(frozen=True)
class Flag:
    """true or false."""

    def check(self, name, value, _siblings=None):
        if not isinstance(value, bool):
            raise _refused(name, value, f"not a boolean; it takes {self.accepted()}")
        return value

    def accepted(self):
        return "true or false"

    def example(self):
        return False


@dataclass(frozen=True)
class Choice:
    """One of the given words."""

    values: tuple

    def check(self, name, value, _siblings=None):
        if not isinstance(value, str) or value not in self.values:
            raise _refused(name, value, f"not a choice; it takes {self.accepted()}")
        return value

    def accepted(self):
        return "one of " + ", ".join(self.values)

    def example(self):
        return self.values[0]


@dataclass(frozen=True)
class Plugin:
    """The name of a CasADi plugin of `kind` among `names`, and shipped loadable (`available`)."""

    kind: str
    names: tuple

    def check(self, name, value, _siblings=None):
        if not isinstance(value, str) or value not in self.names:
            raise _refused(name, value, f"not a {self.kind} plugin ocp accepts; it takes {self.accepted()}")
        require(self.kind, value)
        return value

    def accepted(self):
        return "one of " + ", ".join(n for n in self.names if available(self.kind, n))

    def example(self):
        return next(n for n in self.names if available(self.kind, n))


@dataclass(frozen=True)
class Table:
    """A table of typed options (its keys from `fields`)."""

    fields: dict

    def check(self, name, value, _siblings=None):
        return check_table(self.fields, value, name)

    def accepted(self):
        return "a table of " + (", ".join(self.fields) or "nothing")

    def example(self):
        return {key: kind.example() for key, kind in self.fields.items()}


@dataclass(frozen=True)
class PluginOptions:
    """The options table of the plugin named by the sibling option `option` (`default` where it is
    not given): the fields declared for it in CONICS."""

    option: str
    default: str

    def fields(self, siblings):
        plugin = siblings.get(self.option, self.default) if siblings else self.default
        return CONICS[plugin].fields if plugin in CONICS else COMMON_CONIC

    def check(self, name, value, siblings=None):
        return check_table(self.fields(siblings), value, name)

    def accepted(self):
        return f"a table of the options of its {self.option} (ocp.direct.solvers.CONICS)"

    def example(self):
        return Table(self.fields(None)).example()


def _refused(name, value, why):
    return InputError(f"option {name} = {short(value)} is refused: {why}")


def check_table(fields, options, where):
    """`options` (a dict) with every key on `fields` and its value of the declared type, else
    InputError naming the option, why, and what is accepted."""
    if not isinstance(options, dict):
        raise InputError(f"{where} = {short(options)} is refused: not a table of options")
    checked = {}
    for key, value in options.items():
        name = f"{where}.{key}" if where else str(key)
        if key not in fields:
            raise InputError(f"option {name} is refused: not on the allow-list (it may load a library, run a "
                             f"program or touch a file, or is simply unknown); accepted: {', '.join(fields) or 'none'}")
        checked[key] = fields[key].check(name, value, options)
    return checked


# --- the plugins -----------------------------------------------------------------------------------

POSITIVE = Number(0.0, above=True)
NONNEGATIVE = Number(0.0)
COUNT = Integer(0)
PRINTING = {"print_header": Flag(), "print_iteration": Flag(), "print_status": Flag()}


@dataclass(frozen=True)
class Conic:
    """A QP solver (casadi.conic plugin): its quiet options and the options a user may set."""

    quiet: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)

    @property
    def fields(self):
        return COMMON_CONIC | self.options


#: options of every QP solver
COMMON_CONIC = {"error_on_fail": Flag(), "print_time": Flag(), "print_problem": Flag()}

#: the QP solvers (casadi.conic plugins) a `qpsol` option may name, each loadable without a
#: commercial library (CPLEX, Gurobi, MOSEK and Xpress are loaded from the search path at run time;
#: Cbc and Clp take no quadratic term; "nlpsol" names an NLP solver)
CONICS = {
    "qpoases": Conic({"printLevel": "none"},
                     {"printLevel": Choice(("none", "low", "medium", "high", "tabular", "debug_iter")),
                      "sparse": Flag(), "schur": Flag(), "nWSR": COUNT, "max_schur": COUNT,
                      "enableRegularisation": Flag(), "epsRegularisation": POSITIVE}),
    "qrqp": Conic({"print_iter": False, "print_header": False},
                  {"print_iter": Flag(), "print_header": Flag(), "print_info": Flag(), "print_lincomb": Flag(),
                   "max_iter": COUNT, "constr_viol_tol": POSITIVE, "dual_inf_tol": POSITIVE, "min_lam": NONNEGATIVE}),
    "osqp": Conic({}, {"warm_start_primal": Flag(), "warm_start_dual": Flag(),
                       "osqp": Table({"verbose": Flag(), "eps_abs": POSITIVE, "eps_rel": POSITIVE,
                                      "max_iter": Integer(1), "polish": Flag(), "rho": POSITIVE,
                                      "scaling": COUNT, "adaptive_rho": Flag()})}),
    "hpipm": Conic(),
    "daqp": Conic(),
    "highs": Conic(),
    "ipqp": Conic({}, {"max_iter": COUNT, "constr_viol_tol": POSITIVE, "dual_inf_tol": POSITIVE,
                       "print_iter": Flag(), "print_header": Flag(), "print_info": Flag()}),
    "piqp": Conic(),
    "proxqp": Conic(),
    "superscs": Conic(),
}

#: the linear solvers (casadi.linsol plugins) a `linsol` option may name (HSL's ma27 is shipped as a
#: plugin but needs libhsl, which is not)
LINSOLS = ("ldl", "qr", "csparse", "csparsecholesky", "lapacklu", "lapackqr", "mumps", "symbolicqr", "lsqr",
           "tridiag")


@dataclass(frozen=True)
class Solver:
    """An NLP solver (a casadi.nlpsol plugin): its quiet options (under the user's); `equality`: it
    is told which constraints are equalities; `qp`: the default of its `qpsol` option, whose QP
    solver ocp silences (`CONICS[...].quiet`) and makes report a failed QP through the NLP's status;
    its fair configuration and why; the plugins it loads by default (`uses`, kind -> name); the
    options a user may set (besides COMMON); `iteration_limit`: its option of the iterations per
    start and the solver's own default of it, `cpu_limit`: its option of the CPU seconds per start
    (`limits`)."""

    quiet: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)
    fair: dict | None = None
    why: str = ""
    uses: dict = field(default_factory=dict)
    equality: bool = False
    qp: str | None = None
    iteration_limit: tuple = ()
    cpu_limit: str | None = None

    @property
    def fields(self):
        return COMMON | self.options


#: options of every NLP solver
COMMON = {"expand": Flag(), "print_time": Flag(), "error_on_fail": Flag(), "calc_lam_p": Flag(),
          "calc_lam_x": Flag(), "bound_consistency": Flag(), "warn_initial_bounds": Flag()}

_IPOPT_LINEAR = ("mumps", "spral")      # those that run with this wheel: ma27/57/77/86 need HSL, ma97 crashes
_SQP = {"qpsol": Plugin("conic", tuple(CONICS)), "max_iter": COUNT, "min_iter": COUNT, "tol_pr": POSITIVE,
        "tol_du": POSITIVE, "hessian_approximation": Choice(("exact", "limited-memory")),
        "lbfgs_memory": Integer(1), "convexify_strategy": Choice(("none", "regularize", "eigen-reflect", "eigen-clip")),
        "convexify_margin": NONNEGATIVE, "max_iter_eig": COUNT, "init_feasible": Flag(), **PRINTING}
_SQP_FAIR = {"qpsol": "qrqp", "hessian_approximation": "exact", "convexify_strategy": "regularize",
             "tol_pr": TOL, "tol_du": TOL}
_SQP_QUIET = {"print_header": False, "print_iteration": False}

SOLVERS = {
    "ipopt": Solver(
        quiet={"ipopt.print_level": 0, "ipopt.sb": "yes"},
        options={"ipopt.tol": POSITIVE, "ipopt.max_iter": COUNT, "ipopt.acceptable_tol": POSITIVE,
                 "ipopt.acceptable_iter": COUNT, "ipopt.constr_viol_tol": POSITIVE, "ipopt.dual_inf_tol": POSITIVE,
                 "ipopt.compl_inf_tol": POSITIVE, "ipopt.max_wall_time": POSITIVE, "ipopt.max_cpu_time": POSITIVE,
                 "ipopt.linear_solver": Choice(_IPOPT_LINEAR),
                 "ipopt.mu_strategy": Choice(("monotone", "adaptive")), "ipopt.mu_init": POSITIVE,
                 "ipopt.hessian_approximation": Choice(("exact", "limited-memory")),
                 "ipopt.limited_memory_max_history": COUNT, "ipopt.nlp_scaling_method": Choice(("gradient-based", "none")),
                 "ipopt.print_level": Integer(0, 12), "ipopt.sb": Choice(("yes", "no")),
                 "ipopt.warm_start_init_point": Choice(("no", "yes")), "ipopt.bound_push": POSITIVE,
                 "ipopt.bound_frac": Number(0.0, 0.5, above=True), "ipopt.mumps_pivtol": Number(0.0, 1.0),
                 "ipopt.mumps_mem_percent": COUNT,
                 "ipopt.fixed_variable_treatment": Choice(("make_parameter", "make_parameter_nodual", "make_constraint",
                                                           "relax_bounds"))},
        fair={"ipopt.tol": TOL, "ipopt.linear_solver": "mumps"},
        why="MUMPS: the linear solver the wheel ships (HSL's MA27/MA57 are absent); tol its own default",
        uses={"linsol": "mumps"}, iteration_limit=("ipopt.max_iter", 3000), cpu_limit="ipopt.max_cpu_time"),
    "fatrop": Solver(
        quiet={"structure_detection": "auto", "fatrop.print_level": 0}, equality=True,
        options={"fatrop.tol": POSITIVE, "fatrop.max_iter": COUNT, "fatrop.print_level": Integer(0, 10),
                 "fatrop.acceptable_tol": POSITIVE, "structure_detection": Choice(("auto", "none")), "debug": Flag()},
        fair={"fatrop.tol": TOL}, iteration_limit=("fatrop.max_iter", 1000),
        why="fatrop's own stage structure detection (ocp's default) and the common tolerance"),
    "sqpmethod": Solver(
        quiet=_SQP_QUIET, qp="qpoases", uses={"conic": "qpoases"},
        options=_SQP | {"qpsol_options": PluginOptions("qpsol", "qpoases"), "max_iter_ls": COUNT,
                        "min_step_size": POSITIVE, "elastic_mode": Flag(), "second_order_corrections": Flag()},
        fair=_SQP_FAIR, iteration_limit=("max_iter", 50),
        why="exact Hessian regularised to be positive definite, so that the sparse active-set QP (qrqp) "
            "always has a solution"),
    "feasiblesqpmethod": Solver(
        quiet=_SQP_QUIET, qp="qpoases", uses={"conic": "qpoases"},
        options=_SQP | {"qpsol_options": PluginOptions("qpsol", "qpoases"), "optim_tol": POSITIVE,
                        "feas_tol": POSITIVE, "tr_rad0": POSITIVE, "tr_tol": POSITIVE, "watchdog": COUNT},
        fair=_SQP_FAIR, iteration_limit=("max_iter", 50),
        why="as sqpmethod; its feasible start cannot be given: it is a transfer that reaches the target, "
            "i.e. an answer of the problem"),
    "blocksqp": Solver(
        uses={"linsol": "ma27", "conic": "qpoases"},
        options={"linsol": Plugin("linsol", LINSOLS), "schur": Flag(), "restore_feas": Flag(), "opttol": POSITIVE,
                 "nlinfeastol": POSITIVE, "max_iter": COUNT, "max_it_qp": COUNT, "max_line_search": COUNT,
                 "globalization": Flag(), "hess_update": Integer(0, 5), "hess_lim_mem": Integer(0, 1),
                 "hess_memsize": Integer(1), "block_hess": Integer(0, 2), "warmstart": Flag(),
                 "print_header": Flag(), "print_iteration": Flag(), "print_maxit_reached": Flag()},
        fair={"linsol": "ldl", "schur": False, "restore_feas": False, "opttol": TOL, "nlinfeastol": TOL},
        iteration_limit=("max_iter", 100),
        why="MA27 is absent: CasADi's ldl, with qpOASES's dense QP (its Schur-complement QP needs a pivoting "
            "factorisation, ldl has none) and no restoration phase (it builds a solver of its own on MA27)"),
    "bonmin": Solver(
        quiet={"bonmin.print_level": 0},
        options={"bonmin.tol": POSITIVE, "bonmin.print_level": Integer(0, 12), "bonmin.max_iter": COUNT},
        fair={"bonmin.tol": TOL}, iteration_limit=("bonmin.max_iter", 3000),
        why="no integer variables: Bonmin's NLP solver (IPOPT with MUMPS) at the common tolerance"),
    "alpaqa": Solver(),
    "qrsqp": Solver(options={"max_iter": COUNT, "min_iter": COUNT, "max_iter_ls": COUNT, "tol_pr": POSITIVE,
                             "tol_du": POSITIVE, "min_step_size": POSITIVE, "print_header": Flag(),
                             "print_iteration": Flag(), "hessian_approximation": Choice(("exact", "limited-memory"))},
                    uses={"conic": "qrqp"}, iteration_limit=("max_iter", 50)),
    "scpgen": Solver(),
    # shipped as plugins that need their vendor's library, absent from the wheel: build errors
    "knitro": Solver(),
    "snopt": Solver(),
    "worhp": Solver(),
    "madnlp": Solver(),
}

#: the plugins of each kind ocp may hand to CasADi: those declared above (read when asked, so that
#: an entry added is seen), and the integrators and root finder of `ocp.direct.shooting`
PLUGINS = {"nlpsol": SOLVERS.keys(), "conic": CONICS.keys(), "linsol": LINSOLS,
           "integrator": ("collocation", "cvodes"), "rootfinder": ("fast_newton",)}


def folder():
    """CasADi's own folder, where its plugins are shipped."""
    import casadi

    return os.path.dirname(os.path.abspath(casadi.__file__))


def available(kind, name):
    """Whether `name` is a plugin of `kind` that ocp declares (PLUGINS), CasADi ships
    (libcasadi_<kind>_<name>.so in its folder) and that loads from there by its absolute path (its
    dependencies found): only then does CasADi's own search stop at its folder. Nothing is loaded
    for a name that is not declared."""
    return kind in PLUGINS and name in PLUGINS[kind] and _loads(kind, name)


@cached          # a repeated check after `clear` costs a stat and a dlopen of a library already open
def _loads(kind, name):
    path = os.path.join(folder(), f"libcasadi_{kind}_{name}.so")
    if not os.path.isfile(path):
        return False
    try:
        ctypes.CDLL(path)
    except OSError:
        return False
    return True


def require(kind, name, error=InputError):
    """`error` (InputError: a name from the user; Fault: one ocp itself names) unless `name` is an
    available plugin of `kind` (`available`)."""
    if not available(kind, name):
        shipped = ", ".join(n for n in PLUGINS.get(kind, ()) if available(kind, n))
        declared = name in PLUGINS.get(kind, ())
        raise error(f"{kind} plugin {name!r} is " + ("not loadable from this CasADi installation"
                         if declared else "not one ocp accepts") + f"; accepted: {shipped}")


def solver(name):
    """The registry entry of the NLP solver `name` (InputError naming the accepted ones)."""
    if not isinstance(name, str) or name not in SOLVERS:
        raise InputError(f"solver = {short(name)} is not an NLP solver ocp knows; accepted: {', '.join(SOLVERS)} "
                         f"(available here: {', '.join(available_solvers())})")
    return SOLVERS[name]


def available_solvers():
    """The solvers of SOLVERS this CasADi installation can load."""
    return [name for name in SOLVERS if available("nlpsol", name)]


def limits(name, options, time_limit_s=math.inf):
    """The limits of one start of solver `name` under `options`, each the solver's own option ->
    its value: the iterations (the option given, else the solver's own default, made explicit so
    that the row records it) and, where the solver has a CPU-time option and `time_limit_s` is
    finite, the CPU seconds (the option given, else `time_limit_s`). The iteration limit decides
    alike on any machine; the CPU-time one is a wide margin (a start of the quick suite takes a
    second or less)."""
    entry = solver(name)
    limited = {}
    if entry.iteration_limit:
        option, default = entry.iteration_limit
        limited[option] = options.get(option, default)
    if entry.cpu_limit and (entry.cpu_limit in options or math.isfinite(time_limit_s)):
        limited[entry.cpu_limit] = float(options.get(entry.cpu_limit, time_limit_s))
    return limited


def quiet_options(name, options, symbolic, lbg, ubg):
    """CasADi's defaults made quiet, under the user's `options` (which win): expand where the
    transcription is SX, print levels off, the solver's own times recorded (`record_time`: its
    stats' t_proc_total, t_wall_total); fatrop is told which constraints are equalities; a QP
    solver silenced and its failure reported through the NLP's status."""
    entry = SOLVERS[name]
    opts = dict(options)
    if symbolic == "SX":
        opts.setdefault("expand", True)
    opts.setdefault("print_time", False)
    opts.setdefault("record_time", True)
    for key, value in entry.quiet.items():
        opts.setdefault(key, value)
    if entry.equality:
        opts.setdefault("equality", [bool(lo == hi) for lo, hi in zip(lbg, ubg)])
    if entry.qp:
        qp = opts.get("qpsol", entry.qp)
        opts.setdefault("qpsol_options", {**(CONICS[qp].quiet if qp in CONICS else {}), "error_on_fail": False})
    return opts


# --- loading ------------------------------------------------------------------------------------

_lock = threading.Lock()
_entered = 0
_back = None
_private = None


@contextlib.contextmanager
def loading():
    """Run CasADi calls that may load a plugin with the working folder set to a private empty folder
    (created once per process, mode 0700, removed at its exit), so that CasADi's last search path "." finds nothing;
    restored on leaving (by descriptor: a renamed or removed working folder comes back too).
    Re-entrant and shared between threads: the first to enter moves, the last to leave restores."""
    global _entered, _back, _private
    with _lock:
        if _entered == 0:
            try:
                if _private is None:
                    _private = tempfile.mkdtemp(prefix="ocp-casadi-")
                    atexit.register(_remove, _private, os.getpid())
                _back = os.open(".", os.O_RDONLY)
                os.chdir(_private)
            except OSError as err:
                raise Fault(f"cannot enter ocp's private folder for loading CasADi plugins: {err}") from None
        _entered += 1
    try:
        yield
    finally:
        with _lock:
            _entered -= 1
            if _entered == 0:
                os.fchdir(_back)
                os.close(_back)
                _back = None


def _remove(path, pid):
    """At exit of the process that made it, the private folder removed (if still empty)."""
    if os.getpid() == pid:
        with contextlib.suppress(OSError):
            os.rmdir(path)


class Guarded:
    """A CasADi Function called inside `loading` (a solver may load a plugin at its first call:
    blockSQP's linear solver)."""

    def __init__(self, function):
        self.function = function

    def __call__(self, *args, **kwargs):
        with loading():
            return self.function(*args, **kwargs)

    def stats(self):
        return self.function.stats()
