"""Printing a number with no more digits than its error defends: the one formatter of the suite.

    digits(4.030018687989752, 8e-15)  -> "4.03001868798975"
    digits(5.8397, float("nan"))      -> "5.8397 (accuracy unknown)"
    plus_minus(1.8812, 0.04)          -> "1.88 +- 0.04"
"""

import math


def decimals(error):
    """Decimals an absolute error defends: those down to its leading digit (0 for error >= 1)."""
    return max(0, math.floor(-math.log10(error))) if error > 0 else 16


def digits(value, error):
    """`value` with the decimals its absolute `error` defends (at most 16 significant digits); an
    unknown (NaN or None) error prints 6 significant digits, marked."""
    if error is None or not math.isfinite(error):
        return f"{value:.6g} (accuracy unknown)"
    if error == 0 and float(value).is_integer():
        return str(int(value))
    magnitude = math.floor(math.log10(abs(value))) + 1 if value else 1
    return f"{value:.{max(0, min(decimals(error), 16 - magnitude))}f}"


def plus_minus(value, error):
    """value +- error, the value to the decimal of the error's leading digit."""
    if error is None or not math.isfinite(error):
        return digits(value, error)
    return f"{value:.{decimals(error)}f} +- {error:.1g}"


def order(error):
    """An error as an order of magnitude, e.g. 3e-11; "unknown" for NaN or None."""
    return "unknown" if error is None or not math.isfinite(error) else f"{error:.0e}"
