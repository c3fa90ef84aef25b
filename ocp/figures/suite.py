"""The suite's own figures, from a benchmark results store (`ocp bench`): the work-precision
charts (one a case) and the Dolan-More performance profiles, drawn by `ocp.bench.report` (the same
definitions, colours and defaults as `ocp report`)."""

from pathlib import Path

from ..bench import report
from ..bench.store import Store


def records(store):
    """Every result record of the store at `store`, opened read-only (InputError if there is none,
    Fault if it is not an ocp store)."""
    db = Store(store, write=False)
    try:
        return db.results()
    finally:
        db.close()


def profiles(store, accuracies=report.ACCURACIES, budgets=report.BUDGETS):
    """`ocp.bench.report.profiles` of the store's records: the time to reach each accuracy target,
    and the error reached within each time budget relative to the fastest answer on the case."""
    return report.profiles(records(store), accuracies, budgets)


def write_work_precision(data, stem, formats):
    """One chart a case, beside `stem` (named by `ocp.bench.report.work_precision`)."""
    return report.work_precision(data, Path(stem).parent, formats)


def write_profiles(data, stem, formats):
    stem = Path(stem)
    return report.write_profiles(data, stem.with_name(stem.name + "_time"), stem.with_name(stem.name + "_accuracy"),
                                 formats)
