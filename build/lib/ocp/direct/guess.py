"""Initial guesses of a direct transcription, on normalised time s = t/T in [0, 1]."""

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Guess:
    """An initial guess on normalised time s in [0, 1]: T, and theta, omega at the nodes `s`, u on
    the intervals (len(s) - 1 values). It is resampled to the transcription's grid (linear
    interpolation of the states, the control taken at interval midpoints)."""

    T: float
    s: tuple
    theta: tuple
    omega: tuple
    u: tuple
    label: str = "user"

    @classmethod
    def from_solution(cls, sol, label="warm start"):
        """The grid of a direct solution (an `ocp.direct.DirectSolution`)."""
        return cls(sol.T, tuple(sol.t / sol.T), tuple(sol.x[:, 0]), tuple(sol.x[:, 1]), tuple(sol.u), label)

    def on_grid(self, N):
        s = np.linspace(0.0, 1.0, N + 1)
        src = np.asarray(self.s, float)
        mid = 0.5 * (src[:-1] + src[1:])
        return (np.interp(s, src, self.theta), np.interp(s, src, self.omega),
                np.interp(0.5 * (s[:-1] + s[1:]), mid, self.u))


def default_guesses(problem, N=100):
    """Three guesses with u = 0: braking from x0 to rest at `problem.stop_angle` (theta'' =
    -kappa*sign(omega0), for t_b = |omega0|/kappa), then theta = stop + d*sigma + b*sin(pi*sigma),
    sigma from 0 to 1, d = target - stop (branch `problem.guess_branch`), for a detour b = 0, -1,
    +1 rad (straight at the target, or first swinging the other way: a backswing), arriving at
    `problem.time_estimate`."""
    theta0, omega0 = problem.x0
    kappa, stop = problem.kappa, problem.stop_angle
    d = problem.target(problem.guess_branch)[0] - stop
    t_brake = abs(omega0) / kappa
    T = max(problem.time_estimate, 1.01 * t_brake + 1e-6)
    s = np.linspace(0.0, 1.0, N + 1)
    t = s * T
    braking = theta0 + omega0 * t - math.copysign(kappa, omega0) * t * t / 2
    sigma = np.clip((t - t_brake) / (T - t_brake), 0.0, 1.0)
    direction = math.copysign(1.0, d) if d else 1.0
    guesses = []
    for b, name in ((0.0, "straight"), (-1.0, "backswing"), (1.0, "overswing")):
        theta = np.where(t < t_brake, braking, stop + d * sigma + direction * b * np.sin(math.pi * sigma))
        omega = np.gradient(theta, s) / T
        omega[0] = omega0
        guesses.append(Guess(T, tuple(s), tuple(theta), tuple(omega), (0.0,) * N, name))
    return guesses


def random_guess(problem, seed, N):
    """A seeded random Guess: ocp's straight guess with T scaled by a factor in [1/2, 2], theta
    displaced by three sine modes of amplitude up to 2 rad, and u uniform in [-1, 1]."""
    rng = np.random.default_rng(seed)
    base = default_guesses(problem, N)[0]
    s = np.asarray(base.s)
    T = base.T * math.exp(rng.uniform(-math.log(2), math.log(2)))
    theta = np.asarray(base.theta) + sum(rng.uniform(-2, 2) * np.sin(j * math.pi * s) for j in (1, 2, 3))
    omega = np.gradient(theta, s) / T
    omega[0] = problem.x0[1]
    return Guess(T, tuple(s), tuple(theta), tuple(omega), tuple(rng.uniform(-1, 1, N)), f"random (seed {seed})")
