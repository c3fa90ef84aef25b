"""ocp: an optimal-control benchmark suite around the torque-limited pendulum
theta'' + sin(theta) = kappa*u, |u| <= 1 (see `ocp.model` for the convention)."""

from .problems import Problem, swing_up, damping
from .transcription import DirectCollocation, MultipleShooting
from .direct import Guess
from .pipeline import solve

__all__ = ["Problem", "swing_up", "damping", "MultipleShooting", "DirectCollocation", "solve", "Guess"]
