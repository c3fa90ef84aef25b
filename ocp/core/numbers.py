"""Printing a number with no more digits than its error defends: the one formatter of the suite.

    digits(4.030018687989752, 4e-14)  -> "4.03001868798975"   (down to the error's leading digit)
    digits(5.8397, float("nan"))      -> "5.8397 (accuracy unknown)"
    plus_minus(1.8812, 0.04)          -> "1.88 +- 0.05"   (the error covers the value's rounding)
    order(4.5e-14)                    -> "5e-14"   (an error is rounded up, never down)

A printed value differs from the computed one by at most half a unit in its last place:
`printed_error` is the error of the printed digits (the error plus that rounding).
"""

import math


def decimals(error):
    """Decimals an absolute error defends: those down to its leading digit (0 for error >= 1)."""
    return max(0, -math.floor(math.log10(error))) if error > 0 else 16


def _digits_decimals(value, error):
    """The decimals `digits` prints: down to the error's leading digit, at most 16 significant digits."""
    magnitude = math.floor(math.log10(abs(value))) + 1 if value else 1
    return max(0, min(decimals(error), 16 - magnitude))


def digits(value, error):
    """`value` with the decimals its absolute `error` defends (at most 16 significant digits); an
    unknown (NaN or None) error prints 6 significant digits, marked."""
    if error is None or not math.isfinite(error):
        return f"{value:.6g} (accuracy unknown)"
    if error == 0 and float(value).is_integer():
        return str(int(value))
    return f"{value:.{_digits_decimals(value, error)}f}"


def printed_error(value, error):
    """The error of `digits(value, error)` as printed: `error` plus half a unit in its last place."""
    if error is None or not math.isfinite(error):
        return error
    if error == 0 and float(value).is_integer():
        return 0.0
    return error + 0.5 * 10.0 ** -_digits_decimals(value, error)


def plus_minus(value, error):
    """value +- error, the value to the decimal of the error's leading digit, the error there
    rounded up after adding the value's rounding (half a unit in that place)."""
    if error is None or not math.isfinite(error):
        return digits(value, error)
    places = decimals(error)
    unit = 10.0 ** -places
    covered = math.ceil(round((error + unit / 2) / unit, 9)) * unit
    return f"{value:.{places}f} +- {covered:.{places}f}" if places <= 4 else f"{value:.{places}f} +- {order(covered)}"


def order(error):
    """An error to one significant digit, rounded up (e.g. 2.1e-11 -> 3e-11); "unknown" for NaN or None."""
    if error is None or not math.isfinite(error):
        return "unknown"
    if error <= 0:
        return "0"
    exponent = math.floor(math.log10(error))
    mantissa = math.ceil(round(error / 10.0 ** exponent, 9))
    if mantissa == 10:
        mantissa, exponent = 1, exponent + 1
    return f"{mantissa}e{exponent:+03d}"
