"""Minimum-time swing-up of the torque-limited pendulum, theta'' + sin(theta) = kappa u, |u| <= 1,
with scipy alone, as a user who knows the answer is bang-bang would write it: guess the arc signs,
optimise the arc durations (SLSQP) for the least T = d_1 + ... + d_n with the final state on the
target, the arcs integrated by solve_ivp. Each structure tried is written as a bang-bang answer
(JSON) for `ocp score`: a local method lands on whichever extremal its structure and start lead to.

    python examples/scipy_switching_times.py [FOLDER]        then        ocp score FOLDER/scipy-*.json
"""

import json
import sys
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize

INSTANCE = "swing-up/circle/k0.7702/x0=standard"       # a reference instance: any upright branch counts
kappa, x0 = 0.7702, (0.0, 0.0)
STRUCTURES = {"two-arcs": ([1, -1], [3.0, 2.5], np.pi), "three-arcs": ([-1, 1, -1], [1.0, 3.5, 1.5], np.pi)}


def end_state(durations, signs):
    x = np.array(x0)
    for u, d in zip(signs, durations):
        x = solve_ivp(lambda t, y: [y[1], kappa * u - np.sin(y[0])], (0, d), x, method="DOP853",
                      rtol=1e-10, atol=1e-10).y[:, -1]
    return x


folder = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
folder.mkdir(parents=True, exist_ok=True)
for name, (signs, guess, target) in STRUCTURES.items():
    result = minimize(np.sum, guess, method="SLSQP", bounds=[(1e-3, 10.0)] * len(signs),
                      constraints={"type": "eq", "fun": lambda d: end_state(d, signs) - [target, 0.0]},
                      options={"ftol": 1e-12, "maxiter": 100})
    d = result.x
    answer = {"instance": INSTANCE, "arc_signs": signs, "switch_times": np.cumsum(d)[:-1].tolist(),
              "T": float(np.sum(d)), "tool": f"scipy SLSQP over the arc durations ({result.message})"}
    path = folder / f"scipy-{name}.json"
    path.write_text(json.dumps(answer, indent=1) + "\n")
    print(f"{name}: T = {answer['T']!r}; written {path}")
