"""Root finding and minimisation on an interval, without importing scipy (the hot paths of the suite
stay light: importing scipy.optimize costs more than a whole solve)."""

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


def minimum(f, a, b, xtol, below=None):
    """(x, f(x)) at a minimum of f on [a, b], x to xtol + sqrt(eps) |x|: Brent's bounded
    minimisation (golden sections and parabolic steps; Brent 1973, procedure localmin, as
    Forsythe, Malcolm and Moler's fmin), operation for operation scipy's
    `minimize_scalar(method="bounded")` (scipy 1.17, `_minimize_scalar_bounded`, maxiter 500), so
    that its answer is bit-identical to scipy's. With `below`: the first point it evaluates where
    f < below, as soon as there is one (else the minimum)."""
    sqrt_eps, golden_mean = math.sqrt(2.2e-16), 0.5 * (3.0 - math.sqrt(5.0))
    fulc = a + golden_mean * (b - a)
    nfc = xf = fulc
    rat = e = 0.0
    fx = ffulc = fnfc = f(xf)
    if below is not None and fx < below:
        return xf, fx
    xm = 0.5 * (a + b)
    tol1 = sqrt_eps * abs(xf) + xtol / 3.0
    tol2 = 2.0 * tol1
    for _ in range(499):
        if not abs(xf - xm) > tol2 - 0.5 * (b - a):
            break
        golden = True
        if abs(e) > tol1:
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r, e = e, rat
            if abs(p) < abs(0.5 * q * r) and q * (a - xf) < p < q * (b - xf):
                rat = (p + 0.0) / q
                x = xf + rat
                if x - a < tol2 or b - x < tol2:
                    rat = tol1 * (_sign(xm - xf) + (xm - xf == 0))
            else:
                golden = True
        if golden:
            e = a - xf if xf >= xm else b - xf
            rat = golden_mean * e
        x = xf + (_sign(rat) + (rat == 0)) * max(abs(rat), tol1)
        fu = f(x)
        if below is not None and fu < below:
            return x, fu
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc, nfc, fnfc, xf, fx = nfc, fnfc, xf, fx, x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if fu <= fnfc or nfc == xf:
                fulc, ffulc, nfc, fnfc = nfc, fnfc, x, fu
            elif fu <= ffulc or fulc == xf or fulc == nfc:
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = sqrt_eps * abs(xf) + xtol / 3.0
        tol2 = 2.0 * tol1
    return xf, fx


def _sign(v):
    return 1.0 if v > 0 else (-1.0 if v < 0 else 0.0)
