"""taylor.extremal_variations: the extremal of `extremal` bit for bit, and its derivatives in the
costate angle phi of the start (the variational equations, their jumps at switches, the derivatives
of the switch and turning-point times and angles) against central finite differences of
`extremal` in phi, extrapolated (Richardson: (4 D(H) - D(2H)) / 3, truncation O(H^4), rounding
O(eps / H), both below TOL relative to the derivatives, which grow to 1e3 over the longer arcs)."""

import math

import numpy as np
import pytest

from ocp.indirect import taylor

H = 1e-6
TOL = 1e-7


def start(x0, phi):
    return (np.array([x0[0], x0[1], math.cos(phi), math.sin(phi)]),
            np.array([0.0, 0.0, -math.sin(phi), math.cos(phi)]))


def plain(x0, kappa, phi, duration, direction):
    switches, events = np.empty((64, 5)), np.empty((256, 6))
    n_sw, n_ev, y, u, steps = taylor.extremal(start(x0, phi)[0], kappa, 1.0, duration, direction, *taylor.PRECISE,
                                              switches, events, np.empty(0), np.empty((0, 3)))
    return switches[:n_sw].copy(), events[:n_ev].copy(), y, u, steps


def varied(x0, kappa, phi, duration, direction):
    switches, events = np.empty((64, 8)), np.empty((256, 8))
    n_sw, n_ev, y, dy, u, steps, _ = taylor.extremal_variations(*start(x0, phi), kappa, 1.0, duration, direction,
                                                             *taylor.PRECISE, switches, events)
    return switches[:n_sw].copy(), events[:n_ev].copy(), y, dy, u, steps


# (x0, kappa, phi, duration, direction): several switches each, forwards and backwards in time
CASES = [((0.0, 0.0), 0.3, 1.0, 25.0, 1.0), ((0.0, 0.0), 0.75, 1.19, 20.0, 1.0), ((2.5, -0.3), 0.5, 2.3, 15.0, 1.0),
         ((math.pi, 0.0), 0.4, 2.45, 20.0, -1.0), ((0.0, 2.0), 0.5, 0.73, 25.0, -1.0), ((-3.0, 1.5), 0.3, 1.19, 30.0, -1.0)]


@pytest.mark.parametrize("x0, kappa, phi, duration, direction", CASES)
def test_the_extremal_is_that_of_extremal_bit_for_bit(x0, kappa, phi, duration, direction):
    sw, ev, y, u, steps = plain(x0, kappa, phi, duration, direction)
    vsw, vev, vy, _, vu, vsteps = varied(x0, kappa, phi, duration, direction)
    assert np.array_equal(sw, vsw[:, :5]) and np.array_equal(ev, vev[:, :6])
    assert np.array_equal(y, vy) and u == vu and steps == vsteps


@pytest.mark.parametrize("x0, kappa, phi, duration, direction", CASES)
def test_the_derivatives_are_central_differences_of_extremal(x0, kappa, phi, duration, direction):
    sw, ev, y, dy, _, _ = varied(x0, kappa, phi, duration, direction)
    runs = {h: plain(x0, kappa, phi + h, duration, direction) for h in (-2 * H, -H, H, 2 * H)}
    assert len(sw) >= 3 and len(ev) >= 3, "too few switches and turning points to test the jumps"
    assert all(len(r[0]) == len(sw) and len(r[1]) == len(ev) for r in runs.values())

    def derivative(part, column):
        d = {h: (runs[h][part] - runs[-h][part]) / (2 * h) for h in (H, 2 * H)}
        return ((4 * d[H] - d[2 * H]) / 3) if column is None else ((4 * d[H] - d[2 * H]) / 3)[:, column]

    # switches: the elapsed time; turning points: the elapsed time and the angle
    assert sw[:, 5] == pytest.approx(derivative(0, 0), rel=TOL, abs=TOL)
    assert ev[:, 7] == pytest.approx(derivative(1, 0), rel=TOL, abs=TOL)
    assert ev[:, 6] == pytest.approx(derivative(1, 1), rel=TOL, abs=TOL)
    # the state at each switch, d/dphi x(s(phi)) = dx(s+) + direction f(x, u_new) ds/dphi: the state's
    # variation just after the switch (columns 6, 7) and the switch's elapsed time (column 5)
    u_new = np.sign(math.sin(phi)) * (-1.0) ** np.arange(1, len(sw) + 1)
    theta, omega, ds = sw[:, 1], sw[:, 2], direction * sw[:, 5]
    assert sw[:, 6] + omega * ds == pytest.approx(derivative(0, 1), rel=TOL, abs=TOL)
    assert sw[:, 7] + (kappa * u_new - np.sin(theta)) * ds == pytest.approx(derivative(0, 2), rel=TOL, abs=TOL)
    # the final state and the normalised costate at the fixed final time
    assert dy == pytest.approx(derivative(2, None), rel=TOL, abs=TOL)
