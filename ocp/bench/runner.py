"""Running a suite: references, then every (case, method) pair, through one executor interface
(`ocp.core.parallel`), each row stored as it finishes.

    reference(case)                 the search's optimum of the case (`ocp.bench.reference`)
    measure(case, method, ...)      one pair solved, its times and peak memory (`ocp.bench.measurement`)
    score(measurement, reference)   T - T_ref and the outcome class (`ocp.bench.scoring`)
    run(suite, store, executor)     all of it, row by row into the store, with a progress line
    shard(pairs, index, count)      the index-th of count disjoint slices of the pairs (`--shard`)
    pairs_of(suite, part)           the pairs a shard of a suite runs

A direct method is classified against the search (`ocp.solving.classify`); the search itself is
scored against the formula where one applies, else its optimum is the reference of its own case
and the row says so ("the search scores itself there"). Failures are rows: a pair whose Dask
workers all died running it too (`ocp.core.parallel.drain`) is a solver error saying so, and a
reference lost so is none.
"""

import concurrent.futures as cf
import contextlib
import hashlib
import time

from ..core.errors import Fault, last_line
from ..core.parallel import Progress, drain, timing_note
from . import peer
from .measurement import measure
from .reference import reference
from .row import Measurement, Reference, Row, Timing
from .scoring import score
from .suite import PEERS


def shard(pairs, index, count):
    """The `index`-th (from 1) of `count` disjoint slices of `pairs`: a pair is in slice 1 + (the
    SHA-256 of its case and method keys) mod `count`, so each pair is in exactly one slice, whatever
    the order of the suite and whichever other pairs it holds."""
    def slice_of(case, method):
        digest = hashlib.sha256(f"{case.key}\n{method.key}".encode()).digest()
        return 1 + int.from_bytes(digest[:8], "big") % count
    return [(c, m) for c, m in pairs if slice_of(c, m) == index]


def pairs_of(suite, part=None):
    """The pairs of `suite` run by its shard `part` = (index, count) (`shard`), all of them if None."""
    return suite.pairs() if part is None else shard(suite.pairs(), *part)


def run(suite, store, pool, workers, executor_name, environment, part=None):
    """Run every pair of `suite` (of its shard `part` = (index, count) if given: `shard`) not yet in
    `store` with the suite's settings (references first, of those pairs' problems), storing rows as
    they complete. Each pair is claimed in the store just before it is submitted:
    a pair another live `ocp bench` runs is left to it (a note says how many). The peer's pairs are
    skipped, with a note, when rockit is not installed. Returns {session, executor, pairs (those of
    the shard), records (the Rows of this session), resumed (pairs already stored), claimed_elsewhere,
    notes}."""
    notes = []
    if not peer.available() and any(m.transcription in PEERS for m in suite.methods):
        notes.append(peer.MISSING)
    pairs = pairs_of(suite, part)
    described = executor_name if part is None else f"{executor_name}; shard {part[0]}/{part[1]} of the pairs"
    session = store.open_session(suite.name, described, environment)
    try:
        return _run(suite, pairs, store, pool, workers, executor_name, session, notes)
    except cf.BrokenExecutor as err:
        raise Fault(f"a worker process died ({last_line(err)}; out of memory?)") from None
    finally:
        with contextlib.suppress(Fault):
            store.end_session(session)


def _run(suite, pairs, store, pool, workers, executor_name, session, notes):
    refs = store.references()
    cases = list(dict.fromkeys(c for c, _ in pairs))
    needed = list(dict.fromkeys(c.problem_key for c in cases if c.problem_key not in refs))
    first_case = {c.problem_key: c for c in reversed(cases)}

    def add_reference(key, ref):
        store.add_reference(key, ref)
        refs[key] = ref
        return f"{first_case[key].label}: T = {ref.T} ({ref.source})"

    if needed:
        drain(pool, workers, [(reference, (first_case[k],), k) for k in needed], add_reference,
              Progress(len(needed), "references"), label=lambda k: first_case[k].label,
              lost=lambda k, what: Reference(problem=k, T=None, T_error=None, source=f"none: {what}"))
    settings = suite.settings_key
    done = store.done(settings)
    todo = [(c, m) for c, m in pairs if (c.key, m.key) not in done
            and (m.transcription not in PEERS or not notes)]
    records, skipped = [], {"stored": 0, "claimed": 0}
    progress = Progress(len(todo), "runs")

    def claimed():
        for case, method in todo:
            status = store.claim(case.key, method.key, settings, session)
            if status == "mine":
                yield measure, (case, method, suite.repeats, suite.miss_tol, suite.time_limit_s), (case, method, time.time())
            else:
                skipped[status] += 1
                progress.step(f"{case.label} | {method.label}: {status} by another ocp bench")

    def add_result(context, measurement):
        case, method, started = context
        others = store.concurrent(session, started)
        timing = Timing(executor=executor_name, workers=workers, parallel=workers > 1,
                        concurrent_sessions=tuple(others), note=timing_note(workers, others))
        row = Row.of(measurement, score(measurement, refs[case.problem_key], suite.time_limit_s),
                     suite=suite.name, case=case.key, method=method.key, case_label=case.label, family=method.family,
                     label=method.label, N=method.N, configuration=method.configuration, options=method.applied,
                     problem=case.problem_key, guess="default" if case.guess is None else case.guess,
                     **suite.settings, timing=timing)
        store.add_result(case.key, method.key, session, row, settings, started)
        records.append(row)
        return f"{case.label} | {method.label}: {row.outcome}"

    if todo:
        drain(pool, workers, claimed(), add_result, progress, label=lambda c: f"{c[0].label} | {c[1].label}",
              lost=lambda c, what: Measurement(success=False, status="solver_error",
                                               message=f"solver error: {what}"))
    if skipped["claimed"]:
        notes.append(f"{skipped['claimed']} pairs were being run by another ocp bench on this store and were left "
                     f"to it; the same command, once it has ended, shows them")
    return {"session": session, "executor": executor_name, "pairs": pairs, "records": records,
            "resumed": sum((c.key, m.key) in done for c, m in pairs) + skipped["stored"],
            "claimed_elsewhere": skipped["claimed"], "notes": notes}
