"""Failure maps: where in the phase plane, and where in kappa, a direct method fails.

For a method (`ocp.bench.suite.Method`: transcription, N, solver, configuration) and a grid of
starts (theta, omega) at one kappa, or a sweep of kappa at one start, every cell is a bench row:
the reference of its case from the complete search of extremals (`ocp.bench.reference`), one cold
direct solve (`ocp.bench.measurement`) and its outcome class against the reference
(`ocp.bench.scoring`, the classes of `ocp.bench.outcomes`; no time limit). Nothing here
classifies again.

    grid(kind, kappa, method, window, ...)     a FailureMap over a Window (`ocp.synthesis.field`)
    sweep(kind, kappas, x0, method, ...)       a FailureMap over kappa at one start
    save(fmap, path)                           a compressed numpy file, written whole
"""

import io
import json
import math
import time
from dataclasses import dataclass

import numpy as np

from ..core.files import replacing
from ..core.parallel import Progress, SerialExecutor, drain
from ..direct import MISS_TOL
from .measurement import measure
from .outcomes import OUTCOMES, Outcome
from .reference import reference
from .report import reason, slug
from .scoring import score
from .suite import Case


@dataclass(frozen=True)
class FailureMap:
    """Outcomes of `method` (its `to_dict`) on the cells of `axes`: {"theta", "omega"} (a grid at
    one kappa) or {"kappa"} (a sweep at the start x0). `outcome` holds indices into OUTCOMES, `T`
    the direct answer's time (nan where none), `T_ref` the search's optimum, `reason` the solver's
    and the suite's message of every cell that is not "ok" ("" where it is)."""

    kind: str
    method: dict
    label: str
    kappa: float | None
    x0: tuple | None
    axes: dict
    outcome: np.ndarray
    T: np.ndarray
    T_ref: np.ndarray
    reason: np.ndarray
    time_s: float

    def counts(self):
        """{Outcome: cells}, in the order of OUTCOMES."""
        found = np.bincount(self.outcome.ravel(), minlength=len(OUTCOMES))
        return {outcome: int(n) for outcome, n in zip(OUTCOMES, found) if n}


def cell(case, method, miss_tol=MISS_TOL):
    """(outcome, T, T_ref, reason) of one case: the bench's reference, measure and score, and the
    failure table's reason (`report.reason`)."""
    m = measure(case, method, 1, miss_tol)
    s = score(m, reference(case), math.inf)
    return str(s.outcome), m.T, s.T_ref, "" if s.outcome.success else reason(m, s.outcome)


def _run(kind, kappa, x0, axes, method, cases, pool, workers, progress):
    """The cells of `cases` (in the order of the grid of `axes`) through `pool` (default: this
    process), as a FailureMap."""
    start = time.perf_counter()
    pool = pool or SerialExecutor()
    progress = progress or Progress(len(cases), "cells", io.StringIO())
    outcome = np.zeros(len(cases), dtype=np.int64)
    T, T_ref = np.full(len(cases), np.nan), np.full(len(cases), np.nan)
    reasons = np.full(len(cases), "", dtype=object)

    def handle(i, result):
        name, T[i], T_ref[i], reasons[i] = (np.nan if v is None else v for v in result)
        outcome[i] = OUTCOMES.index(name)
        return f"{cases[i].label}: {name}"

    drain(pool, workers, [(cell, (c, method), i) for i, c in enumerate(cases)], handle, progress,
          label=lambda i: cases[i].label, lost=lambda i, what: (str(Outcome.SOLVER_ERROR), None, None, what))
    shape = tuple(len(v) for v in axes.values())
    return FailureMap(kind, method.to_dict(), method.label, kappa, x0, axes, outcome.reshape(shape), T.reshape(shape),
                      T_ref.reshape(shape), reasons.astype(str).reshape(shape), time.perf_counter() - start)


def grid(kind, kappa, method, window, pool=None, workers=1, progress=None):
    """The FailureMap of `method` over the starts of `window` (`ocp.synthesis.field.Window`) at `kappa`."""
    cases = [Case(kind, kappa, (float(th), float(om))) for th in window.theta for om in window.omega]
    return _run(kind, kappa, None, {"theta": window.theta, "omega": window.omega}, method, cases, pool, workers,
                progress)


def sweep(kind, kappas, x0, method, pool=None, workers=1, progress=None):
    """The FailureMap of `method` over `kappas` from the start `x0` (None: the problem's standard start)."""
    cases = [Case(kind, float(k), x0) for k in kappas]
    return _run(kind, None, x0, {"kappa": np.asarray(kappas, dtype=float)}, method, cases, pool, workers, progress)


def name(fmap):
    """The file name (without suffix) of `fmap`: problem, where, method."""
    where = (f"kappa-{fmap.kappa:g}" if fmap.kappa is not None else
             f"kappa-{fmap.axes['kappa'][0]:g}-{fmap.axes['kappa'][-1]:g}")
    return f"{fmap.kind}-{where}-{slug(fmap.label)}"


def save(fmap, path):
    """`fmap` as a compressed numpy file (arrays, and the settings as JSON in `meta`), written whole."""
    meta = {"kind": fmap.kind, "method": fmap.method, "label": fmap.label, "kappa": fmap.kappa,
            "x0": None if fmap.x0 is None else list(fmap.x0), "outcomes": list(map(str, OUTCOMES)), "time_s": fmap.time_s}
    with replacing(path, "wb") as f:
        np.savez_compressed(f, outcome=fmap.outcome, T=fmap.T, T_ref=fmap.T_ref, reason=fmap.reason,
                            meta=np.array(json.dumps(meta)), **{f"axis_{k}": v for k, v in fmap.axes.items()})
    return path


def summary(fmap):
    """Plain data: the method, where, the count of each outcome, the reasons of failure (each once)."""
    return {"kind": fmap.kind, "method": fmap.label, "kappa": fmap.kappa,
            "x0": None if fmap.x0 is None else list(fmap.x0),
            "axes": {k: [float(v[0]), float(v[-1]), len(v)] for k, v in fmap.axes.items()},
            "outcomes": fmap.counts(), "reasons": sorted(set(map(str, fmap.reason.ravel())) - {""}), "time_s": fmap.time_s}
