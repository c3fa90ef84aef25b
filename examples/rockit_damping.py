"""Minimum-time damping of the torque-limited pendulum, theta'' + sin(theta) = kappa u, |u| <= 1,
from the upright at rest (pi, 0) to hanging at rest (0, 0), with rockit (`pip install rockit-meco`):
free final time, multiple shooting with Runge-Kutta steps, IPOPT. The control on rockit's grid is
written as a sampled control (CSV of t, u, piecewise constant) for `ocp score`.

    python examples/rockit_damping.py [OUT.csv]        then        ocp score OUT.csv
"""

import sys

import casadi as ca
import numpy as np
import rockit

INSTANCE = "damping/plane-b0/k0.5337/x0=standard"       # a reference instance: theta(T) = 0 pinned
kappa, N, M = 0.5337, 80, 4

oc = rockit.Ocp(T=rockit.FreeTime(7.0))
theta, omega, u = oc.state(), oc.state(), oc.control()
oc.set_der(theta, omega)
oc.set_der(omega, kappa * u - ca.sin(theta))
oc.subject_to(-1 <= (u <= 1))
oc.subject_to(oc.at_t0(theta) == np.pi)
oc.subject_to(oc.at_t0(omega) == 0)
oc.subject_to(oc.at_tf(theta) == 0)
oc.subject_to(oc.at_tf(omega) == 0)
oc.set_initial(theta, np.pi * (1 - oc.t / 7.0))
oc.set_initial(omega, -np.pi / 7.0)
oc.subject_to(oc.T >= 0.1)
oc.add_objective(oc.T)
oc.method(rockit.MultipleShooting(N=N, M=M, intg="rk"))
oc.solver("ipopt", {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes"})
sol = oc.solve()

t, values = sol.sample(u, grid="control")
out = sys.argv[1] if len(sys.argv) > 1 else "rockit.csv"
with open(out, "w") as file:
    file.write(f"# instance: {INSTANCE}\n# interpolation: constant\n# tool: rockit MultipleShooting "
               f"N = {N}, M = {M}, rk, IPOPT\nt,u\n")
    for a, b in zip(t, values):
        file.write(f"{float(a)!r},{float(b)!r}\n")
print(f"T = {float(t[-1])!r}; written {out}")
