"""One (case, method) pair solved: `measure(case, method, repeats, miss_tol, time_limit_s)` solves it
`repeats` times, each cold (every cache of built objects cleared, `ocp.core.cache.clear`), each
start under the solver's own limits (`ocp.direct.solvers.limits`: its iterations, and
`time_limit_s` as its CPU seconds where it has such an option; the search's own time limit), and
returns a `Measurement`: the fields of the first solve, the median build, solve and total times,
the solver's own CPU time and the peak resident set over the repeats. Workers receive plain data (`Case`, `Method`) and rebuild
everything. A plugin that cannot load, a build error, a solver that raises: each is a
Measurement with its status, not a crash."""

import contextlib
import math
import statistics
import sys
import time

from .. import direct
from ..core import cache
from ..core.errors import InputError, last_line
from ..core.output import solver_output
from ..solving import solve
from . import peer
from .row import Measurement, Repeat, StartRecord
from .suite import PEERS, SEARCH


def _number(x):
    """x as a float, None when missing or not finite (the store holds JSON)."""
    return float(x) if x is not None and math.isfinite(x) else None


def _integer(x):
    return None if x is None else int(x)


def _solve_once(case, method, miss_tol, time_limit_s):
    """(Solution or DirectSolution, (n_w, n_g)) of one cold solve."""
    cache.clear()
    problem = case.problem()
    if method.transcription == SEARCH:
        return solve(problem, time_limit=time_limit_s if math.isfinite(time_limit_s) else None), (0, 0)
    guess = case.initial_guess(method.N)
    if method.transcription in PEERS:
        return peer.solve(problem, method, guess, miss_tol, time_limit_s)
    settings = method.transcription_object()
    sol = direct.solve(problem, settings, method.solver, method.applied, guess, miss_tol, time_limit_s=time_limit_s)
    built = direct.nlp.build(settings, method.solver, sol.method["options"], problem.reading)    # the one solved
    return sol, (built.n_w, built.n_g)


def peak_rss():
    """(peak resident set of this process in MiB, since when): on Linux the high-water mark VmHWM,
    reset by `reset_peak_rss`; elsewhere getrusage's ru_maxrss, the peak since the process began."""
    try:
        with open("/proc/self/status") as f:
            kb = next(int(line.split()[1]) for line in f if line.startswith("VmHWM:"))
        return kb / 1024, "this run"
    except (OSError, StopIteration, ValueError):
        import resource
        scale = 1 if sys.platform == "darwin" else 1024          # bytes on macOS, KiB on Linux
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * scale / 2**20, "the process so far"


def reset_peak_rss():
    """Reset this process's peak resident set to its current one (Linux >= 4.0; elsewhere nothing)."""
    with contextlib.suppress(OSError):
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")


def _fields(sol, size, search, time_limit_s):
    """The Measurement fields of one solve: a search Solution (`search`) or a DirectSolution."""
    common = dict(success=bool(sol.success), status=sol.status.name.lower(), message=sol.message, T=_number(sol.T),
                  branch=_integer(sol.branch))
    if search:
        stopped = bool(sol.coverage and sol.coverage.stopped)
        return dict(common, T_error=_number(sol.T_error), n_switches=sol.n_switches,
                    arc_signs=tuple(map(int, sol.arc_signs)), switch_times=tuple(map(float, sol.switch_times)),
                    bang_bang=True, extremals_integrated=sol.coverage.extremals if sol.coverage else 0,
                    converged=bool(sol.success), limited=stopped,
                    limits={"time_limit": time_limit_s} if math.isfinite(time_limit_s) else {})
    s = sol.structure
    return dict(common, solver_message=sol.solver_message, direct_status=int(sol.status), converged=bool(sol.converged),
                limited=bool(sol.limited), limits=dict(sol.limits),
                iterations=_integer(sol.iterations), T_error=_number(sol.T_bound), n_switches=s.n_switches,
                arc_signs=tuple(map(int, s.arc_signs)), switch_times=tuple(map(float, s.switch_times)),
                bang_bang=bool(s.bang_bang), longest_interior_run=_integer(s.longest_interior_run),
                resim_miss=_number(sol.resim_miss), miss_bound=_number(sol.miss_bound), starts=len(sol.starts),
                n_w=int(size[0]), n_g=int(size[1]),
                every_start=tuple(StartRecord(guess=str(s.guess), status=str(s.status), message=str(s.message),
                                              solver_message=str(s.solver_message), limited=bool(s.limited),
                                              T=_number(s.T), iterations=_integer(s.iterations),
                                              resim_miss=_number(s.resim_miss), miss_bound=_number(s.miss_bound),
                                              solve_time_s=float(s.solve_time_s), cpu_time_s=float(s.cpu_time_s))
                                  for s in sol.starts))


def measure(case, method, repeats=1, miss_tol=1e-6, time_limit_s=math.inf):
    """The Measurement of the pair over `repeats` cold solves (module doc): the first solve's
    fields, the median of each time and of the peak resident set of the worker process during each
    repeat (`peak_rss`: the interpreter and its libraries included), every repeat's, and the spread
    of T across repeats. The solver's own CPU time: a direct solve's from the solver's stats
    (`ocp.direct.solve.own_times`) and its build's process time; the search's, the process's."""
    times, first, Ts = [], None, []
    with solver_output("devnull"):
        for _ in range(repeats):
            reset_peak_rss()
            cpu = time.process_time()
            try:
                sol, size = _solve_once(case, method, miss_tol, time_limit_s)
            except InputError as err:
                return Measurement(success=False, status="build_error", message=f"build error: {err}")
            except Exception as err:        # noqa: BLE001  (a solver that raises is a result, not a crash)
                return Measurement(success=False, status="solver_error",
                                   message=f"solver error: {type(err).__name__}: {last_line(err)}")
            cpu = time.process_time() - cpu
            times.append(Repeat(build_time_s=getattr(sol, "build_time_s", 0.0),
                                solve_time_s=getattr(sol, "solve_time_s", sol.total_time_s),
                                total_time_s=sol.total_time_s, cpu_time_s=cpu,
                                solver_cpu_time_s=getattr(sol, "cpu_time_s", cpu), peak_rss_mib=peak_rss()[0]))
            first = first or _fields(sol, size, method.transcription == SEARCH, time_limit_s)
            Ts.append(sol.T)
    finite = [T for T in Ts if math.isfinite(T)]
    medians = {k: statistics.median(getattr(t, k) for t in times)
               for k in ("build_time_s", "solve_time_s", "total_time_s", "cpu_time_s", "solver_cpu_time_s",
                         "peak_rss_mib")}
    checks = statistics.median(max(0.0, t.total_time_s - t.build_time_s - t.solve_time_s) for t in times)
    return Measurement(**first, **medians, check_time_s=checks, T_spread=max(finite) - min(finite) if finite else None,
                       times=tuple(times), peak_rss_scope=peak_rss()[1])
