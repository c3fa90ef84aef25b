"""The multi-precision refinement of a bang-bang extremal, independent of the search's integrator.

The shooting equations of an extremal with arc signs s_1..s_n (n >= 2) from x0 to (theta*, 0):

    unknowns   z = (phi, d_1, ..., d_n)    the costate angle, p(0) = (cos phi, sin phi), and the arc
                                           durations
    equations  p2(t_j) = 0, j = 1..n-1     at each switch t_j = d_1 + ... + d_j
               theta(T) - theta* = 0, omega(T) = 0,   T = d_1 + ... + d_n

p(0) is found up to its scale, which H = 0 fixes afterwards: p(0) = (cos phi, sin phi) / (p . f(x0, u0)).
The state and costate, theta' = omega, omega' = kappa u - sin(theta), p1' = p2 cos(theta), p2' = -p1,
are integrated arc by arc by a Taylor series of fixed order K (about the number of digits) in
fixed-point integer arithmetic (Python integers scaled by 2^B, B = digits * log2(10) + GUARD bits),
the step h = min_{k = K-1, K} (tol / |y_k|)^(1/k) exp(-0.7 / (K - 1)) from the last coefficients
(Jorba and Zou 2005), the last step of an arc cut to end on it; sin and cos of theta at each step's
start by mpmath. Newton's method (the chord variant: one Jacobian, by forward differences of step
2^(-B/2), restarted at the arc a duration changes) from the double-precision answer converges to the
working precision in two or three iterations.

`refine` solves at DIGITS and at CHECK_DIGITS (another precision, order and step): the two differ by
more than the error of the less precise one, so their difference bounds the error of the more precise,
floored at 10^-DIGITS relative. Nothing is shared with `ocp.indirect.taylor` (compiled, floating point)
but the equations.
"""

import math
from dataclasses import dataclass

import mpmath

#: the two precisions (decimal digits) of the refinement: the answer at CHECK_DIGITS, its error from
#: the difference to the one at DIGITS
DIGITS = 32
CHECK_DIGITS = 40
#: guard bits of the fixed-point arithmetic beyond the digits asked for
GUARD = 24
#: Newton iterations allowed after the Jacobian
ITERATIONS = 8


class NotConverged(ArithmeticError):
    """Newton's method did not reach the working precision."""


@dataclass(frozen=True)
class Precision:
    """Decimal `digits`, fixed-point `bits`, Taylor `order`, and the step tolerance 2^-(bits - GUARD)."""

    digits: int

    @property
    def bits(self):
        return math.ceil(self.digits * math.log2(10)) + GUARD

    @property
    def order(self):
        return self.digits + 4 + self.digits // 8

    @property
    def log2_tol(self):
        return -(self.bits - GUARD)


class _Arithmetic:
    """Fixed point at 2^-B: conversions to and from mpmath, and the Taylor flow of one arc."""

    def __init__(self, precision, kappa):
        self.p = precision
        self.B = precision.bits
        self.one = 1 << self.B
        self.K = precision.order
        self.kappa = self.fixed(kappa)
        self.steps = 0

    def fixed(self, x):
        with mpmath.workprec(self.B + 64):
            return int(mpmath.nint(mpmath.mpf(x) * self.one))

    def value(self, n):
        with mpmath.workprec(self.B + 64):
            return mpmath.mpf(n) / self.one

    def _sincos(self, theta):
        with mpmath.workprec(self.B + 32):
            t = mpmath.mpf(theta) / self.one
            return self.fixed(mpmath.sin(t)), self.fixed(mpmath.cos(t))

    def _series(self, y, u):
        """Taylor coefficients c[k] = (theta_k, omega_k, p1_k, p2_k), k = 0..K, at y under u."""
        B, K = self.B, self.K
        th, om, p1, p2 = [[v] for v in y]
        s, c = self._sincos(y[0])
        s, c = [s], [c]
        for k in range(K):
            k1 = k + 1
            th.append(om[k] // k1)
            om.append(((self.kappa * u if k == 0 else 0) - s[k]) // k1)
            p1.append((sum(p2[j] * c[k - j] for j in range(k1)) >> B) // k1)
            p2.append(-p1[k] // k1)
            jt = [j * th[j] for j in range(1, k1 + 1)]
            s.append((sum(jt[j - 1] * c[k1 - j] for j in range(1, k1 + 1)) >> B) // k1)
            c.append(-(sum(jt[j - 1] * s[k1 - j] for j in range(1, k1 + 1)) >> B) // k1)
        return th, om, p1, p2

    def _step(self, series):
        """The step h (a float) from the last two coefficients."""
        K, h = self.K, math.inf
        for k in (K - 1, K):
            m = max(abs(comp[k]) for comp in series)
            if m:
                log2_m = math.log2(m) - self.B
                h = min(h, 2.0 ** ((self.p.log2_tol - log2_m) / k))
        return h * math.exp(-0.7 / (K - 1))

    def arc(self, y, u, duration):
        """y = (theta, omega, p1, p2) after `duration` (fixed point) under constant u."""
        B = self.B
        left = duration
        y = list(y)
        while left > 0:
            series = self._series(y, u)
            h = min(left, self.fixed(self._step(series)))
            h = max(h, 1)
            for i, comp in enumerate(series):
                acc = comp[-1]
                for a in reversed(comp[:-1]):
                    acc = ((acc * h) >> B) + a
                y[i] = acc
            left -= h
            self.steps += 1
        return y


def _residuals(ar, x0, signs, target, z, starts=None, first=0):
    """The shooting equations at z = (phi, d_1..d_n) (fixed point), and the states at the start of every
    arc; with `starts` from an earlier call, the integration restarts at arc `first`."""
    n = len(signs)
    if starts is None:
        phi = ar.value(z[0])
        with mpmath.workprec(ar.B + 32):
            y = [ar.fixed(x0[0]), ar.fixed(x0[1]), ar.fixed(mpmath.cos(phi)), ar.fixed(mpmath.sin(phi))]
        starts, first = [y], 0
    starts = starts[:first + 1]
    y = starts[first]
    for i in range(first, n):
        y = ar.arc(y, signs[i], z[1 + i])
        starts.append(y)
    switch_p2 = [starts[j][3] for j in range(1, n)]
    end = starts[n]
    return switch_p2 + [end[0] - target, end[1]], starts


def _solve(precision, x0, kappa, signs, target, guess):
    """z = (phi, d_1..d_n) (mpmath numbers) solving the shooting equations at `precision`, and the states
    (theta, omega, p1, p2) at the arc ends, from `guess` (phi, durations)."""
    ar = _Arithmetic(precision, kappa)
    n = len(signs)
    z = [ar.fixed(v) for v in guess]
    theta_target = ar.fixed(target)
    F, starts = _residuals(ar, x0, signs, theta_target, z)
    step = 1 << (ar.B // 2)
    J = mpmath.matrix(n + 1, n + 1)
    for j in range(n + 1):
        zj = list(z)
        zj[j] += step
        Fj, _ = _residuals(ar, x0, signs, theta_target, zj) if j == 0 else \
            _residuals(ar, x0, signs, theta_target, zj, starts, j - 1)
        for i in range(n + 1):
            J[i, j] = mpmath.mpf(Fj[i] - F[i]) / step
    tol = 1 << (GUARD + 8)
    with mpmath.workprec(ar.B + 32):
        for _ in range(ITERATIONS):
            dz = mpmath.lu_solve(J, mpmath.matrix([mpmath.mpf(f) for f in F]))
            z = [zi - int(mpmath.nint(d)) for zi, d in zip(z, dz)]
            F, starts = _residuals(ar, x0, signs, theta_target, z)
            if max(abs(d) for d in dz) <= tol and max(abs(f) for f in F) <= tol:
                break
        else:
            raise NotConverged(f"Newton at {precision.digits} digits: residual 2^{math.log2(max(map(abs, F)) or 1) - ar.B:.0f} "
                               f"after {ITERATIONS} iterations")
    return [ar.value(v) for v in z], [[ar.value(v) for v in y] for y in starts], ar.steps


@dataclass(frozen=True)
class Refined:
    """An extremal at multi-precision: T, switch times, switch states (theta, omega), p(0) scaled by H = 0,
    and phi, each an mpmath number with its error bound (the difference of the two precisions, floored
    at 10^-DIGITS relative); the Taylor steps of the last solve."""

    T: object
    T_error: object
    switch_times: tuple
    switch_time_errors: tuple
    switch_states: tuple
    switch_state_errors: tuple
    p0: tuple
    p0_errors: tuple
    phi: object
    phi_error: object
    digits: tuple
    steps: int


def _floor(value, difference, digits):
    return max(abs(difference), mpmath.mpf(10) ** -digits * max(1, abs(value)))


def refine(x0, kappa, signs, target_over_pi, phi, durations):
    """The Refined extremal with arc `signs` from x0 to (target_over_pi * pi, 0) for bound kappa (x0 and
    kappa the decimals of their shortest representation, repr(float), taken exactly; the target an exact
    multiple of pi), from the double-precision costate angle `phi` and arc `durations`. NotConverged if
    Newton fails at either precision; ValueError for fewer than two arcs (a single arc has no costate)."""
    if len(signs) < 2:
        raise ValueError("the refinement needs at least one switch")
    exact = lambda v: mpmath.mpf(repr(float(v)))
    results = []
    for digits in (DIGITS, CHECK_DIGITS):
        mpmath.mp.prec = Precision(digits).bits + 32
        x0_mp, kappa_mp = [exact(x0[0]), exact(x0[1])], exact(kappa)
        z, starts, steps = _solve(Precision(digits), x0_mp, kappa_mp, tuple(int(s) for s in signs),
                                  int(target_over_pi) * mpmath.pi, [phi, *durations])
        phi_z, d = z[0], z[1:]
        times = [sum(d[:j + 1]) for j in range(len(d))]
        u0 = signs[0]
        scale = x0_mp[1] * mpmath.cos(phi_z) + (kappa_mp * u0 - mpmath.sin(x0_mp[0])) * mpmath.sin(phi_z)
        results.append(dict(T=times[-1], times=times[:-1], states=[(s[0], s[1]) for s in starts[1:-1]],
                            p0=(mpmath.cos(phi_z) / scale, mpmath.sin(phi_z) / scale), phi=phi_z, steps=steps))
    low, high = results
    D = DIGITS
    err = lambda a, b: _floor(b, b - a, D)
    return Refined(
        T=high["T"], T_error=err(low["T"], high["T"]),
        switch_times=tuple(high["times"]), switch_time_errors=tuple(err(a, b) for a, b in zip(low["times"], high["times"])),
        switch_states=tuple(high["states"]),
        switch_state_errors=tuple(tuple(err(a, b) for a, b in zip(sa, sb)) for sa, sb in zip(low["states"], high["states"])),
        p0=high["p0"], p0_errors=tuple(err(a, b) for a, b in zip(low["p0"], high["p0"])),
        phi=high["phi"], phi_error=err(low["phi"], high["phi"]), digits=(DIGITS, CHECK_DIGITS), steps=high["steps"])
