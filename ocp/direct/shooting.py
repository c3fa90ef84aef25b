"""Multiple shooting: an integrator maps the node state over each interval,

    z_{k+1} = (F(x_k, u_k, h), T_k),   h = T_k / N,

with F from the registry INTEGRATORS: "rk4" (M classical RK4 steps), "collocation" (CasADi's
integrator, M Radau elements of degree 3), "cvodes" (CasADi's SUNDIALS CVODES, tolerance tol).
A new integrator: a function (settings) -> F(x, u, h, kappa) and one line in INTEGRATORS.
"""

from dataclasses import dataclass

from ..core import model
from ..core.errors import Fault
from . import solvers
from .base import N_MAX, Setting, SizeLimit, Transcription, grid_bound

M_MAX = 64
#: `grid_bound` is stated for rk4 up to this N, where its coverage was measured (71 of 71 random
#: instances at N = 400, the four cases of the N-sweep): beyond, IPOPT's default tolerance
#: (tol = 1e-8) leaves an error of a few 1e-6 in T that it does not count (benchmarks/direct_error.py
#: --coverage: at N = 800 it failed on 7 of 39 random instances, by up to 1.7 times)
BOUND_N_MAX = 400
#: the NLP's size per integrator (integration steps: what its memory and time grow with) and its
#: limit, measured by benchmarks/direct_size.py (benchmarks/direct_size.jsonl: one start of
#: swing-up kappa = 1, IPOPT, on the shared 2-core machine under load)
SIZES = {
    "rk4": (lambda s: s.N * s.M, SizeLimit(20000, "N*M", "about 1.6 GB, 25 to 80 s to build and 2.5 s per start")),
    "collocation": (lambda s: s.N * s.M, SizeLimit(2000, "N*M", "about 0.2 GB, 25 s to build and 75 s per start")),
    "cvodes": (lambda s: s.N, SizeLimit(500, "N", "about 0.13 GB, 2 s to build and 40 s per start with IPOPT")),
}


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


def _rk4(settings):
    import casadi as ca

    x, u, h, kappa = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("h"), ca.SX.sym("kappa")
    return ca.Function("F", [x, u, h, kappa], [rk4_flow(x, u, kappa, h, settings.M)])


def _casadi_integrator(plugin, options):
    """CasADi's integrator `plugin` (and the root finder an option names), each checked to be a
    plugin CasADi ships and loads from its own folder, built inside `solvers.loading`."""
    import casadi as ca

    solvers.require("integrator", plugin, Fault)
    if "rootfinder" in options:
        solvers.require("rootfinder", options["rootfinder"], Fault)
    x, u, h, kappa = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("h"), ca.SX.sym("kappa")
    with solvers.loading():
        integ = ca.integrator("I", plugin, {"x": x, "p": ca.vertcat(u, h, kappa), "ode": h * model.rhs(x, u, kappa)},
                              0, 1, options)
    xs, us, hs, ks = ca.MX.sym("x", 2), ca.MX.sym("u"), ca.MX.sym("h"), ca.MX.sym("kappa")
    return ca.Function("F", [xs, us, hs, ks], [integ(x0=xs, p=ca.vertcat(us, hs, ks))["xf"]])


def _collocation(settings):
    return _casadi_integrator("collocation", {"number_of_finite_elements": settings.M, "interpolation_order": 3,
                                              "collocation_scheme": "radau", "simplify": True,
                                              "rootfinder": "fast_newton"}).expand()


def _cvodes(settings):
    return _casadi_integrator("cvodes", {"abstol": settings.tol, "reltol": settings.tol})


#: integrator name -> (builder, the settings it takes besides N and integrator)
INTEGRATORS = {
    "rk4": (_rk4, ("M",)),
    "collocation": (_collocation, ("M",)),
    "cvodes": (_cvodes, ("tol",)),
}


@dataclass(frozen=True)
class MultipleShooting(Transcription):
    """N intervals; `integrator` over each (INTEGRATORS): "rk4" or "collocation" with M steps or
    elements, "cvodes" with relative and absolute tolerance `tol`."""

    N: int = 100
    integrator: str = "rk4"
    M: int = 4
    tol: float = 1e-10

    name = "multiple-shooting"
    SETTINGS = (
        Setting("N", int, 100, "intervals", 2, N_MAX),
        Setting("integrator", str, "rk4", "the integrator over each interval", choices=tuple(INTEGRATORS)),
        Setting("M", int, 4, "rk4 steps or collocation elements per interval", 1, M_MAX),
        Setting("tol", float, 1e-10, "cvodes relative and absolute tolerance", 1e-14, 1e-3),
    )

    def __post_init__(self):
        self.check_settings()

    @property
    def symbolic(self):
        return "MX" if self.integrator == "cvodes" else "SX"

    def applicable(self):
        return ("N", "integrator") + INTEGRATORS[self.integrator][1]

    def prepare(self):
        """F(x, u, h, kappa): the state after time h under constant u, by the chosen integrator."""
        return INTEGRATORS[self.integrator][0](self)

    def stage(self, x, u, h, kappa, extra, prepared):
        return prepared(x, u, h, kappa), []

    def size(self):
        return SIZES[self.integrator][0](self)

    def size_limit(self):
        return SIZES[self.integrator][1]

    def T_bound(self, structure, kappa, resim_miss):
        """`grid_bound` for rk4 up to BOUND_N_MAX (where its coverage was measured), else None."""
        return grid_bound(structure, kappa, resim_miss) if self.integrator == "rk4" and self.N <= BOUND_N_MAX else None

    def family(self):
        return f"MS {self.integrator} " + (f"tol={self.tol:g}" if self.integrator == "cvodes" else f"M={self.M}")

    def describe(self):
        option = f"tol = {self.tol:g}" if self.integrator == "cvodes" else f"M = {self.M}"
        return f"multiple shooting, N = {self.N}, {self.integrator} ({option})"
