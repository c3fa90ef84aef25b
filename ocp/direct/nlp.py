"""The NLP of a transcription (`ocp.direct.base`), handed to `casadi.nlpsol`.

    w = [z_0, u_0, c_0, z_1, u_1, c_1, ..., z_N],  z_k = (theta_k, omega_k, T_k),  c_k the stage's
    extra variables;  p = (kappa, target);
    minimise T_0  s.t.  stage constraints,  z_{k+1} = (x at the end of stage k, T_k),
                        z_0 = (x0, T_0) (bounds),  x(T) in the target set (`terminal_bounds`
                        on z_N, `terminal_constraints`).

A built NLP depends only on the transcription, the solver and its options, and the reading
(circle or plane): kappa, x0, the target angle and the initial guess are solve-time inputs, so
one build serves every problem (`build`, cached in `ocp.core.cache`).
"""

import json
import time
from dataclasses import dataclass

import numpy as np

from ..core.cache import cached
from ..core.errors import InputError, last_line
from ..core.output import solver_output
from ..core.problem import CONTROL_BOUNDS, terminal_bounds, terminal_constraints
from . import solvers, watch
from .base import Transcription


@dataclass
class NLP:
    """A built NLP: the CasADi solver (and its iteration callback, `ocp.direct.watch`, kept alive
    with it), the layout of its variables, and the wall and CPU time (the process's) of its build."""

    settings: Transcription
    solver_name: str
    options: dict
    reading: str
    solver: object
    n_w: int
    n_g: int
    lbg: np.ndarray
    ubg: np.ndarray
    build_time_s: float
    build_cpu_time_s: float
    callback: object = None

    @property
    def N(self):
        return self.settings.N

    def index(self):
        """Index arrays into w: theta, omega, T (N+1 each) and u (N)."""
        node = np.arange(self.N + 1) * (4 + self.settings.extra)
        return node, node + 1, node + 2, node[:-1] + 3

    def extra_index(self):
        """Index array into w of the stages' extra variables, (N, extra)."""
        return self.index()[3][:, None] + 1 + np.arange(self.settings.extra)

    def pack(self, theta, omega, T, u):
        """w from node values; the stages' extra variables as the transcription guesses them from
        these (`Transcription.extra_guess`)."""
        w = np.zeros(self.n_w)
        i_th, i_om, i_T, i_u = self.index()
        w[i_th], w[i_om], w[i_T], w[i_u] = theta, omega, T, u
        w[self.extra_index()] = self.settings.extra_guess(np.asarray(theta, float), np.asarray(omega, float))
        return w

    def bounds(self, x0, target, T_bounds):
        """lbx, ubx: z_0 fixed to x0, u in CONTROL_BOUNDS, T in T_bounds, z_N as the target set fixes
        it (`terminal_bounds`)."""
        lbx, ubx = np.full(self.n_w, -np.inf), np.full(self.n_w, np.inf)
        i_th, i_om, i_T, i_u = self.index()
        lbx[i_u], ubx[i_u] = CONTROL_BOUNDS
        lbx[i_T], ubx[i_T] = T_bounds
        lbx[i_th[0]] = ubx[i_th[0]] = x0[0]
        lbx[i_om[0]] = ubx[i_om[0]] = x0[1]
        fixed = terminal_bounds(self.reading, target)
        for index, name in ((i_th[-1], "theta"), (i_om[-1], "omega")):
            if fixed[name] is not None:
                lbx[index] = ubx[index] = fixed[name]
        return lbx, ubx


def _nlp(settings, reading):
    import casadi as ca

    N = settings.N
    sym = getattr(ca, settings.symbolic)
    prepared = settings.prepare()
    z = [sym.sym(f"z{k}", 3) for k in range(N + 1)]
    u = [sym.sym(f"u{k}") for k in range(N)]
    kappa, target = sym.sym("kappa"), sym.sym("target")
    w, g, lbg, ubg = [], [], [], []
    for k in range(N):
        extra = sym.sym(f"c{k}", settings.extra)
        w += [z[k], u[k], extra]
        end, own = settings.stage(z[k][:2], u[k], z[k][2] / N, kappa, extra, prepared)
        for c in own + [z[k + 1] - ca.vertcat(end, z[k][2])]:
            g.append(c)
            lbg += [0.0] * c.numel()
            ubg += [0.0] * c.numel()
    w.append(z[N])
    for expression, lower, upper in terminal_constraints(reading, z[N][0], z[N][1], target):
        g.append(expression)
        lbg.append(lower)
        ubg.append(upper)
    nlp = {"x": ca.vertcat(*w), "f": z[0][2], "g": ca.vertcat(*g), "p": ca.vertcat(kappa, target)}
    return nlp, np.array(lbg), np.array(ubg)


def build(settings, solver_name="ipopt", options=None, reading="circle"):
    """The NLP of `settings` for `reading`, handed to casadi.nlpsol(solver_name, options): cached
    per arguments (`ocp.core.cache.clear` forgets it). `options` pass to nlpsol over quiet defaults
    (`ocp.direct.solvers.quiet_options`); the caller has checked them (`ocp.direct.options.checked`).
    The solver is one of `ocp.direct.solvers.SOLVERS`, loadable from CasADi's folder, checked before
    CasADi sees its name; the build and every call of the solver run inside `solvers.loading`."""
    solvers.solver(solver_name)
    solvers.require("nlpsol", solver_name)
    return _build(settings, solver_name, json.dumps(options or {}, sort_keys=True), reading)


@cached
def _build(settings, solver_name, options_json, reading):
    import casadi as ca

    start, cpu = time.perf_counter(), time.process_time()
    options = json.loads(options_json)
    with solvers.loading():
        nlp, lbg, ubg = _nlp(settings, reading)
        callback = watch.callback(nlp["x"].numel(), nlp["g"].numel(), nlp["p"].numel())
        try:
            with solver_output("devnull"):      # a rejected option prints the solver's help, fatrop hundreds of warnings
                function = ca.nlpsol("nlp", solver_name, nlp,
                                     dict(solvers.quiet_options(solver_name, options, settings.symbolic, lbg, ubg),
                                          iteration_callback=callback))
        except RuntimeError as err:
            raise InputError(f"casadi.nlpsol({solver_name!r}) could not be built with the options {options}: "
                             f"{_cause(err, solver_name)}") from None
    return NLP(settings, solver_name, options, reading, solvers.Guarded(function), nlp["x"].numel(), nlp["g"].numel(),
               lbg, ubg, time.perf_counter() - start, time.process_time() - cpu, callback)


def _cause(err, solver_name):
    """The line of a CasADi error that gives the cause: the solver's own ("Fatrop: ...", its first
    sentence), else the last."""
    for line in str(err).splitlines():
        if line.lower().startswith(solver_name + ":"):
            return line.split(". ", 1)[0].rstrip(".") + "."
    return last_line(err)

