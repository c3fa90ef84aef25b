"""The instances of the reference set, declared once: a stable id named by what each is, and the
families that make the set (every number in an id is the number the instance uses).

    kappa-sweep      the standard start, kappa log-spaced from 0.05 to 10 (4 significant digits)
    bifurcation      kappa_n (1 +- 1e-3), kappa_n (1 +- 1e-2) at the standard start and at the state
                     attaining kappa_n (`ocp/synthesis/data/bifurcation.jsonl`)
    attaining-state  the state attaining kappa_n, at kappa_n: two extremals tie there
    plane            the standard start on the plane (target branch 0 pinned)
    random           seeded starts |theta0| <= pi, |omega0| <= 4 (4 decimals), kappa log-uniform in
                     [0.25, 4] (3 significant digits), and more (a second seed) with kappa in [1, 5]
    fast             seeded starts |theta0| <= pi, 4 < |omega0| <= 20
    near-dispersal   (DELTA, 0) for swing-up and (pi + DELTA, 0) for damping: next to the start whose two
                     mirror-image optima tie, so two optima lie within 1e-6 of each other

An id is KIND/READING/kKAPPA/x0=START: READING is circle or plane-bK (branch K pinned), KAPPA the
value or kappa_n*FACTOR, START "standard", "attaining-n" or "(THETA0,OMEGA0)".
"""

import math
from dataclasses import dataclass, field

import numpy as np

#: the seed of the random and fast starts
SEED = 20
#: the offset of the near-dispersal starts from the symmetric ones
DELTA = 1e-7
FACTORS = ("0.99", "0.999", "1.001", "1.01")


@dataclass(frozen=True)
class Instance:
    """One minimum-time transfer of the set: `kind`, `kappa`, start `x0`, `branch` (None: the circle)."""

    id: str
    kind: str
    kappa: float
    x0: tuple
    branch: int | None
    families: tuple = field(default=())

    def problem(self):
        from ..core.problem import make
        return make(self.kind, self.kappa, self.x0, self.branch)


def _start(x0):
    return "(" + ",".join(f"{v:.10g}" for v in x0) + ")"


def _instance(kind, kappa, x0, branch, families, kappa_text=None, start_text=None):
    from ..core.problem import KINDS

    standard = x0 is None
    x0 = KINDS[kind].start if standard else tuple(float(v) for v in x0)
    reading = "circle" if branch is None else f"plane-b{branch}"
    start = "standard" if standard else (start_text or _start(x0))
    return Instance(f"{kind}/{reading}/k{kappa_text or f'{kappa:.10g}'}/x0={start}", kind, float(kappa), x0, branch,
                    tuple(families) + (("standard-start",) if standard else ()))


def _bifurcations():
    """[(kind, n, kappa_n, attaining state)] of the stored bifurcation values."""
    from ..synthesis.results import stored

    return [(r["kind"], r["n"], r["kappa"], tuple(r["state"])) for r in stored().values() if r["reading"] == "circle"]


def _random(rng, kind, count, omega_low, omega_high, family, kappas=(0.25, 4)):
    out = []
    for _ in range(count):
        theta0 = round(float(rng.uniform(-math.pi, math.pi)), 4)
        omega0 = round(float(rng.choice((-1, 1)) * rng.uniform(omega_low, omega_high)), 4)
        kappa = float(f"{math.exp(rng.uniform(*np.log(kappas))):.3g}")
        out.append(_instance(kind, kappa, (theta0, omega0), None, (family,)))
    return out


def all_instances():
    """Every Instance of the set, in a fixed order."""
    out = []
    for kind in ("swing-up", "damping"):
        for kappa in np.geomspace(0.05, 10, 32):
            out.append(_instance(kind, float(f"{kappa:.4g}"), None, None, ("kappa-sweep",)))
    for kind, n, kappa_n, state in _bifurcations():
        out.append(_instance(kind, kappa_n, state, None, ("attaining-state", "bifurcation"), f"=kappa{n}",
                             f"attaining-{n}"))
        for factor in FACTORS:
            kappa = kappa_n * float(factor)
            out.append(_instance(kind, kappa, None, None, ("bifurcation",), f"=kappa{n}*{factor}"))
            out.append(_instance(kind, kappa, state, None, ("bifurcation",), f"=kappa{n}*{factor}", f"attaining-{n}"))
    for kind in ("swing-up", "damping"):
        for kappa in np.geomspace(0.1, 10, 12):
            out.append(_instance(kind, float(f"{kappa:.4g}"), None, 0, ("plane",)))
    rng = np.random.default_rng(SEED)
    for kind in ("swing-up", "damping"):
        out += _random(rng, kind, 24, 0.0, 4.0, "random")
    for kind in ("swing-up", "damping"):
        out += _random(rng, kind, 10, 4.0, 20.0, "fast")
    rng = np.random.default_rng(SEED + 1)
    for kind in ("swing-up", "damping"):
        out += _random(rng, kind, 24, 0.0, 4.0, "random", (1, 5))
    for kappa in (0.3, 0.5, 0.75, 1.0, 2.0, 5.0):
        out.append(_instance("swing-up", kappa, (DELTA, 0.0), None, ("near-dispersal",)))
        out.append(_instance("damping", kappa, (math.pi + DELTA, 0.0), None, ("near-dispersal",),
                             start_text=f"(pi+{DELTA:g},0)"))
    return out


def find(instance_id):
    """The Instance with this id, or None."""
    return next((i for i in all_instances() if i.id == instance_id), None)
