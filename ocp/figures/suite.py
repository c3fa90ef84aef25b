"""The suite's own figures, from a benchmark results store (`ocp bench`): the work-precision
charts (one a case) and the Dolan-More performance profiles, drawn by `ocp.bench.report`."""

from pathlib import Path

from ..bench import report
from ..bench.store import Store

BUDGET_S, ACCURACY = 1.0, 1e-4  #: as `ocp report`'s defaults


def records(store):
    """Every result record of the store at `store`, opened read-only (InputError if there is none,
    Fault if it is not an ocp store)."""
    db = Store(store, write=False)
    try:
        return db.results()
    finally:
        db.close()


def profiles(store, budget_s=BUDGET_S, accuracy=ACCURACY):
    """{"time": ratios, "error": ratios}: `ocp.bench.report.performance_profile` of the time to
    reach |T - T_ref| <= accuracy and of the error reached within budget_s seconds."""
    costs = report.profile_costs(records(store), budget_s, accuracy)
    return {"time": report.performance_profile(costs, "time"), "error": report.performance_profile(costs, "error"),
            "budget_s": budget_s, "accuracy": accuracy}


def write_work_precision(data, stem, formats):
    """One chart a case, beside `stem` (named by `ocp.bench.report.work_precision`)."""
    return report.work_precision(data, Path(stem).parent, formats)


def write_profiles(data, stem, formats):
    stem = Path(stem)
    return (report.profile_chart(data["time"], f"time to reach |T - T_ref| <= {data['accuracy']:g}",
                                 stem.with_name(stem.name + "_time"), formats)
            + report.profile_chart(data["error"], f"accuracy within {data['budget_s']:g} s",
                                   stem.with_name(stem.name + "_accuracy"), formats))
