"""Angle ticks at multiples of pi, labelled as fractions of pi (0, π/8, −π/2, 3π/2, 2π)."""

import math
from fractions import Fraction


def pi_label(multiple):
    """The tick label of `multiple`*pi (a Fraction)."""
    if multiple == 0:
        return "0"
    n, d = abs(multiple.numerator), multiple.denominator
    return ("−" if multiple < 0 else "") + (str(n) if n != 1 else "") + "π" + (f"/{d}" if d != 1 else "")


def pi_ticks(axis, lo, hi, step=Fraction(1, 2)):
    """Ticks of `axis` (ax.xaxis or ax.yaxis) at the multiples of step*pi in [lo, hi]."""
    unit = float(step) * math.pi
    ks = range(math.ceil(lo / unit - 1e-9), math.floor(hi / unit + 1e-9) + 1)
    axis.set_ticks([k * unit for k in ks], [pi_label(k * step) for k in ks])
