"""Minimum-time problems for the pendulum of `ocp.model`, declared as plain data.

    minimise T  subject to  x' = f(x, u; kappa), |u| <= 1, x(0) = x0, x(T) = target.

theta lives on a circle, so a target is a set of branches: the upright (pi + 2*pi*k, 0) for
swing-up, the hanging (2*pi*k, 0) for damping. `branch=None` lets the solver reach any branch
(the result says which); an integer k pins one.
"""

import math
from dataclasses import dataclass, asdict

from .errors import InputError, finite

#: problem name -> (target angle of branch 0, default initial state)
KINDS = {
    "swing-up": (math.pi, (0.0, 0.0)),
    "damping": (0.0, (math.pi, 0.0)),
}


@dataclass(frozen=True)
class Problem:
    """One minimum-time transfer: `kind` in KINDS, torque bound `kappa` > 0, start `x0`."""

    kind: str
    kappa: float
    x0: tuple[float, float]
    branch: int | None = None

    def __post_init__(self):
        if self.kind not in KINDS:
            raise InputError(f"unknown problem {self.kind!r}; accepted: {', '.join(KINDS)}")
        kappa = finite("kappa", self.kappa, "a finite number > 0")
        if kappa <= 0:
            raise InputError(f"kappa = {self.kappa!r} must be > 0 (the torque bound tau0/(m g l))")
        try:
            theta0, omega0 = self.x0
        except (TypeError, ValueError):
            raise InputError(f"x0 = {self.x0!r} is not a pair THETA OMEGA of finite numbers") from None
        x0 = (finite("theta0", theta0), finite("omega0", omega0))
        if self.branch is not None and (isinstance(self.branch, bool) or int(self.branch) != self.branch):
            raise InputError(f"branch = {self.branch!r} must be an integer k (target angle base + 2*pi*k)")
        object.__setattr__(self, "kappa", kappa)
        object.__setattr__(self, "x0", x0)
        if self.branch is not None:
            object.__setattr__(self, "branch", int(self.branch))

    @property
    def target_base(self):
        """Target angle of branch 0: pi (swing-up) or 0 (damping)."""
        return KINDS[self.kind][0]

    def target(self, k):
        """Target state of branch k: (base + 2*pi*k, 0)."""
        return (self.target_base + 2 * math.pi * k, 0.0)

    def nearest_branch(self, theta):
        """The branch k whose target angle is nearest to theta (ties go to the smaller |k|)."""
        s = (theta - self.target_base) / (2 * math.pi)
        lo, hi = math.floor(s), math.ceil(s)
        if s - lo != hi - s:
            return lo if s - lo < hi - s else hi
        return min((lo, hi), key=abs)

    @property
    def stop_angle(self):
        """theta0 + omega0*|omega0|/(2*kappa): where full braking (u = -sign(omega), gravity
        neglected) brings the pendulum to rest."""
        theta0, omega0 = self.x0
        return theta0 + omega0 * abs(omega0) / (2 * self.kappa)

    @property
    def guess_branch(self):
        """The branch an initial guess aims at: the pinned one, else the nearest to `stop_angle`."""
        return self.branch if self.branch is not None else self.nearest_branch(self.stop_angle)

    def to_dict(self):
        return asdict(self)


def swing_up(kappa, x0=None, branch=None):
    """Minimum-time swing-up from x0 (default (0, 0), hanging at rest) to the upright (pi + 2*pi*k, 0)."""
    return Problem("swing-up", kappa, KINDS["swing-up"][1] if x0 is None else x0, branch)


def damping(kappa, x0=None, branch=None):
    """Minimum-time damping from x0 (default (pi, 0), upright at rest) to the hanging (2*pi*k, 0)."""
    return Problem("damping", kappa, KINDS["damping"][1] if x0 is None else x0, branch)


def make(kind, kappa, x0=None, branch=None):
    """The problem named `kind` ("swing-up" or "damping")."""
    if kind not in KINDS:
        raise InputError(f"unknown problem {kind!r}; accepted: {', '.join(KINDS)}")
    return {"swing-up": swing_up, "damping": damping}[kind](kappa, x0, branch)
