"""Running a suite: references, then every (case, method) pair, through one executor interface.

    reference(case)                the optimum of the case's problem, from ocp.solve's complete
                                   search of extremals (independent of every direct method scored),
                                   scanned to twice the optimum so that slower direct answers are
                                   classified; T replaced by Finch's formula where one applies and
                                   agrees
    measure(case, method, ...)     one pair solved `repeats` times, each cold (every cache of built
                                   objects cleared, `ocp.core.cache.clear`): the outcome and the
                                   median build, solve and total times
    score(record, reference, ...)  T - T_ref, and the outcome class
    run(suite, store, executor)    all of it, row by row into the store, with a progress bar

A direct method is classified against the search (`ocp.solving.classify`); the search itself is
scored against the formula where one applies, else its optimum is the reference of its own case
and the record says so ("the search scores itself there"). Workers receive plain data (`Case`,
`Method`) and rebuild everything. Failures are rows: a plugin that cannot load, a build error, a
solver that raises, all stored with their status.
"""

import concurrent.futures as cf
import contextlib
import ctypes
import gc
import math
import os
import re
import signal
import statistics
import sys
import threading
import time
from types import SimpleNamespace

from .. import direct
from ..core import cache
from ..core.errors import Fault, InputError, last_line
from ..core.output import solver_output
from ..reference import bench_reference
from ..result import DirectClass
from ..solving import classify, solve
from . import peer
from .store import process_alive
from .suite import PEERS, SEARCH

#: a formula and the search agree when their T differ by less than this
AGREE = 1e-9
#: the reference scans to (1 + REFERENCE_MARGIN) times the optimum, to classify slower direct answers
REFERENCE_MARGIN = 1.0
#: outcome classes (DirectClass names, and what precedes a classification)
OUTCOMES = ("ok", "build error", "time limit", *(c.name.lower().replace("_", " ") for c in DirectClass
                                                   if c != DirectClass.OPTIMUM), "no reference")


def _num(x):
    """x as a float, None when missing or not finite (the store holds JSON)."""
    return float(x) if x is not None and math.isfinite(x) else None


# --- references ---------------------------------------------------------------------------------

def reference(case):
    """The reference of case.problem(): the search's optimum (its ties and every extremal found, for
    classifying direct answers), with T and switch times from Finch's formula where one applies to
    its structure and agrees within AGREE. `source` says which. A problem of the reference set
    (`ocp.reference`) is read from it, not searched again."""
    problem = case.problem()
    stored = bench_reference(problem, case.problem_key)
    if stored is not None:
        return stored
    start = time.perf_counter()
    try:
        sol = solve(problem, margin=REFERENCE_MARGIN)
    except Exception as err:        # noqa: BLE001  (no reference is a recorded fact, not a crash)
        return {"problem": case.problem_key, "T": None, "T_error": None, "source":
                f"none: the search raised {type(err).__name__}: {last_line(err)}", "time_s": time.perf_counter() - start}
    if not sol.success or sol.answer is None:
        return {"problem": case.problem_key, "T": None, "T_error": None, "source": f"none: {sol.message}",
                "time_s": time.perf_counter() - start}
    a = sol.answer
    rec = {"problem": case.problem_key, "T": a.T, "T_error": a.T_error, "arc_signs": list(a.signs),
           "switch_times": list(a.switch_times), "branch": a.branch, "optimal": sol.optimal,
           "ties": [e.to_dict() for e in sol.ties], "extremals": [e.to_dict() for e in sol.extremals],
           "horizon": sol.coverage.horizon,
           "source": "complete search of extremals" + ("" if sol.optimal else " (NOT proved optimal: unresolved)")}
    x = sol.crosscheck
    if x is not None and abs(x.T) < AGREE:
        rec.update(T=x.analytic.T, T_error=x.analytic.error, switch_times=list(x.analytic.switch_times),
                   source=f"{x.formula}, agreeing with the complete search to {abs(x.T):.0e}")
    rec["time_s"] = time.perf_counter() - start
    return rec


def _extremal(d):
    """An extremal stored as a dict, with the attributes `classify` reads."""
    return SimpleNamespace(signs=tuple(d["arc_signs"]), branch=d["branch"], T=d["T"])


# --- one pair -----------------------------------------------------------------------------------

def _solve_once(case, method, miss_tol):
    """(Solution or DirectSolution, (n_w, n_g)) of one cold solve."""
    cache.clear()
    problem = case.problem()
    if method.transcription == SEARCH:
        return solve(problem), (0, 0)
    guess = case.initial_guess(method.N)
    if method.transcription in PEERS:
        return peer.solve(problem, method, guess, miss_tol)
    settings = method.transcription_object()
    sol = direct.solve(problem, settings, method.solver, method.applied, guess, miss_tol)
    built = direct.nlp.build(settings, method.solver, method.applied, problem.reading)
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


def _fields(sol, size):
    """The stored fields of one solve (a search Solution or a DirectSolution)."""
    if hasattr(sol, "answer"):         # the search
        return {"success": sol.success, "status": sol.status.name.lower(), "message": sol.message,
                "T": _num(sol.T), "T_error": _num(sol.T_error), "branch": sol.branch,
                "n_switches": sol.n_switches, "arc_signs": list(sol.arc_signs),
                "switch_times": [float(t) for t in sol.switch_times], "bang_bang": True,
                "extremals_integrated": sol.coverage.extremals if sol.coverage else 0, "n_w": 0, "n_g": 0,
                "converged": sol.success, "direct_status": None, "iterations": None, "starts": 0}
    s = sol.structure
    return {"success": sol.success, "status": sol.status.name.lower(), "message": sol.message,
            "solver_message": sol.solver_message, "direct_status": int(sol.status), "converged": sol.converged,
            "iterations": sol.iterations, "T": _num(sol.T), "T_error": _num(sol.T_bound), "branch": sol.branch,
            "n_switches": s.n_switches, "arc_signs": list(s.arc_signs),
            "switch_times": [float(t) for t in s.switch_times], "bang_bang": s.bang_bang,
            "longest_interior_run": s.longest_interior_run, "resim_miss": _num(sol.resim_miss),
            "starts": len(sol.starts), "n_w": int(size[0]), "n_g": int(size[1])}


def measure(case, method, repeats=1, miss_tol=1e-6):
    """Solve the pair `repeats` times, each cold; the fields of the first solve, the median of each
    time and of the peak resident set of the worker process during each repeat (`peak_rss`: the
    interpreter and its libraries included), every repeat's, and the spread of T across repeats. A
    build that fails (a plugin that cannot load, an option it rejects) or a solve that raises gives
    a failure record."""
    times, first = [], None
    with solver_output("devnull"):
        for _ in range(repeats):
            reset_peak_rss()
            try:
                sol, size = _solve_once(case, method, miss_tol)
            except InputError as err:
                return {"success": False, "status": "build_error", "message": f"build error: {err}", "times": []}
            except Exception as err:        # noqa: BLE001  (a solver that raises is a result, not a crash)
                return {"success": False, "status": "solver_error",
                        "message": f"solver error: {type(err).__name__}: {last_line(err)}", "times": []}
            times.append({"build_time_s": getattr(sol, "build_time_s", 0.0),
                          "solve_time_s": getattr(sol, "solve_time_s", sol.total_time_s),
                          "total_time_s": sol.total_time_s, "peak_rss_mib": peak_rss()[0]})
            first = first or (_fields(sol, size), [])
            first[1].append(sol.T)
    fields, Ts = first
    finite = [T for T in Ts if math.isfinite(T)]
    fields["T_spread"] = max(finite) - min(finite) if finite else None
    fields.update({k: statistics.median(t[k] for t in times) for k in times[0]})
    fields["times"] = times
    fields["peak_rss_scope"] = peak_rss()[1]
    return fields


# --- scoring ------------------------------------------------------------------------------------

def outcome(r, ref, time_limit_s):
    """The class of a record against its reference (OUTCOMES): "ok" where the optimum was reached."""
    if r["status"] == "build_error":
        return "build error"
    if r.get("total_time_s", 0.0) > time_limit_s:
        return "time limit"
    if ref["T"] is None:
        return "no reference"
    if r.get("direct_status") is None and r["status"] != "solver_error":      # the search
        ok = r["success"] and abs(r["T"] - ref["T"]) <= (r["T_error"] or 0.0) + (ref["T_error"] or 0.0) + 1e-12
        return "ok" if ok else ("inaccurate" if r["success"] else "no convergence")
    if r["status"] == "solver_error" and r.get("direct_status") is None:
        return "solver error"
    d = SimpleNamespace(status=direct.DirectStatus(r["direct_status"]), T=r["T"], branch=r["branch"],
                        T_bound=r["T_error"], structure=SimpleNamespace(arc_signs=tuple(r["arc_signs"]),
                                                                      bang_bang=r["bang_bang"]))
    answer = SimpleNamespace(signs=tuple(ref["arc_signs"]), branch=ref["branch"], T=ref["T"])
    c = classify(d, answer, [_extremal(t) for t in ref["ties"]], [_extremal(e) for e in ref["extremals"]],
                 ref["horizon"])
    return "ok" if c == DirectClass.OPTIMUM else c.name.lower().replace("_", " ")


def score(record, ref, case, time_limit_s):
    """`record` with the reference, T - T_ref, switch-time errors and the outcome."""
    r = dict(record, T_ref=ref["T"], T_ref_error=ref["T_error"], ref_source=ref["source"], T_minus_ref=None,
             switch_time_errors=None)
    r.setdefault("total_time_s", 0.0)
    if r.get("T") is not None and ref["T"] is not None:
        r["T_minus_ref"] = r["T"] - ref["T"]
        if len(r["switch_times"]) == len(ref["switch_times"]):
            r["switch_time_errors"] = [t - t_ref for t, t_ref in zip(r["switch_times"], ref["switch_times"])]
    r["outcome"] = outcome(r, ref, time_limit_s)
    return r


# --- executors and the run ----------------------------------------------------------------------

class SerialExecutor(cf.Executor):
    """The concurrent.futures interface, run in this process at submit (`--jobs 1`)."""

    def submit(self, fn, /, *args, **kwargs):
        future = cf.Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception as err:     # noqa: BLE001  (delivered through the future, as other executors do)
            future.set_exception(err)
        return future


@contextlib.contextmanager
def executor(jobs=1, scheduler=None):
    """(executor, workers, description): local processes (`jobs`), or a Dask distributed cluster at
    `scheduler` (the `dask` extra), all behind concurrent.futures.Executor."""
    if scheduler:
        try:
            import distributed
        except ImportError:
            raise InputError("--scheduler needs Dask distributed: pip install 'ocp[dask]'") from None
        if not SCHEDULER.fullmatch(scheduler):
            raise InputError(f"--scheduler {scheduler[:60]!r} is not a scheduler address; accepted: an address such as "
                             f"tcp://host:8786 (tcp, tls, ws, wss, ucx)")
        try:
            client = distributed.Client(scheduler, timeout=10)
        except (OSError, TimeoutError, ValueError, TypeError) as err:
            # the half-built Client is collected now: its __del__, run later inside another
            # Client's start, deadlocks on the event loop's lock
            gc.collect()
            raise InputError(f"cannot reach the Dask scheduler at {scheduler}: {last_line(err)}") from None
        with client:
            yield client.get_executor(), max(1, sum(client.nthreads().values())), f"dask {scheduler}"
    elif jobs == 1:
        yield SerialExecutor(), 1, "serial (this process)"
    else:
        with cf.ProcessPoolExecutor(jobs, initializer=die_with_parent, initargs=(os.getpid(),)) as pool:
            yield pool, jobs, f"{jobs} local worker processes"


#: a Dask scheduler address: scheme://host:port
SCHEDULER = re.compile(r"(tcp|tls|ws|wss|ucx)://([A-Za-z0-9.\-]+|\[[0-9A-Fa-f:]+\]):[0-9]{1,5}")

PR_SET_PDEATHSIG = 1


def die_with_parent(parent):
    """Worker initializer: this process ends when the process `parent` does (a killed `ocp bench`
    leaves no orphans): Linux's parent-death signal where `parent` is the direct parent, and a
    thread that checks once a second."""
    if sys.platform.startswith("linux") and os.getppid() == parent:
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    threading.Thread(target=_watch, args=(parent,), daemon=True).start()


def _watch(parent):
    while process_alive(parent):
        time.sleep(1.0)
    os._exit(1)


class Progress:
    """A progress bar on stderr: redrawn in place on a terminal, a line per tenth otherwise."""

    def __init__(self, total, what, stream=None):
        self.total, self.what, self.done = total, what, 0
        self.stream = stream or sys.stderr
        self.start = time.perf_counter()
        self.tty = self.stream.isatty()
        self.shown = -1

    def step(self, note=""):
        self.done += 1
        elapsed = time.perf_counter() - self.start
        left = elapsed / self.done * (self.total - self.done)
        filled = 30 * self.done // max(self.total, 1)
        line = (f"[{'#' * filled}{'.' * (30 - filled)}] {self.done}/{self.total} {self.what}  "
                f"{elapsed:.0f} s, ~{left:.0f} s left  {note}")
        if self.tty:
            self.stream.write("\r" + line[:150].ljust(150))
            if self.done == self.total:
                self.stream.write("\n")
        elif 10 * self.done // max(self.total, 1) > self.shown:
            self.shown = 10 * self.done // max(self.total, 1)
            self.stream.write(line + "\n")
        self.stream.flush()


def drain(pool, workers, tasks, handle, progress):
    """Submit tasks (fn, args, context), at most 2 per worker in flight; handle(context, result) each
    as it completes. An interruption cancels what has not started; handled rows stay handled."""
    tasks, pending = iter(tasks), {}
    try:
        while True:
            for fn, args, context in tasks:
                pending[pool.submit(fn, *args)] = context
                if len(pending) >= 2 * workers:
                    break
            if not pending:
                return
            done, _ = cf.wait(pending, return_when=cf.FIRST_COMPLETED)
            for future in done:
                context = pending.pop(future)
                progress.step(handle(context, future.result()))
    finally:
        for future in pending:
            future.cancel()


def timing_note(workers, others):
    """How a row was timed: alone, in parallel with its own workers, and/or while other `ocp bench`
    sessions (ids `others`) wrote to the same store."""
    parts = ["timed in parallel: workers share the machine"] if workers > 1 else []
    if others:
        parts.append(f"timed while another ocp bench wrote to this store (session {', '.join(map(str, others))}): "
                     f"it may have shared the machine")
    return "; ".join(parts) or "timed alone"


def run(suite, store, pool, workers, executor_name, environment):
    """Run every pair of `suite` not yet in `store` with the suite's settings (references first),
    storing rows as they complete. Each pair is claimed in the store just before it is submitted:
    a pair another live `ocp bench` runs is left to it (a note says how many). The peer's pairs are
    skipped, with a note, when rockit is not installed. Returns {session, executor, records (of
    this session), resumed (pairs already stored), claimed_elsewhere, notes}."""
    notes = []
    if not peer.available() and any(m.transcription in PEERS for m in suite.methods):
        notes.append(peer.MISSING)
    session = store.open_session(suite.name, executor_name, environment)
    try:
        return _run(suite, store, pool, workers, executor_name, session, notes)
    except cf.BrokenExecutor as err:
        raise Fault(f"a worker process died ({last_line(err)}; out of memory?)") from None
    finally:
        with contextlib.suppress(Fault):
            store.end_session(session)


def _run(suite, store, pool, workers, executor_name, session, notes):
    refs = store.references()
    needed = list(dict.fromkeys(c.problem_key for c in suite.cases if c.problem_key not in refs))
    first_case = {c.problem_key: c for c in reversed(suite.cases)}

    def add_reference(key, rec):
        store.add_reference(key, rec)
        refs[key] = rec
        return f"{first_case[key].label}: T = {rec['T']} ({rec['source']})"

    if needed:
        drain(pool, workers, [(reference, (first_case[k],), k) for k in needed], add_reference,
               Progress(len(needed), "references"))
    settings = suite.settings_key
    done = store.done(settings)
    todo = [(c, m) for c, m in suite.pairs() if (c.key, m.key) not in done
            and (m.transcription not in PEERS or not notes)]
    records, skipped = [], {"stored": 0, "claimed": 0}
    progress = Progress(len(todo), "runs")

    def claimed():
        for case, method in todo:
            status = store.claim(case.key, method.key, settings, session)
            if status == "mine":
                yield measure, (case, method, suite.repeats, suite.miss_tol), (case, method, time.time())
            else:
                skipped[status] += 1
                progress.step(f"{case.label} | {method.label}: {status} by another ocp bench")

    def add_result(context, rec):
        case, method, started = context
        rec = score(rec, refs[case.problem_key], case, suite.time_limit_s)
        others = store.concurrent(session, started)
        timing = {"executor": executor_name, "workers": workers, "parallel": workers > 1,
                  "concurrent_sessions": others, "note": timing_note(workers, others)}
        rec.update(suite=suite.name, case=case.key, method=method.key, case_label=case.label,
                   family=method.family, label=method.label, N=method.N, configuration=method.configuration,
                   options=method.applied, problem=case.problem_key,
                   guess="default" if case.guess is None else case.guess, **suite.settings, timing=timing)
        store.add_result(case.key, method.key, session, rec, settings, started)
        records.append(rec)
        return f"{case.label} | {method.label}: {rec['outcome']}"

    if todo:
        drain(pool, workers, claimed(), add_result, progress)
    if skipped["claimed"]:
        notes.append(f"{skipped['claimed']} pairs were being run by another ocp bench on this store and were left "
                     f"to it; the same command, once it has ended, shows them")
    return {"session": session, "executor": executor_name, "records": records,
            "resumed": sum((c.key, m.key) in done for c, m in suite.pairs()) + skipped["stored"],
            "claimed_elsewhere": skipped["claimed"], "notes": notes}
