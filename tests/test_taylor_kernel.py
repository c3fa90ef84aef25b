"""The compiled Taylor kernel (ocp/indirect/_taylor.c) against a plain-Python transliteration of its
algorithm (bit for bit: the same IEEE operations in the same order, libm's sin, cos, pow, exp and
hypot), and its variations against central differences of the extremal."""

import math

import numpy as np
import pytest

from ocp.indirect import _taylor, taylor


# ---- the plain-Python transliteration (the numba kernels the C code replaced, run as Python) ----

def _series(y, u, kappa, K):
    c = [[0.0] * 4 for _ in range(K + 1)]
    s, co = [0.0] * (K + 1), [0.0] * (K + 1)
    c[0] = [float(v) for v in y]
    s[0], co[0] = math.sin(y[0]), math.cos(y[0])
    for k in range(K):
        k1 = k + 1
        c[k1][0] = c[k][1] / k1
        c[k1][1] = ((kappa * u if k == 0 else 0.0) - s[k]) / k1
        acc = 0.0
        for j in range(k1):
            acc += c[j][3] * co[k - j]
        c[k1][2] = acc / k1
        c[k1][3] = -c[k][2] / k1
        ss = cc = 0.0
        for j in range(1, k1 + 1):
            jt = j * c[j][0]
            ss += jt * co[k1 - j]
            cc += jt * s[k1 - j]
        s[k1], co[k1] = ss / k1, -cc / k1
    return c


def _step(c, K, tol):
    h = 1e300
    for k in (K - 1, K):
        m = 0.0
        for i in range(4):
            m = max(m, abs(c[k][i]))
        if m > 0.0:
            h = min(h, (tol / m) ** (1.0 / k))
    return h * math.exp(-0.7 / (K - 1))


def _at(c, K, i, tau):
    v = c[K][i]
    for k in range(K - 1, -1, -1):
        v = v * tau + c[k][i]
    return v


def _slope(c, K, i, tau):
    v = K * c[K][i]
    for k in range(K - 1, 0, -1):
        v = v * tau + k * c[k][i]
    return v


def _clear(c, K, i, h):
    h, v = abs(h), abs(c[K][i])
    for k in range(K - 1, 0, -1):
        v = v * h + abs(c[k][i])
    return abs(c[0][i]) > v * h


def _zero(c, K, i, a, b):
    fa = _at(c, K, i, a)
    if fa == 0.0:
        return a
    x = 0.5 * (a + b)
    for _ in range(200):
        f = _at(c, K, i, x)
        if f == 0.0:
            return x
        if (f > 0.0) == (fa > 0.0):
            a, fa = x, f
        else:
            b = x
        d = _slope(c, K, i, x)
        xn = x - f / d if d != 0.0 else 0.5 * (a + b)
        if not (min(a, b) < xn < max(a, b)):
            xn = 0.5 * (a + b)
        if abs(xn - x) <= 2e-16 * max(1.0, abs(x)) or a == b:
            return xn
        x = xn
    return x


def _normalise(y):
    n = float(np.hypot(y[2], y[3]))             # libm's hypot (math.hypot is CPython's own)
    if n > 0.0:
        y[2] /= n
        y[3] /= n


def _extremal(y0, kappa, u_start, duration, direction, tol, K, n_switches, n_events, sample_t):
    y = [float(v) for v in y0]
    _normalise(y)
    u = u_start if y[3] == 0.0 else (1.0 if y[3] > 0.0 else -1.0)
    t, switches, events, samples, in_arc, steps = 0.0, [], [], [], 0, 0
    while t < duration:
        steps += 1
        c = _series(y, u, kappa, K)
        h = min(_step(c, K, tol), duration - t)
        stop, switched, before = direction * h, False, 0.0
        for q in range(1, 0 if _clear(c, K, 3, stop) else taylor.SUBSTEPS + 1):
            tq = stop * q / taylor.SUBSTEPS
            if u * _at(c, K, 3, tq) < 0.0:
                stop, switched = _zero(c, K, 3, before, tq), True
                break
            before = tq
        w0, before = c[0][1], 0.0
        for q in range(1, 0 if _clear(c, K, 1, stop) else taylor.SUBSTEPS + 1):
            tq = stop * q / taylor.SUBSTEPS
            w1 = _at(c, K, 1, tq)
            if (w0 > 0.0 and w1 <= 0.0) or (w0 < 0.0 and w1 >= 0.0):
                r = _zero(c, K, 1, before, tq) if w1 != 0.0 else tq
                events.append([t + abs(r), _at(c, K, 0, r), len(switches), in_arc, _at(c, K, 2, r), _at(c, K, 3, r)])
                in_arc += 1
            if w1 != 0.0:
                w0 = w1
            before = tq
        while len(samples) < len(sample_t) and sample_t[len(samples)] <= t + abs(stop):
            tau = direction * (sample_t[len(samples)] - t)
            samples.append([_at(c, K, 0, tau), _at(c, K, 1, tau), len(switches)])
        y = [_at(c, K, i, stop) for i in range(4)]
        t += abs(stop)
        if switched:
            y[3] = 0.0
            switches.append([t] + y)
            u, in_arc = -u, 0
        _normalise(y)
    return len(switches), len(events), y, u, steps, switches[:n_switches], events[:n_events], samples


def _bits(a):
    return np.asarray(a, dtype=float).view(np.int64).tolist()


CASES = [  # (y0, kappa, u_start, duration, direction, tol, K): short arcs at low orders, several switches
    ((0.0, 0.0, math.cos(1.0), math.sin(1.0)), 0.3, 1.0, 9.0, 1.0, 1e-9, 6),
    ((math.pi, 0.0, math.cos(2.4), math.sin(2.4)), 0.5, -1.0, 10.0, -1.0, 1e-10, 8),
    ((0.4, -1.2, 0.5, 3.0), 0.3, 1.0, 8.0, 1.0, 1e-6, 5),           # an unnormalised costate
    ((2.0, 0.5, 1.0, 0.0), 0.75, -1.0, 8.0, -1.0, 1e-12, 9),        # on the seam p2 = 0: u_start
    ((-0.3, 0.0, math.cos(5.5), math.sin(5.5)), 0.2, -1.0, 12.0, -1.0, 1e-9, 11),
]


@pytest.mark.parametrize("case", CASES)
def test_the_compiled_extremal_is_the_transliteration_bit_for_bit(case):
    """Counts, final y and u, steps, every switch, event and sample row, with arrays too short for
    the counts (the counts still complete, the rows written as far as the arrays reach)."""
    y0, kappa, u_start, duration, direction, tol, K = case
    sample_t = np.linspace(0.0, duration, 7)[1:]
    n_sw, n_ev, y, u, steps, switches, events, samples = _extremal(y0, kappa, u_start, duration, direction, tol, K,
                                                                    2, 3, sample_t)
    assert n_sw >= 2 and n_ev >= 2
    sw, ev, sa = np.full((2, 5), np.nan), np.full((3, 6), np.nan), np.full((6, 3), np.nan)
    got = taylor.extremal(np.array(y0), kappa, u_start, duration, direction, tol, K, sw, ev, sample_t, sa)
    assert (got[0], got[1], got[3], got[4]) == (n_sw, n_ev, u, steps)
    assert _bits(got[2]) == _bits(y)
    assert _bits(sw[:len(switches)]) == _bits(switches) and _bits(ev[:len(events)]) == _bits(events)
    assert _bits(sa) == _bits(samples)
    assert np.isnan(sw[len(switches):]).all() and np.isnan(ev[len(events):]).all()


def test_the_compiled_bang_and_series_are_the_transliteration_bit_for_bit():
    signs, durations, kappa, tol, K = [1.0, -1.0, 1.0], [0.7, 0.0, 1.9], 0.6, 1e-9, 7
    y = [0.2, -0.1, 0.0, 0.0]
    for sign, duration in zip(signs, durations):
        t = 0.0
        while t < duration:
            c = _series(y, sign, kappa, K)
            h = min(_step(c, K, tol), duration - t)
            y[:2] = [_at(c, K, i, h) for i in range(2)]
            t += h
    assert _bits(taylor.bang(np.array([0.2, -0.1]), np.array(signs), np.array(durations), kappa, tol, K)) == _bits(y[:2])
    c = np.empty((13, 4))
    taylor._series(np.array([0.3, -2.0, 0.6, -0.8]), -1.0, 1.3, 12, c)
    assert _bits(c) == _bits(_series([0.3, -2.0, 0.6, -0.8], -1.0, 1.3, 12))


def test_the_kernel_refuses_arrays_of_the_wrong_shape():
    y0, ok = np.array([0.0, 0.0, 1.0, 0.0]), np.empty((4, 5))
    with pytest.raises(ValueError, match="events"):
        taylor.extremal(y0, 1.0, 1.0, 1.0, 1.0, 1e-9, 11, ok, np.empty((4, 5)), np.empty(0), np.empty((0, 3)))
    with pytest.raises(ValueError, match="samples"):
        taylor.extremal(y0, 1.0, 1.0, 1.0, 1.0, 1e-9, 11, ok, np.empty((4, 6)), np.ones(2), np.empty((1, 3)))
    with pytest.raises(TypeError, match="switches"):
        taylor.extremal(y0, 1.0, 1.0, 1.0, 1.0, 1e-9, 11, ok[:, ::2], np.empty((4, 6)), np.empty(0), np.empty((0, 3)))
    with pytest.raises(ValueError, match="order"):
        taylor.extremal(y0, 1.0, 1.0, 1.0, 1.0, 1e-9, 1, ok, np.empty((4, 6)), np.empty(0), np.empty((0, 3)))


@pytest.mark.parametrize("bad, error, words", [
    (dict(y=np.zeros(4, dtype=np.float32)), ValueError, "y: a float64 array of shape \\(4,\\)"),
    (dict(y=np.zeros(8)[::2]), TypeError, "y: a C-contiguous writable float64"),
    (dict(y=np.zeros(3)), ValueError, "y: a float64 array of shape \\(4,\\)"),
    (dict(y=[0.0, 0.0, 1.0, 0.0]), TypeError, "y: a C-contiguous writable"),
    (dict(dy=np.zeros(4).reshape(2, 2)), ValueError, "dy: .* shape \\(4,\\)"),
    (dict(switches=np.empty((6, 4)).T), TypeError, "switches: a C-contiguous"),
    (dict(switches=np.empty((4, 5))), ValueError, "switches: .* shape \\(n, 8\\)"),
    (dict(events=np.empty((4, 8), dtype=np.int64)), ValueError, "events: a float64"),
    (dict(events=np.empty((4, 8)).copy(order="F")), TypeError, "events: a C-contiguous"),
    (dict(marked=np.empty(4)), ValueError, "marked: a float64 array of shape \\(8,\\)"),
    (dict(marked=np.empty(16)[::2]), TypeError, "marked: a C-contiguous"),
    (dict(y="read-only"), TypeError, "y: a C-contiguous writable"),
])
def test_the_variations_kernel_names_a_wrong_array(bad, error, words):
    """Every array of the C kernel checked (type, contiguity, writability, shape) before use: a clear
    exception naming it, the kernel never reached."""
    read_only = np.zeros(4)
    read_only.setflags(write=False)
    arrays = dict(y=np.zeros(4), dy=np.zeros(4), switches=np.empty((4, 8)), events=np.empty((4, 8)),
                  marked=np.empty(8))
    arrays.update({k: read_only if isinstance(v, str) else v for k, v in bad.items()})
    with pytest.raises(error, match=words):
        _taylor.extremal_variations(arrays["y"], arrays["dy"], 1.0, 1.0, 1.0, 1.0, 1e-9, 11, arrays["switches"],
                                    arrays["events"], 0.5, arrays["marked"])


# ---- the variations ----

START = {1.0: (0.0, 0.0), -1.0: (math.pi, 0.0)}      # forwards from rest below, backwards from the target


def _fresh(direction, phi):
    theta0, omega0 = START[direction]
    return np.array([theta0, omega0, math.cos(phi), math.sin(phi)]), np.array([0.0, 0.0, -math.sin(phi), math.cos(phi)])


@pytest.mark.parametrize("direction, phi, kappa, duration", [(1.0, 1.2, 0.3, 14.0), (1.0, 4.4, 0.3, 14.0),
                                                             (-1.0, 2.4, 0.5, 10.0), (-1.0, 5.7, 0.5, 10.0)])
def test_the_variations_are_the_derivatives_of_the_extremal_in_phi(direction, phi, kappa, duration):
    """dy, ds_s/dphi, dtheta_e/dphi and ds_e/dphi against central differences of `extremal` (step
    1e-6 at PRECISE accuracy: they agree to 1e-8 relative, 1e-9 in most components, the
    truncation ~ h^2 |y'''| and rounding ~ 1e-16 |y|/h), over arcs with several switches; y, switch and event rows bit-identical."""
    tol, K = taylor.PRECISE
    u0 = 1.0 if math.sin(phi) > 0 else -1.0

    def plain(p):
        sw, ev = np.empty((40, 5)), np.empty((40, 6))
        n_sw, n_ev, y, u, steps = taylor.extremal(_fresh(direction, p)[0], kappa, u0, duration, direction, tol, K, sw,
                                                  ev, np.empty(0), np.empty((0, 3)))
        return n_sw, n_ev, y, u, steps, sw[:n_sw], ev[:n_ev]

    y0, dy0 = _fresh(direction, phi)
    sw, ev = np.empty((40, 8)), np.empty((40, 8))
    n_sw, n_ev, y, dy, u, steps, marked = taylor.extremal_variations(y0, dy0, kappa, u0, duration, direction, tol, K, sw, ev)
    sw, ev = sw[:n_sw], ev[:n_ev]
    base = plain(phi)
    assert marked is None and n_sw >= 2 and n_ev >= 2
    assert (n_sw, n_ev, u, steps) == (base[0], base[1], base[3], base[4])
    assert _bits(y) == _bits(base[2]) and _bits(sw[:, :5]) == _bits(base[5]) and _bits(ev[:, :6]) == _bits(base[6])

    h = 1e-6
    hi, lo = plain(phi + h), plain(phi - h)
    assert hi[:2] == lo[:2] == (n_sw, n_ev)       # the same arcs on either side
    fd = lambda a, b: (a - b) / (2 * h)
    scale = lambda v: 1e-7 * np.maximum(1.0, np.abs(v))
    assert np.all(np.abs(dy - fd(hi[2], lo[2])) <= scale(dy))
    assert np.all(np.abs(sw[:, 5] - fd(hi[5][:, 0], lo[5][:, 0])) <= scale(sw[:, 5]))
    assert np.all(np.abs(ev[:, 6] - fd(hi[6][:, 1], lo[6][:, 1])) <= scale(ev[:, 6]))
    assert np.all(np.abs(ev[:, 7] - fd(hi[6][:, 0], lo[6][:, 0])) <= scale(ev[:, 7]))


@pytest.mark.parametrize("case", CASES)
def test_the_mark_is_the_dense_output_of_the_same_steps(case):
    """(y, dy) at the mark: the integration otherwise bit for bit the one without a mark, theta and
    omega there bit for bit `extremal`'s sample at that time (the same polynomial at the same tau),
    and theta, omega and their dy bit for bit those of the integration stopped at the mark (its
    last step, cut to end there, is the step containing the mark; p, dp differ by the stopped
    one's normalisation at its end)."""
    y0, kappa, u_start, duration, direction, tol, K = case
    phi = math.atan2(y0[3], y0[2])
    dy0 = np.array([0.0, 0.0, -math.sin(phi), math.cos(phi)])
    mark = 0.8 * duration

    def run(duration, mark=None):
        sw, ev = np.full((40, 8), np.nan), np.full((40, 8), np.nan)
        out = taylor.extremal_variations(np.array(y0), dy0, kappa, u_start, duration, direction, tol, K, sw, ev, mark)
        return out, sw, ev

    (plain, sw, ev), (marked, sw_m, ev_m) = run(duration), run(duration, mark)
    n_sw, n_ev, y, dy, u, steps, (y_m, dy_m) = marked
    assert (n_sw, n_ev, u, steps) == (plain[0], plain[1], plain[4], plain[5])
    assert _bits(y) == _bits(plain[2]) and _bits(dy) == _bits(plain[3])
    assert _bits(sw) == _bits(sw_m) and _bits(ev) == _bits(ev_m)
    sa = np.empty((1, 3))
    taylor.extremal(np.array(y0), kappa, u_start, duration, direction, tol, K, np.empty((40, 5)), np.empty((40, 6)),
                    np.array([mark]), sa)
    assert _bits(y_m[:2]) == _bits(sa[0, :2])
    (_, _, y_s, dy_s, _, _, _), _, _ = run(mark)
    assert _bits(y_m[:2]) == _bits(y_s[:2]) and _bits(dy_m[:2]) == _bits(dy_s[:2])
