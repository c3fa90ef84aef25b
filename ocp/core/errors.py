"""The two error types a user meets, and the checks of input values.

    InputError   bad input: the command line prints its one-line message and exits 2
    Fault        the environment failed (a folder not writable, a full disk, a corrupted file):
                 one line, exit 1, nothing already finished lost

A message says what was wrong and what is accepted.
"""

import math
import re

#: a number as the command line and the files accept it: ASCII digits, an optional sign, point and
#: exponent (float() alone also takes '1_000', non-ASCII digits and 'infinity')
NUMBER = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")
#: an integer: ASCII digits and an optional sign (str.isdigit() also passes '²', which int() refuses)
INTEGER = re.compile(r"[+-]?[0-9]{1,20}")
NOT_FINITE = re.compile(r"[+-]?(nan|inf|infinity)", re.IGNORECASE)


class InputError(ValueError):
    """Bad input from a user."""


class Fault(RuntimeError):
    """A fault of the environment, not of the input."""


def finite(name, value, accepted="a finite number", low=-math.inf, high=math.inf):
    """float(value), or InputError naming the argument and what it accepts (finite, in [low, high])."""
    if isinstance(value, bool):
        raise InputError(f"{name} = {value!r} is not a number; {name} accepts {accepted}")
    text = value.strip(" ") if isinstance(value, str) else None
    if text is not None and not (NUMBER.fullmatch(text) or NOT_FINITE.fullmatch(text)):
        raise InputError(f"{name} = {short(value)} is not a number; {name} accepts {accepted}")
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} = {short(value)} is not a number; {name} accepts {accepted}") from None
    if not math.isfinite(number):
        raise InputError(f"{name} = {short(value)} is not finite; {name} accepts {accepted}")
    if not low <= number <= high:
        raise InputError(f"{name} = {short(value)} is out of range; {name} accepts {accepted}")
    return number


def integer(name, value, accepted, low, high):
    """int(value) for an integer in [low, high] (text of ASCII digits with an optional sign, an int,
    or an integral float), or InputError."""
    if isinstance(value, bool):
        raise InputError(f"{name} = {value!r} is not an integer; {name} accepts {accepted}")
    if isinstance(value, str):
        text = value.strip(" ")
        if not INTEGER.fullmatch(text):
            raise InputError(f"{name} = {short(value)} is not an integer; {name} accepts {accepted}")
        number = int(text)
    elif isinstance(value, int):
        number = value
    elif isinstance(value, float) and value.is_integer():
        number = int(value)
    else:
        raise InputError(f"{name} = {short(value)} is not an integer; {name} accepts {accepted}")
    if not low <= number <= high:
        raise InputError(f"{name} = {short(value)} is out of range; {name} accepts {accepted}")
    return number


def short(value):
    """repr(value), cut to 40 characters."""
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def last_line(err):
    """The last non-empty line of an exception's message (CasADi puts the cause there)."""
    lines = [line.strip() for line in str(err).splitlines() if line.strip()]
    return lines[-1] if lines else type(err).__name__
