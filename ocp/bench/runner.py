"""Running a suite: references, then every (case, method) pair, through one executor interface.

    reference(case)                the best known answer of a problem, and where it comes from
    measure(case, method, ...)     one pair solved `repeats` times from scratch: the outcome and the
                                   median build, solve, refinement and total times
    score(record, reference, ...)  the errors against the reference and the outcome class
    run(suite, store, executor)    all of it, row by row into the store, with a progress bar

Workers receive plain data (`Case`, `Method`) and rebuild the NLP; every repeat clears the
transcription's build cache, so each timing is of a cold solve and does not depend on which
worker ran what before. Failures are rows: a plugin that cannot load, a build error, a solver
that raises, all stored with their status.
"""

import concurrent.futures as cf
import contextlib
import math
import statistics
import sys
import time

from .. import analytic, pipeline, transcription
from ..errors import InputError, last_line
from ..redirect import solver_output
from . import peer

#: the direct stage of a reference solve (its structure seeds the refinement)
REFERENCE_METHOD = transcription.MultipleShooting(100)
#: a formula and the refinement agree when their T differ by less than this
AGREE = 1e-8
#: outcome classes, in the order they are tested (the first that applies names a row)
OUTCOMES = ("ok", "build error", "solver error", "time limit", "no convergence", "misses target", "chattering",
            "local optimum", "wrong structure", "inaccurate", "no reference")


def _num(x):
    """x as a float, None when missing or not finite (the store holds JSON)."""
    return float(x) if x is not None and math.isfinite(x) else None


# --- references ---------------------------------------------------------------------------------

def _signs(bb):
    return [bb.first_u * (-1) ** i for i in range(bb.n_switches + 1)]


def reference(case):
    """The reference of case.problem(): `ocp.solve` with refinement and certificate (direct stage
    REFERENCE_METHOD), and the exact formulas where one applies (`ocp.analytic.formula_for`, one
    or two switches, on the branch the refinement reached): a formula of the same switch count and
    T within AGREE replaces the refined values (exact to its own error bound); a formula faster
    than the refinement replaces it too (the refinement found a local optimum), and the record
    says so. `source` names where the numbers come from."""
    problem = case.problem()
    start = time.perf_counter()
    try:
        with solver_output("devnull"):
            sol = pipeline.solve(problem, REFERENCE_METHOD)
    except Exception as err:        # noqa: BLE001  (no reference is a recorded fact, not a crash)
        return {"problem": case.problem_key, "T": None, "T_error": None, "arc_signs": None, "switch_times": None,
                "branch": None, "source": f"none: the reference solve raised {type(err).__name__}: {last_line(err)}",
                "time_s": time.perf_counter() - start}
    rec = {"problem": case.problem_key, "refined_T": _num(sol.T) if sol.refined else None, "certified": sol.certified,
           "T": None, "T_error": None, "arc_signs": None, "switch_times": None, "branch": None, "source": "none"}
    if sol.refined:
        rec.update(T=sol.T, T_error=sol.refined.T_error, arc_signs=list(sol.arc_signs), switch_times=sol.switch_times,
                   branch=sol.refined_branch,
                   source="certified refinement" if sol.certified else "refinement, NOT certified")
    branch = sol.refined_branch if sol.refined else problem.guess_branch
    formulas = [analytic.formula_for(problem, branch, n, first) for n in (1, 2) for first in (1, -1)]
    for bb in filter(None, formulas):
        same = sol.refined is not None and bb.n_switches == sol.n_switches and abs(bb.T - sol.T) < AGREE
        if same or rec["T"] is None or bb.T < rec["T"] - AGREE:
            note = (f"agrees with the {rec['source']} to {abs(bb.T - sol.T):.0e}" if same else
                    "faster than the refinement found" if sol.refined else "no refined solution")
            name = f"{'one' if bb.n_switches == 1 else 'two'}_switch"
            rec.update(T=bb.T, T_error=bb.error, arc_signs=_signs(bb), switch_times=list(bb.switch_times),
                       branch=branch, source=f"analytic {name} ({note})")
    rec["time_s"] = time.perf_counter() - start
    return rec


# --- one pair -----------------------------------------------------------------------------------

def _solve_once(case, method, miss_tol):
    """(Solution, (n_w, n_g)) of one cold solve."""
    problem, guess = case.problem(), case.initial_guess(method.N)
    if method.transcription == "rockit":
        return peer.solve(problem, method, guess, miss_tol)
    transcription.clear_cache()               # a cold build every repeat
    sol = pipeline.solve(problem, method.settings(), method.solver, method.options, guess, miss_tol, method.refine)
    built = transcription.build(method.settings(), method.solver, method.options, free_branch=problem.branch is None)
    return sol, (built.n_w, built.n_g)


def _fields(sol, size):
    """The stored fields of one solve."""
    d, s = sol.to_dict(), sol.structure
    return {
        "success": sol.success, "solver_success": sol.solver_success, "status": sol.status,
        "iterations": sol.iterations, "T": _num(sol.T), "T_accuracy": _num(d["T_error"]), "T_direct": _num(sol.T_direct),
        "branch": d["branch"], "n_switches": sol.n_switches, "arc_signs": list(sol.arc_signs),
        "switch_times": [float(t) for t in sol.switch_times], "bang_bang": s.bang_bang,
        "longest_interior_run": s.longest_interior_run, "resim_miss": _num(d["resim_miss"]),
        "refined": sol.refined is not None, "certified": sol.certified, "starts": len(sol.starts),
        "n_w": int(size[0]), "n_g": int(size[1]),
    }


def measure(case, method, repeats=1, miss_tol=1e-6):
    """Solve the pair `repeats` times from scratch; the fields of the first solve, the median of
    each time, every repeat's times, and the spread of T across repeats. A build that fails (a
    plugin that cannot load, an option it rejects) or a solve that raises gives a failure record."""
    times = []
    first = None
    with solver_output("devnull"):
        for _ in range(repeats):
            try:
                sol, size = _solve_once(case, method, miss_tol)
            except InputError as err:
                return {"success": False, "solver_success": False, "status": f"build error: {err}", "times": []}
            except Exception as err:        # noqa: BLE001  (a solver that raises is a result, not a crash)
                return {"success": False, "solver_success": False,
                        "status": f"solver error: {type(err).__name__}: {last_line(err)}", "times": []}
            times.append({k: getattr(sol, k) for k in ("build_time_s", "solve_time_s", "refine_time_s", "total_time_s")})
            first = first or (_fields(sol, size), [])
            first[1].append(sol.T)
    fields, Ts = first
    finite = [T for T in Ts if math.isfinite(T)]
    fields["T_spread"] = max(finite) - min(finite) if finite else None
    fields.update({k: statistics.median(t[k] for t in times) for k in times[0]})
    fields["times"] = times
    return fields


# --- scoring ------------------------------------------------------------------------------------

def mirror_branch(problem, k):
    """The branch of the mirror image of branch k (theta -> 2*theta0 - theta, u -> -u), when the start
    is its own mirror image (omega0 = 0, theta0 a multiple of pi from the target); else None."""
    theta0, omega0 = problem.x0
    m = (theta0 - problem.target_base) / math.pi
    return round(m) - k if omega0 == 0 and abs(m - round(m)) < 1e-12 else None


def structure_ok(record, ref, problem):
    """Same switch count, arc signs and target branch as the reference, or as its mirror image."""
    if ref["arc_signs"] is None or record.get("arc_signs") is None:
        return None
    if record["arc_signs"] == ref["arc_signs"] and record["branch"] == ref["branch"]:
        return True
    return record["arc_signs"] == [-s for s in ref["arc_signs"]] and record["branch"] == mirror_branch(problem, ref["branch"])


def outcome(r, time_limit_s):
    """The class of a scored record (OUTCOMES): the first failure that applies, else "ok"."""
    status = r["status"]
    if status.startswith("build error"):
        return "build error"
    if status.startswith("solver error"):
        return "solver error"
    if r["total_time_s"] > time_limit_s or "time" in status.lower() and "exceeded" in status.lower():
        return "time limit"
    if not r["solver_success"]:
        return "no convergence"
    if not r["success"]:
        return "misses target"
    if not r["bang_bang"]:
        return "chattering"
    if r["T_error"] is None:
        return "no reference"
    bound = r["T_accuracy"] + (r["T_ref_error"] or 0.0)
    if not r["structure_ok"]:
        return "local optimum" if r["T_error"] > bound else "wrong structure"
    return "ok" if abs(r["T_error"]) <= bound else "inaccurate"


def score(record, ref, case, time_limit_s):
    """`record` with the reference, T - T_ref, switch-time errors, structure check and outcome."""
    r = dict(record, T_ref=ref["T"], T_ref_error=ref["T_error"], ref_source=ref["source"], T_error=None,
             switch_time_errors=None, structure_ok=None)
    r.setdefault("total_time_s", 0.0)
    if r.get("T") is not None and ref["T"] is not None:
        r["T_error"] = r["T"] - ref["T"]
        r["structure_ok"] = structure_ok(r, ref, case.problem())
        if len(r["switch_times"]) == len(ref["switch_times"]):
            r["switch_time_errors"] = [t - t_ref for t, t_ref in zip(r["switch_times"], ref["switch_times"])]
    r["outcome"] = outcome(r, time_limit_s)
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
        try:
            client = distributed.Client(scheduler, timeout=10)
        except (OSError, TimeoutError) as err:
            raise InputError(f"cannot reach the Dask scheduler at {scheduler}: {last_line(err)}") from None
        with client:
            yield client.get_executor(), max(1, sum(client.nthreads().values())), f"dask {scheduler}"
    elif jobs == 1:
        yield SerialExecutor(), 1, "serial (this process)"
    else:
        with cf.ProcessPoolExecutor(jobs) as pool:
            yield pool, jobs, f"{jobs} local worker processes"


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


def _drain(pool, workers, tasks, handle, progress):
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


def run(suite, store, pool, workers, executor_name, environment):
    """Run every pair of `suite` not yet in `store` (references first), storing rows as they
    complete. The peer's pairs are skipped, with a note, when rockit is not installed. Returns
    {session, executor, records (of this session), resumed (pairs already stored), notes}."""
    notes = []
    if not peer.available() and any(m.transcription == "rockit" for m in suite.methods):
        notes.append(peer.MISSING)
    session = store.open_session(suite.name, executor_name, environment)
    timing = {"executor": executor_name, "workers": workers, "parallel": workers > 1,
              "note": "timed in parallel: workers share the machine" if workers > 1 else "timed alone"}
    refs = store.references()
    needed = list(dict.fromkeys(c.problem_key for c in suite.cases if c.problem_key not in refs))
    first_case = {c.problem_key: c for c in reversed(suite.cases)}

    def add_reference(key, rec):
        store.add_reference(key, rec)
        refs[key] = rec
        return f"{first_case[key].label}: T = {rec['T']} ({rec['source']})"

    if needed:
        _drain(pool, workers, [(reference, (first_case[k],), k) for k in needed], add_reference,
               Progress(len(needed), "references"))
    done = store.done()
    todo = [(c, m) for c, m in suite.pairs() if (c.key, m.key) not in done
            and (m.transcription != "rockit" or not notes)]
    records = []

    def add_result(pair, rec):
        case, method = pair
        rec = score(rec, refs[case.problem_key], case, suite.time_limit_s)
        rec.update(suite=suite.name, case=case.key, method=method.key, case_label=case.label,
                   family=method.family, label=method.label, N=method.N, problem=case.problem_key,
                   guess="default" if case.guess is None else case.guess, repeats=suite.repeats, timing=timing)
        store.add_result(case.key, method.key, session, rec)
        records.append(rec)
        return f"{case.label} | {method.label}: {rec['outcome']}"

    if todo:
        _drain(pool, workers, [(measure, (c, m, suite.repeats, suite.miss_tol), (c, m)) for c, m in todo],
               add_result, Progress(len(todo), "runs"))
    resumed = sum((c.key, m.key) in done for c, m in suite.pairs())
    return {"session": session, "executor": executor_name, "records": records, "resumed": resumed, "notes": notes}
