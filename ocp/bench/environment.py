"""The machine and software a benchmark ran on, recorded beside its results."""

import datetime
import importlib.metadata
import os
import platform
from pathlib import Path

from ..core.provenance import git_commit
from ..direct import INTEGRATORS
from ..direct.solvers import available, available_solvers

#: distributions whose versions are recorded (absent ones are recorded as None)
PACKAGES = ("ocp", "casadi", "numpy", "scipy", "matplotlib", "rockit-meco", "dask", "distributed")


def _version(name):
    try:
        return importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        return None


def _cpu():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def environment():
    """Plain data: time (UTC), git commit, Python, package versions, CasADi plugins that load,
    CPU model, core count and load average (1, 5, 15 min)."""
    return {
        "time_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "git_commit": git_commit(),
        "python": platform.python_version(),
        "implementation": platform.python_implementation(),
        "platform": platform.platform(),
        "packages": {name: _version(name) for name in PACKAGES},
        "casadi_nlpsol_plugins": available_solvers(),
        "casadi_integrator_plugins": [name for name in INTEGRATORS if name != "rk4" and available("integrator", name)],
        "cpu": _cpu(),
        "cores": os.cpu_count(),
        "load_average": list(os.getloadavg()),
    }
