"""Batista and Peternelj (2006), Figure 1: the falling integral I(theta0) of the inverted pendulum
released at rest, and its asymptotic form (18), in the paper's convention (theta0 from the upright;
I is dimensionless, the falling time being sqrt(L/(2g)) I). Beside it, what the figure cannot show:
the relative error (I - (18))/I on logarithmic axes, with the paper's Table 2 values marked."""

import math
from fractions import Fraction

import matplotlib.pyplot as plt
import numpy as np

from ..papers import references
from ..scenes import falling
from .ticks import pi_ticks


def figure1(n=400):
    """`ocp.scenes.falling.figure1(n)` (theta0, I, asymptotic18 on (0, pi/2]), plus the relative
    error of (18) on a logarithmic grid over [1e-4, 1] (`small`, `relative_error`), and
    Table 2's printed relative errors at theta0 = pi/n (`table2_theta0`, `table2_relative_error`)."""
    data = falling.figure1(n)
    small = np.geomspace(1e-4, 1.0, n)
    exact = falling.falling_integral(small)
    data.update(small=small, relative_error=(exact - falling.asymptotic18(small)) / exact,
                table2_theta0=np.array([math.pi / k for k in falling.TABLE2]),
                table2_relative_error=np.array([references.value("batista2006", f"t2_relerr_pi{k}")
                                                for k in falling.TABLE2]))
    return data


def draw_figure1(data):
    fig, (left, right) = plt.subplots(1, 2, figsize=(9.6, 4.0))
    left.plot(data["theta0"], data["I"], color="black", label=r"$I(\theta_0)$, closed form (17)")
    left.plot(data["theta0"], data["asymptotic18"], color="#d62728", ls="--", label="asymptotic form (18)")
    left.set(xlim=(0, falling.GROUND), ylim=(0, 8), xlabel=r"$\theta_0$ (rad from the upright)",
             ylabel=r"$I(\theta_0)$ (dimensionless; $T = I\,\sqrt{L/2g}$)",
             title="Batista & Peternelj (2006) Fig. 1")
    pi_ticks(left.xaxis, 0, falling.GROUND, Fraction(1, 8))
    left.legend(loc="upper right")
    right.loglog(data["small"], np.abs(data["relative_error"]), color="black", label="|I − (18)| / I, computed")
    right.loglog(data["table2_theta0"], np.abs(data["table2_relative_error"]), "o", mfc="none", mec="#d62728",
                 label="Table 2, printed")
    right.set(xlabel=r"$\theta_0$ (rad from the upright)", ylabel="relative error of (18)",
              title="How good is (18)?")
    right.legend(loc="upper left")
    fig.tight_layout()
    return fig
