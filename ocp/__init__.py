"""ocp: an optimal-control benchmark suite around the torque-limited pendulum
theta'' + sin(theta) = kappa*u, |u| <= 1 (see `ocp.core.model` for the convention).

    ocp.solve(ocp.swing_up(0.75))                     the minimum time, from the complete search
    ocp.solve(problem, ocp.MultipleShooting(N=200))   and a direct transcription classified against it
    ocp.score("answer.json")                          a solution from any tool against the reference set

Names are loaded on first use, so that `import ocp` (and `ocp --help`) stays light.
"""

import importlib

_EXPORTS = {
    "Problem": "ocp.core.problem", "swing_up": "ocp.core.problem", "damping": "ocp.core.problem",
    "MultipleShooting": "ocp.direct", "DirectCollocation": "ocp.direct", "Guess": "ocp.direct",
    "solve": "ocp.solving", "score": "ocp.reference.score", "Solution": "ocp.result", "SolveStatus": "ocp.result", "DirectClass": "ocp.result",
}
__all__ = list(_EXPORTS)


def __getattr__(name):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'ocp' has no attribute {name!r}")
    value = getattr(importlib.import_module(_EXPORTS[name]), name)
    globals()[name] = value
    return value
