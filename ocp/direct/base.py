"""The contract of a direct transcription, in the spirit of scipy's `OdeSolver`.

Every transcription has free final time: time is scaled to s = t/T in [0, 1], cut into N equal
intervals with a constant control u_k in CONTROL_BOUNDS each; the node states
z_k = (theta_k, omega_k, T_k) carry T as a state (constant across the stages), so the NLP is
stagewise, as structure-exploiting solvers (fatrop) require. A transcription is a frozen
dataclass (plain data: it travels to worker processes) and implements:

    1. `name`: its key in `ocp.direct.TRANSCRIPTIONS`
    2. its settings as dataclass fields, each declared in `SETTINGS` (a `Setting`: type, range,
       help; the command line's flags are made from them) and checked by `check_settings()` in
       `__post_init__` (InputError)
    3. `applicable()`: the names of the settings that apply (an option given that does not apply is
       an error, not ignored: `ocp.direct.make`)
    4. `extra`: NLP variables per stage besides z_k and u_k (e.g. collocation states)
    5. `prepare()`: what every stage shares, built once per NLP (an integrator's map, a matrix)
    6. `stage(x, u, h, kappa, extra, prepared)`: the state at the end of the interval and the
       stage's own constraints (expressions that must vanish), in CasADi symbols
    7. `describe()`: one line for summaries; `family()`: the short label of charts without N
    8. `extra_guess(theta, omega)`: the initial values of the stages' extra variables, an
       (N, extra) array, from a guess's node values (N+1 each)
    9. `size()` and `size_limit()`: the NLP's size in the unit its memory and time grow with (e.g.
       RK4 steps N*M), and the largest accepted with what it costs (`SizeLimit`, measured by
       benchmarks/direct_size.py); `check_settings()` refuses a larger NLP (InputError)
    10. `T_bound(structure, kappa, resim_miss)`: the stated bound of the error of a verified T (the
       transcription's own evidence; `grid_bound` where it holds), None where none is stated
    11. `integration_error(t, u, x0, kappa)`: the transcription's own estimate of how far its
       integration of a control lands from the exact flow's (what the re-simulated miss of a
       converged answer is, at that N): by default its map (`stage`, its extra variables solved
       from its own constraints by Newton's method) at h and at two half steps (`step_doubling`)
"""

from dataclasses import asdict, dataclass, fields

import numpy as np

from ..core.errors import Fault, InputError, finite, integer

N_MAX = 5000     # the largest N of any transcription; the NLP's size is limited too (`size_limit`)
#: the safety factor of `grid_bound` over its leading-order term (the terms of order h^3 neglected)
GRID_SAFETY = 2.0


@dataclass(frozen=True)
class Setting:
    """One setting of a transcription: its type (int, float or str), default, range or choices, and
    a one-line help. The command line's `--NAME` flags, their help and their checks are made from
    these (`ocp.direct.settings()`)."""

    name: str
    kind: type
    default: object
    help: str
    low: float | None = None
    high: float | None = None
    choices: tuple = ()

    def accepted(self):
        """What the setting accepts, in words."""
        if self.choices:
            return f"one of {', '.join(map(str, self.choices))}"
        what = {int: "an integer", float: "a number"}[self.kind]
        return f"{what} from {self.low:g} to {self.high:g}"

    def parse(self, value):
        """`value` (text or a number) as the setting's type, checked; InputError names the setting
        and what it accepts."""
        accepted = f"{self.accepted()} ({self.help})"
        if self.choices:
            if value not in self.choices:
                raise InputError(f"{self.name} = {str(value)[:40]!r} is not accepted; {self.name} accepts {accepted}")
            return value
        if self.kind is int:
            return integer(self.name, value, accepted, self.low, self.high)
        return finite(self.name, value, accepted, self.low, self.high)


@dataclass(frozen=True)
class SizeLimit:
    """The largest accepted NLP size (`Transcription.size`), in words (`unit`, e.g. "N*M"), and
    what the NLP of that size was measured to take (`cost`, e.g. "1.5 GB and 25 s to build")."""

    limit: int
    unit: str
    cost: str


def grid_bound(structure, kappa, resim_miss):
    """The error bound of T for a bang-bang control piecewise constant on a uniform grid of step h:

        |T - T*| <= GRID_SAFETY * h^2 * sum_i kappa / (4 w_i) + resim_miss * (1/kappa + 1/w_n),
        w_i = |omega_i| - (1 + kappa) h.

    The first term is the switch's: a switch at fraction a of its interval, replaced by the
    interval's mean control, leaves the same omega and theta short by kappa h^2 a (1 - a) <=
    kappa h^2 / 4, which costs lambda_theta * dtheta in T, with lambda_theta = -1/omega_i at the
    switch (H = 1 + lambda . f = 0 where lambda_omega = 0); omega_i is the direct answer's, within
    (1 + kappa) h of the optimum's (|omega'| <= 1 + kappa, switch times within h). The second is
    the integrator's: the re-simulated control misses the target by resim_miss, which costs
    |lambda(T)| resim_miss, |lambda_omega(T)| = 1/kappa at rest on the target, |lambda_theta| that
    of the last switch. Valid to leading order in h: where a switch lies within (1 + kappa) h of a
    turning point (w_i <= 0) or there is no switch, None (no bound). Its coverage against the exact
    search: benchmarks/direct_error.py --coverage (benchmarks/README.md)."""
    if not structure.bang_bang or not structure.switch_states:
        return None
    h = structure.h
    w = [abs(omega) - (1 + kappa) * h for _, omega in structure.switch_states]
    if min(w) <= 0:
        return None
    return GRID_SAFETY * h * h * sum(kappa / (4 * wi) for wi in w) + resim_miss * (1 / kappa + 1 / w[-1])


def step_doubling(flow, t, u, x0, kappa):
    """The error of the end state of the map x_{k+1} = flow(x_k, u_k, h_k, kappa) along the grid
    `t` from x0, estimated from the same map at two half steps: to leading order, for a map of
    order p >= 1, err = |x_h - x_{h/2}| 2^p / (2^p - 1) <= 2 |x_h - x_{h/2}|, the estimate returned."""
    whole, halves = np.array(x0, float), np.array(x0, float)
    for h, uk in zip(np.diff(t), u):
        whole = np.array(flow(whole, uk, h, kappa)).ravel()
        for _ in range(2):
            halves = np.array(flow(halves, uk, h / 2, kappa)).ravel()
    return 2.0 * float(np.hypot(*(whole - halves)))


class Transcription:
    name = ""
    extra = 0
    symbolic = "SX"          # "MX" where an integrator call cannot be expanded (cvodes)
    #: every setting the transcription can take (the dataclass fields), with type, range and help
    SETTINGS = ()

    def check_settings(self):
        """Each setting's value checked by its declaration, then the NLP's size by its limit
        (InputError)."""
        for setting in self.SETTINGS:
            setting.parse(getattr(self, setting.name))
        limit = self.size_limit()
        if self.size() > limit.limit:
            raise InputError(f"{limit.unit} = {self.size()} is too large for {self.describe()}; accepted: "
                             f"{limit.unit} <= {limit.limit} (that NLP takes {limit.cost})")

    def size(self):
        raise NotImplementedError

    def size_limit(self):
        raise NotImplementedError

    def extra_guess(self, theta, omega):
        return np.zeros((len(theta) - 1, self.extra))

    def T_bound(self, structure, kappa, resim_miss):
        return None

    def integration_error(self, t, u, x0, kappa):
        return step_doubling(self.flow(), t, u, x0, kappa)

    def flow(self):
        """The stage as a numeric map (x, u, h, kappa) -> its end state: its extra variables solved
        from its own constraints (CasADi's rootfinder fast_newton, from `extra_guess`)."""
        import casadi as ca

        from . import solvers
        sym = getattr(ca, self.symbolic)
        x, u, h, kappa, extra = sym.sym("x", 2), sym.sym("u"), sym.sym("h"), sym.sym("kappa"), sym.sym("c", self.extra)
        end, own = self.stage(x, u, h, kappa, extra, self.prepare())
        inputs = ca.vertcat(x, u, h, kappa)
        ends = ca.Function("end", [extra, inputs], [end])
        if not self.extra:
            return lambda xk, uk, hk, k: ends(ca.DM(0, 1), ca.vertcat(xk, uk, hk, k))
        solvers.require("rootfinder", "fast_newton", Fault)
        with solvers.loading():
            solve = ca.rootfinder("stage", "fast_newton", ca.Function("g", [extra, inputs], [ca.vertcat(*own)]))

        def step(xk, uk, hk, k):
            given = ca.vertcat(xk, uk, hk, k)
            guess = self.extra_guess(np.full(2, xk[0]), np.full(2, xk[1]))[0]
            return ends(solve(guess, given), given)
        return step

    def applicable(self):
        return tuple(f.name for f in fields(self))

    def prepare(self):
        return None

    def stage(self, x, u, h, kappa, extra, prepared):
        raise NotImplementedError

    def describe(self):
        raise NotImplementedError

    def family(self):
        raise NotImplementedError

    def to_dict(self):
        return dict({k: v for k, v in asdict(self).items() if k in self.applicable()}, transcription=self.name)


def settings_error(transcription, given):
    """InputError for the settings in `given` that do not apply to `transcription`."""
    extra = sorted(set(given) - set(transcription.applicable()))
    if extra:
        raise InputError(f"{', '.join(extra)} do{'es' if len(extra) == 1 else ''} not apply to {transcription.describe()}; "
                         f"it takes: {', '.join(transcription.applicable())}")
