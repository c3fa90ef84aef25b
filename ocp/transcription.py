"""Direct transcriptions with free final time, for the problems of `ocp.problems`.

Time is scaled to s = t/T in [0, 1]; on N equal intervals the control is constant, u_k in [-1, 1].
`MultipleShooting`: an integrator maps the node state over one interval,

    z_{k+1} = F(z_k, u_k),   z_k = (theta_k, omega_k, T_k),   T_{k+1} = T_k,
    minimise T_0   s.t.   z_0 = (x0, T_0),   omega_N = 0,   theta_N at the target.

`DirectCollocation`: the state on interval k is the polynomial through x_k and d Radau points
X_k1..X_kd (unknowns of the NLP, stage k), sum_r C[r, j] X_kr = h f(X_kj, u_k) for j = 1..d, and
x_{k+1} = X_kd (Radau IIA, order 2d - 1 at the nodes).

T is carried as a state (constant across the stages) so the NLP is stagewise, as structure-
exploiting solvers (fatrop) require. The target angle is either pinned by bounds
(theta_N = base + 2*pi*k) or left to any branch: sin(theta_N - base) = 0, cos(theta_N - base) >= 0.

A built NLP depends only on the transcription settings, the solver and its options, and
whether the branch is free: kappa, x0, the target and the initial guess are solve-time inputs, so
one build serves every problem (`build` caches it).
"""

import json
import math
import time
from dataclasses import dataclass, asdict
from functools import lru_cache

import casadi as ca
import numpy as np

from . import model
from .errors import InputError, last_line

INTEGRATORS = ("rk4", "cvodes", "collocation")
T_BOUNDS = (1e-3, 1e3)


@dataclass(frozen=True)
class MultipleShooting:
    """N intervals; `integrator` over each: "rk4" (M fixed steps), "collocation" (CasADi's,
    M finite elements of Radau degree 3), "cvodes" (CasADi's, relative/absolute `tol`)."""

    N: int = 100
    integrator: str = "rk4"
    M: int = 4
    tol: float = 1e-10

    def __post_init__(self):
        if isinstance(self.N, bool) or not isinstance(self.N, int) or self.N < 2:
            raise InputError(f"N = {self.N!r} must be an integer >= 2 (the number of shooting intervals)")
        if self.integrator not in INTEGRATORS:
            raise InputError(f"unknown integrator {self.integrator!r}; accepted: {', '.join(INTEGRATORS)}")
        if isinstance(self.M, bool) or not isinstance(self.M, int) or self.M < 1:
            raise InputError(f"M = {self.M!r} must be an integer >= 1 (integrator steps per interval)")
        if not (0 < self.tol < 1):
            raise InputError(f"tol = {self.tol!r} must be in (0, 1) (CVODES relative and absolute tolerance)")

    def to_dict(self):
        return dict(asdict(self), transcription="multiple shooting")

    @property
    def stage_extra(self):
        return 0


@dataclass(frozen=True)
class DirectCollocation:
    """N intervals, each with Radau collocation of `degree` (order 2*degree - 1 at the nodes)."""

    N: int = 100
    degree: int = 3

    def __post_init__(self):
        if isinstance(self.N, bool) or not isinstance(self.N, int) or self.N < 2:
            raise InputError(f"N = {self.N!r} must be an integer >= 2 (the number of collocation intervals)")
        if isinstance(self.degree, bool) or not isinstance(self.degree, int) or not 1 <= self.degree <= 9:
            raise InputError(f"degree = {self.degree!r} must be an integer from 1 to 9 (Radau points per interval)")

    def to_dict(self):
        return dict(asdict(self), transcription="direct collocation", integrator="radau")

    @property
    def stage_extra(self):
        """Collocation states per stage: 2 per Radau point."""
        return 2 * self.degree


def radau_matrices(degree):
    """C (d+1 x d+1): C[r, j] = l_r'(tau_j) for the Lagrange basis on (0, tau_1..tau_d), the
    Radau IIA points of `degree`."""
    tau = np.concatenate([[0.0], ca.collocation_points(degree, "radau")])
    C = np.zeros((degree + 1, degree + 1))
    for r in range(degree + 1):
        basis = np.poly1d([1.0])
        for m in range(degree + 1):
            if m != r:
                basis *= np.poly1d([1.0, -tau[m]]) / (tau[r] - tau[m])
        C[r] = np.polyder(basis)(tau)
    return C


def rk4_flow(x, u, kappa, duration, steps):
    """x after `duration` under constant u: `steps` classical RK4 steps (symbolic or numeric)."""
    h = duration / steps
    for _ in range(steps):
        k1 = model.rhs(x, u, kappa)
        k2 = model.rhs(x + h / 2 * k1, u, kappa)
        k3 = model.rhs(x + h / 2 * k2, u, kappa)
        k4 = model.rhs(x + h * k3, u, kappa)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return x


def interval_map(settings):
    """F(x, u, h, kappa) -> x after time h under constant u, by the chosen integrator."""
    x, u, h, kappa = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("h"), ca.SX.sym("kappa")
    if settings.integrator == "rk4":
        return ca.Function("F", [x, u, h, kappa], [rk4_flow(x, u, kappa, h, settings.M)],
                           ["x", "u", "h", "kappa"], ["xf"])
    p = ca.vertcat(u, h, kappa)
    dae = {"x": x, "p": p, "ode": h * model.rhs(x, u, kappa)}
    if settings.integrator == "collocation":
        opts = {"number_of_finite_elements": settings.M, "interpolation_order": 3,
                "collocation_scheme": "radau", "simplify": True, "rootfinder": "fast_newton"}
    else:
        opts = {"abstol": settings.tol, "reltol": settings.tol}
    integ = ca.integrator("I", settings.integrator, dae, 0, 1, opts)
    xs, us, hs, ks = ca.MX.sym("x", 2), ca.MX.sym("u"), ca.MX.sym("h"), ca.MX.sym("kappa")
    xf = integ(x0=xs, p=ca.vertcat(us, hs, ks))["xf"]
    F = ca.Function("F", [xs, us, hs, ks], [xf], ["x", "u", "h", "kappa"], ["xf"])
    return F.expand() if settings.integrator == "collocation" else F


@dataclass
class Transcription:
    """A built NLP: the CasADi solver and the layout of its variables.

    w = [z_0, u_0, c_0, z_1, u_1, c_1, ..., z_N] with z_k = (theta_k, omega_k, T_k), c_k the
    collocation states of stage k (none for shooting); p = (kappa, base).
    """

    settings: MultipleShooting
    solver_name: str
    options: dict
    free_branch: bool
    solver: ca.Function
    n_w: int
    n_g: int
    lbg: np.ndarray
    ubg: np.ndarray
    build_time_s: float

    @property
    def N(self):
        return self.settings.N

    def index(self):
        """Index arrays into w: theta, omega, T (N+1 each) and u (N)."""
        node = np.arange(self.N + 1) * (4 + self.settings.stage_extra)
        return node, node + 1, node + 2, node[:-1] + 3

    def pack(self, theta, omega, T, u):
        """w from node values; collocation states start at the interval's first node."""
        w = np.zeros(self.n_w)
        i_th, i_om, i_T, i_u = self.index()
        w[i_th], w[i_om], w[i_T], w[i_u] = theta, omega, T, u
        for j in range(self.settings.stage_extra // 2):
            w[i_u + 1 + 2 * j], w[i_u + 2 + 2 * j] = theta[:-1], omega[:-1]
        return w

    def bounds(self, x0, theta_end=None):
        """lbx, ubx: z_0 fixed to x0, u in [-1, 1], T in T_BOUNDS, omega_N = 0, theta_N pinned if given."""
        lbx, ubx = np.full(self.n_w, -np.inf), np.full(self.n_w, np.inf)
        i_th, i_om, i_T, i_u = self.index()
        lbx[i_u], ubx[i_u] = -1.0, 1.0
        lbx[i_T], ubx[i_T] = T_BOUNDS
        lbx[i_th[0]] = ubx[i_th[0]] = x0[0]
        lbx[i_om[0]] = ubx[i_om[0]] = x0[1]
        lbx[i_om[-1]] = ubx[i_om[-1]] = 0.0
        if theta_end is not None:
            lbx[i_th[-1]] = ubx[i_th[-1]] = theta_end
        return lbx, ubx


def _nlp(settings, free_branch):
    N = settings.N
    collocation = isinstance(settings, DirectCollocation)
    F = None if collocation else interval_map(settings)
    sym = ca.MX if getattr(settings, "integrator", "") == "cvodes" else ca.SX
    z = [sym.sym(f"z{k}", 3) for k in range(N + 1)]
    u = [sym.sym(f"u{k}") for k in range(N)]
    kappa, base = sym.sym("kappa"), sym.sym("base")
    w, g, lbg, ubg = [], [], [], []
    for k in range(N):
        h = z[k][2] / N
        w += [z[k], u[k]]
        if collocation:
            d = settings.degree
            X = [z[k][:2]] + [sym.sym(f"x{k}_{j}", 2) for j in range(1, d + 1)]
            w += X[1:]
            C = radau_matrices(d)
            for j in range(1, d + 1):
                g.append(sum(C[r, j] * X[r] for r in range(d + 1)) - h * model.rhs(X[j], u[k], kappa))
            xf = X[d]
            lbg += [0.0] * 2 * d
            ubg += [0.0] * 2 * d
        else:
            xf = F(z[k][:2], u[k], h, kappa)
        g.append(z[k + 1] - ca.vertcat(xf, z[k][2]))
        lbg += [0.0] * 3
        ubg += [0.0] * 3
    w.append(z[N])
    if free_branch:
        g += [ca.sin(z[N][0] - base), ca.cos(z[N][0] - base)]
        lbg += [0.0, 0.0]
        ubg += [0.0, math.inf]
    nlp = {"x": ca.vertcat(*w), "f": z[0][2], "g": ca.vertcat(*g), "p": ca.vertcat(kappa, base)}
    return nlp, np.array(lbg), np.array(ubg)


def _solver_options(solver_name, options, settings, lbg, ubg):
    opts = dict(options)
    if getattr(settings, "integrator", "") != "cvodes":
        opts.setdefault("expand", True)
    if solver_name == "ipopt":
        opts.setdefault("ipopt.print_level", 0)
        opts.setdefault("print_time", False)
        opts.setdefault("ipopt.sb", "yes")
    elif solver_name == "fatrop":
        opts.setdefault("structure_detection", "auto")
        opts.setdefault("equality", [bool(lo == hi) for lo, hi in zip(lbg, ubg)])
        opts.setdefault("print_time", False)
        opts.setdefault("fatrop.print_level", 0)
    elif solver_name in ("sqpmethod", "feasiblesqpmethod"):
        opts.setdefault("print_time", False)
        opts.setdefault("print_header", False)
        opts.setdefault("print_iteration", False)
        opts.setdefault("qpsol", "qrqp")
        opts.setdefault("qpsol_options", {"print_iter": False, "print_header": False, "error_on_fail": False})
        opts.setdefault("hessian_approximation", "exact")
    elif solver_name == "bonmin":
        opts.setdefault("bonmin.print_level", 0)
        opts.setdefault("print_time", False)
    return opts


def build(settings, solver_name="ipopt", options=None, free_branch=True):
    """The NLP for `settings`, handed to casadi.nlpsol(solver_name, options): cached per arguments.

    `options` pass to nlpsol untouched, over quiet defaults (expand=True where the integrator
    allows it; print levels off)."""
    if not ca.has_nlpsol(solver_name):
        raise InputError(f"unknown or unavailable NLP solver {solver_name!r}; accepted: {', '.join(available_solvers())}")
    return _build(settings, solver_name, json.dumps(options or {}, sort_keys=True), bool(free_branch))


@lru_cache(maxsize=32)
def _build(settings, solver_name, options_json, free_branch):
    start = time.perf_counter()
    nlp, lbg, ubg = _nlp(settings, free_branch)
    options = json.loads(options_json)
    try:
        solver = ca.nlpsol("nlp", solver_name, nlp, _solver_options(solver_name, options, settings, lbg, ubg))
    except RuntimeError as err:
        raise InputError(f"casadi.nlpsol({solver_name!r}) could not be built with the options {options}: "
                         f"{last_line(err)}") from None
    return Transcription(settings, solver_name, options, free_branch, solver, nlp["x"].numel(),
                         nlp["g"].numel(), lbg, ubg, time.perf_counter() - start)




def clear_cache():
    """Forget every built NLP (the next solve builds cold, e.g. to time a build)."""
    _build.cache_clear()


#: NLP plugins tried by `available_solvers`
NLP_PLUGINS = ("ipopt", "fatrop", "sqpmethod", "feasiblesqpmethod", "blocksqp", "bonmin", "knitro", "snopt",
               "worhp", "madnlp", "alpaqa", "qrsqp", "scpgen")


def available_solvers():
    """The `casadi.nlpsol` plugins this CasADi build can load."""
    return [name for name in NLP_PLUGINS if ca.has_nlpsol(name)]
