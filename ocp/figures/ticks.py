"""Angle ticks at multiples of pi, labelled as fractions of pi (0, π/8, −π/2, 3π/2, 2π)."""

import math
from fractions import Fraction


def pi_label(multiple):
    """The tick label of `multiple`*pi (a Fraction)."""
    if multiple == 0:
        return "0"
    n, d = abs(multiple.numerator), multiple.denominator
    return ("−" if multiple < 0 else "") + (str(n) if n != 1 else "") + "π" + (f"/{d}" if d != 1 else "")


def pi_ticks(axis, lo, hi, step=None):
    """Ticks of `axis` (ax.xaxis or ax.yaxis) at the multiples of step*pi in [lo, hi]; by default
    the largest step among pi, pi/2, pi/4, pi/8, pi/16 that gives at least three ticks."""
    if step is None:
        step = next((s for s in (Fraction(1), Fraction(1, 2), Fraction(1, 4), Fraction(1, 8))
                     if (hi - lo) / (float(s) * math.pi) >= 3), Fraction(1, 16))
    unit = float(step) * math.pi
    ks = range(math.ceil(lo / unit - 1e-9), math.floor(hi / unit + 1e-9) + 1)
    axis.set_ticks([k * unit for k in ks], [pi_label(k * step) for k in ks])
