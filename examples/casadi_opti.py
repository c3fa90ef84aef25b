"""Minimum-time swing-up of the torque-limited pendulum, theta'' + sin(theta) = kappa u, |u| <= 1,
from (0, 0) to (pi, 0), with CasADi's Opti as a textbook writes it: multiple shooting, N intervals of
M classical Runge-Kutta steps, free final time T, minimise T. The control is written as a sampled
control (CSV of t, u, piecewise constant) for `ocp score`.

    python examples/casadi_opti.py [OUT.csv]        then        ocp score OUT.csv
"""

import sys

import casadi as ca
import numpy as np

INSTANCE = "swing-up/plane-b0/k0.8111/x0=standard"      # a reference instance: theta(T) = pi pinned
kappa, N, M = 0.8111, 100, 4

opti = ca.Opti()
X = opti.variable(2, N + 1)          # (theta, omega) at the nodes
U = opti.variable(1, N)              # u on each interval
T = opti.variable()                  # the final time


def f(x, u):
    return ca.vertcat(x[1], kappa * u - ca.sin(x[0]))


h = T / (N * M)
for k in range(N):
    x = X[:, k]
    for _ in range(M):
        k1 = f(x, U[k])
        k2 = f(x + h / 2 * k1, U[k])
        k3 = f(x + h / 2 * k2, U[k])
        k4 = f(x + h * k3, U[k])
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    opti.subject_to(X[:, k + 1] == x)
opti.subject_to(opti.bounded(-1, U, 1))
opti.subject_to(X[:, 0] == ca.vertcat(0, 0))
opti.subject_to(X[:, N] == ca.vertcat(np.pi, 0))
opti.subject_to(T >= 0.1)
opti.minimize(T)

opti.set_initial(T, 6.0)
opti.set_initial(X[0, :], np.linspace(0, np.pi, N + 1))
opti.set_initial(U, np.sign(np.sin(np.linspace(0, 3 * np.pi, N))))
opti.solver("ipopt", {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes", "ipopt.tol": 1e-12})
sol = opti.solve()

T_opt, u = float(sol.value(T)), np.atleast_1d(sol.value(U))
out = sys.argv[1] if len(sys.argv) > 1 else "casadi-opti.csv"
with open(out, "w") as file:
    file.write(f"# instance: {INSTANCE}\n# interpolation: constant\n# tool: CasADi Opti, multiple shooting RK4 "
               f"N = {N}, M = {M}, IPOPT\nt,u\n")
    for t, value in zip(np.linspace(0, T_opt, N + 1), np.append(u, u[-1])):
        file.write(f"{float(t)!r},{float(value)!r}\n")
print(f"T = {T_opt!r}; written {out}")
