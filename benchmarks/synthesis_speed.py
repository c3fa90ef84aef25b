"""Speed of the synthesis maps against per-state solves, side by side in one run.

    python benchmarks/synthesis_speed.py [--states 50]

A map of about 10^5 states (401 x 250 cells) is drawn from the field of extremals (warm: the
compiled kernels loaded by a first, small map), for swing-up and damping on the circle; beside it,
`ocp.solve` (the complete search from one state) at `states` random cells of the same map, whose
median time gives the cost of the same map state by state. Ratios, not absolute times, are the
finding: the machine is shared.
"""

import argparse
import math
import platform
import statistics
import subprocess
import time

import numpy as np

from ocp.core.problem import make
from ocp.solving import solve
from ocp.synthesis.field import Window, interior_cells, synthesize

CASES = [("swing-up", "circle", 1.0, (-math.pi, math.pi, -3.0, 3.0), 10.0),
         ("swing-up", "circle", 0.5, (-math.pi, math.pi, -3.0, 3.0), 14.0),
         ("damping", "circle", 1.0, (-math.pi, math.pi, -3.0, 3.0), 10.0)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=50)
    states = parser.parse_args().states
    synthesize("swing-up", 1.0, "circle", Window(-1, 1, -1, 1, 11, 11), 4.0)      # load the kernels
    rng = np.random.default_rng(0)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    print(f"commit {commit}, Python {platform.python_version()}, {platform.machine()}\n")
    print("| case | cells | map s | cells per s | ocp.solve per state s (median of "
          f"{states}) | map / (cells x per-state) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for kind, reading, kappa, window, horizon in CASES:
        w = Window(*window, 401, 250)
        start = time.perf_counter()
        s = synthesize(kind, kappa, reading, w, horizon)
        t_map = time.perf_counter() - start
        cells = w.n_theta * w.n_omega
        picked = interior_cells(s)
        times = []
        for i, j in picked[rng.choice(len(picked), size=states, replace=False)]:
            start = time.perf_counter()
            solve(make(kind, kappa, (float(w.theta[i]), float(w.omega[j])), None if reading == "circle" else 0))
            times.append(time.perf_counter() - start)
        per_state = statistics.median(times)
        print(f"| {kind} {reading} kappa={kappa:g} | {cells} | {t_map:.2f} | {cells / t_map:.0f} | {per_state:.3f} | "
              f"{t_map / (cells * per_state):.1e} |")


if __name__ == "__main__":
    main()
