"""Root finding on an interval, without importing scipy (the hot paths of the suite stay light)."""

import math


def brent(f, a, b, xtol=0.0, fa=None, fb=None):
    """A root of f in [a, b] (f(a), f(b) of opposite signs; pass them as fa, fb when known), to
    xtol + 4 eps |root|, by Brent's method (R. P. Brent, Algorithms for Minimization without
    Derivatives, 1973, procedure zero)."""
    fa = f(a) if fa is None else fa
    fb = f(b) if fb is None else fb
    if fa * fb > 0:
        raise ValueError(f"no sign change of f between {a!r} and {b!r}")
    c, fc = a, fa
    d = e = b - a
    for _ in range(200):
        if fb * fc > 0:
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 2 * 2.2e-16 * abs(b) + 0.5 * xtol
        half = 0.5 * (c - b)
        if abs(half) <= tol or fb == 0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:
                p, q = 2 * half * s, 1 - s
            else:
                q, r = fa / fc, fb / fc
                p = s * (2 * half * q * (q - r) - (b - a) * (r - 1))
                q = (q - 1) * (r - 1) * (s - 1)
            if p > 0:
                q = -q
            p = abs(p)
            if 2 * p < min(3 * half * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = half
        else:
            d = e = half
        a, fa = b, fb
        b += d if abs(d) > tol else math.copysign(tol, half)
        fb = f(b)
    return b
