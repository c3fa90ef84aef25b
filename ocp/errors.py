"""The one error type for bad input: its message says what was wrong and what is accepted."""


class InputError(ValueError):
    """Bad input from a user: the command line prints its message on one line and exits 2."""


def finite(name, value, accepted="a finite number"):
    """Return float(value), or raise InputError naming the argument and what it accepts."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r} is not a number; {name} accepts {accepted}") from None
    if number != number or number in (float("inf"), float("-inf")):
        raise InputError(f"{name} = {value!r} is not finite; {name} accepts {accepted}")
    return number


def last_line(err):
    """The last non-empty line of an exception's message (CasADi puts the cause there)."""
    lines = [line.strip() for line in str(err).splitlines() if line.strip()]
    return lines[-1] if lines else type(err).__name__
