"""Weinstein and Tam, the vertically driven inverted pendulum: every printed value of
`data/weinstein_tam.toml`, computed by `ocp.scenes.kapitza`."""

import math

import numpy as np
from scipy.integrate import quad

from ..scenes.kapitza import A, critical_frequencies, examples_table, kapitza_frequency, simulate, tam_frequency
from .verify import Reproduction


def reproduce():
    """The papers' printed claims, computed (keys of data/weinstein_tam.toml)."""
    mean, error = quad(math.cos, 0.0, 2 * math.pi, epsabs=1e-12)
    out = {"cos_average": Reproduction(mean / (2 * math.pi), error / (2 * math.pi) + 1e-16,
                                       "(1/2pi) int_0^2pi cos(tau) dtau by adaptive Gauss-Kronrod (scipy quad), "
                                       "with its error estimate", evidence=(
        "the mean of cos over a period is 0 exactly; 1/sqrt(2) is its root mean square (Tam's own "
        "premise, mean of cos^2 = 1/2). The exact Floquet boundary (the stabilisation is of second "
        f"order in A/l) puts the device's critical frequency at {critical_frequencies(A)[0]:.1f} rad/s, "
        f"not Tam's {tam_frequency(A):.1f} rad/s"))}
    lower = critical_frequencies(A)[0]
    for row in examples_table():
        key = f"{row['figure']}_stable_{row['reading']}"
        how = (f"Floquet: w = {row['omega']:.4g} rad/s, 2 - |tr M| = {row['margin']:.3e}, "
               f"max |mu| = {row['max_abs_mu']:.6g}")
        evidence = ""
        if row["floquet"] < 0 and row["figure"] == "fig4":
            t, theta = simulate(A, row["omega"])
            evidence = (f"max |mu| = {row['max_abs_mu']:.4f} > 1 per drive period: w = {row['omega']:.1f} rad/s "
                        f"is below the exact lower boundary {lower:.1f} rad/s (Kapitza {kapitza_frequency(A):.1f}); "
                        f"the simulation of Tam (20) from 0.1 rad passes pi/2 at t = {t[np.argmax(np.abs(theta) > math.pi / 2)]:.2f} s")
        out[key] = Reproduction(float(row["floquet"]), 0.0, how, evidence)
    return out
