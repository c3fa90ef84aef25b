"""The one formatter: a printed value's stated error covers its distance from the computed value
plus the rounding of the print, and an error is never rounded down."""

import math

import numpy as np
import pytest

from ocp.core.numbers import digits, order, plus_minus, printed_error


def test_examples_of_the_module():
    assert digits(4.030018687989752, 4e-14) == "4.03001868798975"
    assert plus_minus(1.8812, 0.04) == "1.88 +- 0.05"
    assert order(4.5e-14) == "5e-14" and order(2.1e-11) == "3e-11" and order(9.99e-3) == "1e-02"
    assert digits(5.8397, math.nan) == "5.8397 (accuracy unknown)"


@pytest.mark.parametrize("seed", range(5))
def test_the_printed_error_covers_the_printed_value(seed):
    """For random values and errors: |printed - true| <= printed error, whenever |computed - true|
    <= error (the true value at either end of the error interval, the worst case)."""
    rng = np.random.default_rng(seed)
    for value, error in zip(rng.uniform(-50, 50, 200), 10.0 ** rng.uniform(-14, 0, 200)):
        for true in (value - error, value + error):
            shown = float(digits(value, error))
            assert abs(shown - true) <= printed_error(value, error) * (1 + 1e-9) + 1e-15 * abs(value)
            text, bound = plus_minus(value, error).split(" +- ")
            assert abs(float(text) - true) <= float(bound) * (1 + 1e-9) + 1e-15 * abs(value)
            assert float(order(printed_error(value, error))) >= printed_error(value, error) * (1 - 1e-12)
