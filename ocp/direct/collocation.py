"""Direct collocation: on interval k the state is the polynomial through x_k and the states
X_k1..X_kd at the Radau IIA points (unknowns of the NLP, stage k),

    sum_r C[r, j] X_kr = h f(X_kj, u_k)  (j = 1..d),   x_{k+1} = X_kd,

of order 2d - 1 at the nodes.
"""

from dataclasses import dataclass

import numpy as np

from ..core import model
from .base import N_MAX, Setting, SizeLimit, Transcription


def radau_matrices(degree):
    """C (d+1 x d+1): C[r, j] = l_r'(tau_j) for the Lagrange basis on (0, tau_1..tau_d), the
    Radau IIA points of `degree`."""
    import casadi as ca

    tau = np.concatenate([[0.0], ca.collocation_points(degree, "radau")])
    C = np.zeros((degree + 1, degree + 1))
    for r in range(degree + 1):
        basis = np.poly1d([1.0])
        for m in range(degree + 1):
            if m != r:
                basis *= np.poly1d([1.0, -tau[m]]) / (tau[r] - tau[m])
        C[r] = np.polyder(basis)(tau)
    return C


#: the largest NLP accepted, in N*degree^2 (an interval's collocation equations have about degree^2
#: terms; its build time grows so), measured by benchmarks/direct_size.py: N = 5000 at degree 3
SIZE_LIMIT = SizeLimit(45000, "N*degree^2", "about 0.35 GB, 45 s to build and 11 s per start")


@dataclass(frozen=True)
class DirectCollocation(Transcription):
    """N intervals, each with Radau collocation of `degree` (order 2*degree - 1 at the nodes)."""

    N: int = 100
    degree: int = 3

    name = "direct-collocation"
    SETTINGS = (
        Setting("N", int, 100, "intervals", 2, N_MAX),
        Setting("degree", int, 3, "Radau points per interval", 1, 9),
    )

    def __post_init__(self):
        self.check_settings()

    @property
    def extra(self):
        """Collocation states per stage: 2 per Radau point."""
        return 2 * self.degree

    def prepare(self):
        return radau_matrices(self.degree)

    def extra_guess(self, theta, omega):
        """Every Radau point's state at its interval's first node."""
        return np.tile(np.column_stack([theta[:-1], omega[:-1]]), self.degree)

    def size(self):
        return self.N * self.degree ** 2

    def size_limit(self):
        return SIZE_LIMIT

    def stage(self, x, u, h, kappa, extra, prepared):
        d, C = self.degree, prepared
        X = [x] + [extra[2 * j:2 * j + 2] for j in range(d)]
        constraints = [sum(C[r, j] * X[r] for r in range(d + 1)) - h * model.rhs(X[j], u, kappa) for j in range(1, d + 1)]
        return X[d], constraints

    def family(self):
        return f"DC radau{self.degree}"

    def describe(self):
        return f"direct collocation, N = {self.N}, Radau degree {self.degree}"
