"""Where each bifurcation value was located: the bracket of kappa (states with n + 1 switches at
kappa_lo, none at kappa_hi) and the window of final costate angles psi whose extremals carry them.

Located by the maps (`ocp synthesis KIND --kappa ...`: the switch counts over a window) and by the
least gap of `ocp.synthesis.bifurcation.profile` scanned over every psi whose (n + 1)-th switch
comes within 20 time units (300 to 400 angles) at kappa_lo; `ocp bifurcation` recomputes each value
from its case. The mirror image (theta -> -theta, psi -> psi + pi) carries the same value.
"""

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Case:
    kind: str
    reading: str
    n: int
    kappa_lo: float
    kappa_hi: float
    psi_lo: float
    psi_hi: float
    located: str

    @property
    def id(self):
        return f"{self.kind}/{self.reading}/{self.n}"


CASES = (
    Case("swing-up", "circle", 1, 0.795, 0.81, 2.47, 2.50,
         "maps: 2 switches near the origin at kappa = 0.79, none at 0.81; least gap at psi = 2.4869"),
    Case("swing-up", "circle", 2, 0.43, 0.45, 2.40, 2.50,
         "maps: 3 switches near the origin at kappa = 0.42, none at 0.44; least gap at psi = 2.4550"),
    Case("swing-up", "circle", 3, 0.25, 0.30, 5.50, 5.65,
         "maps: 4 switches near the origin at kappa = 0.25, none at 0.30; least gap at psi = 5.5873"),
    Case("swing-up", "circle", 4, 0.22, 0.235, 2.39, 2.45,
         "maps: 5 switches near the origin at kappa = 0.22, none at 0.235 (401 x 241 cells over [-pi, pi] x "
         "[-3, 3], horizon 32); least gap at psi = 2.4070 at kappa = 0.22"),
    Case("swing-up", "circle", 5, 0.18, 0.19, 2.38, 2.45,
         "maps: 6 switches near the origin at kappa = 0.18, none at 0.19 (401 x 241 cells over [-pi, pi] x "
         "[-3, 3], horizon 32); least gap at psi = 2.4070 at kappa = 0.18"),
    Case("damping", "circle", 1, 1.0, 1.04, 2.15, 2.30,
         "least gap: negative at kappa = 1.0 (psi = 2.235, a switch point at omega = 7.3), positive at 1.04"),
)


@dataclass(frozen=True)
class TieCase(Case):
    """A region of n + 1 switches whose end is computed by the fold-and-tie equations alone
    (`bifurcation.fold_and_tie`, against `competitor` = (arc signs, branch)): a lower bound of kappa_n,
    and kappa_n itself where the stored sweep at kappa = `above` (`results.sweep`: the gap at
    `angles` final costate angles over (0, pi), the mirror image carrying (pi, 2 pi), up to the
    time-to-go `s_max`) finds no other crossed switch with a negative gap, and the complete search
    finds n + 1 switches just upstream of the switch of the extremal psi at kappa, (kappa, psi) =
    `below` (a crossed switch of negative gap away from the fold: near it the arriving trajectory
    meets the folded switching curve again upstream)."""

    competitor: tuple = ()
    above: float = None
    below: tuple = None
    angles: int = 120
    s_max: float = 40.0

    @property
    def sweep_file(self):
        return f"sweep-{self.kind}-{self.n + 1}-{self.above!r}.jsonl"


@dataclass(frozen=True)
class PlaneCase:
    """The plane's (one pinned target) principal value of `kind`: computed by the far turnaround
    (`ocp.synthesis.limit`), its tongues' lower edge at the kappas, confirmed by the complete
    search at the states (kappa, theta_s: the turnaround of the candidate) of `confirm`."""

    kind: str
    n: int
    kappas: tuple
    confirm: tuple
    located: str
    reading = "plane"

    @property
    def id(self):
        return f"{self.kind}/plane/{self.n}"


_FAR = ("the far turnaround: the one-switch candidate's p_omega vanishes again on its first arc "
        "(limit.candidate), located at kappa = 12 by the search's tongue at (62.99, 44.43)")
PLANE_CASES = (
    PlaneCase("swing-up", 1, (2.0, 5.0, 12.0),
              ((0.9, 20 * math.pi + 0.3), (5.0, 20 * math.pi + math.pi / 4), (12.0, 40 * math.pi + math.pi / 4)), _FAR),
    PlaneCase("damping", 1, (5.0,),
              ((5.0, 20 * math.pi + math.pi / 4), (12.0, 40 * math.pi + math.pi / 4)), _FAR),
)
CASES = CASES + (
    TieCase("swing-up", "circle", 6, 0.1523, 0.1528, 2.41, 2.44,
            "maps: 7 switches near the origin at kappa = 0.15, none at 0.156 (horizon 32); at the seventh switching "
            "curve's fold (psi = 2.423) the gap against (-1, 1, -1, 1, -1, 1, -1) to branch 1 is -0.48 at kappa = "
            "0.1523, +0.34 at 0.1528 (that extremal is born between 0.1520 and 0.1522)",
            ((-1, 1, -1, 1, -1, 1, -1), 1), 0.1526, (0.1523, 2.4204)),
    TieCase("swing-up", "circle", 7, 0.131, 0.134, 2.40, 2.43,
            "the eighth switching curve's fold (psi = 2.41 to 2.43, from kappa_5 and kappa_6): gap -0.077 at kappa = "
            "0.131, +1.29 at 0.134 against (1, -1, 1, -1, 1, -1, 1, -1) to branch 1",
            ((1, -1, 1, -1, 1, -1, 1, -1), 1), 0.1312, (0.131, 2.4155)),
    TieCase("damping", "circle", 2, 0.5, 0.51, 2.20, 2.29,
            "maps: 3 switches at omega of 10 to 12 at kappa = 0.5 (a band on the braking curves); gap -0.105 at "
            "kappa = 0.5 (psi = 2.25), +0.187 at kappa = 0.51 (psi = 2.226)",
            ((-1, 1, -1), -1), 0.50341, (0.5, 2.2085)),
    TieCase("damping", "circle", 3, 0.325, 0.33, 2.22, 2.34,
            "the band of four switches on the braking curves (psi = 2.1 to 2.4): its fourth switching curve folds at "
            "psi = 2.3044, 2.28, 2.2682 at kappa = 0.325, 0.3275, 0.33 (none in that window at 0.335); the gap at the "
            "fold against (1, -1, 1, -1) to branch 1 is -0.329 at kappa = 0.325 (the state (-81.706, 7.509)), +0.057 "
            "at 0.33 (the state (-244.035, 12.789))",
            ((1, -1, 1, -1), 1), 0.3292, (0.325, 2.254), s_max=48.0),
) + PLANE_CASES


def find(case_id):
    """The Case of an id "KIND/READING/N"."""
    for case in CASES:
        if case.id == case_id:
            return case
    from ..core.errors import InputError
    raise InputError(f"unknown case {case_id!r}; accepted: {', '.join(c.id for c in CASES)}")
