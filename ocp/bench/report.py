"""`ocp report`: tables and charts drawn from a results store only (nothing is solved here).

    method table        per method family (a method without its N): runs, success rate, rate of
                        reaching the best known optimum (all guesses; random guesses alone),
                        median |T - T_ref| and median total time
    failure table       per family and outcome class (`ocp.bench.runner.OUTCOMES`), with the
                        cases and a status; every failing row is counted, none is left out
    work precision      per case (default guess): |T - T_ref| against the median total time, one
                        curve per family as N varies; failed runs are not points (they are counted
                        in the legend and listed in the failure table)
    profiles            Dolan-More performance profiles across cases: the time to reach an
                        accuracy (|T - T_ref| <= `accuracy`), and the accuracy reached within a
                        time budget (`budget` seconds); rho(tau) = share of cases whose cost is
                        within tau times the best family's

The best known optimum of a problem is its reference T (the complete search's optimum, or Finch's
formula where one applies); a run reaches it when its outcome is "ok" or "inaccurate" (the optimal
structure) and T - T_best <= its stated error (`T_error`: h^2/2 for a direct answer where measured,
the search's estimate) plus the reference's.
"""

import math
import re
import statistics
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

from ..core import plotting
from ..core.files import folder, write_text
from .store import Store, to_csv, to_json

GOOD = ("ok", "inaccurate")     # converged to the right structure (accurate or not)


def best_known(records):
    """{problem: best known T}: the reference, or an ok run of the extremal search below it."""
    best = {}
    for r in records:
        candidates = [r["T_ref"]] if r["T_ref"] is not None else []
        if r["family"] == "extremal search" and r["outcome"] == "ok":
            candidates.append(r["T"])
        if candidates:
            best[r["problem"]] = min(candidates + [best.get(r["problem"], math.inf)])
    return best


def reached(r, best):
    """Whether run r reached the best known optimum of its problem (module doc)."""
    T_best = best.get(r["problem"])
    if T_best is None or r["outcome"] not in GOOD:
        return False
    return r["T"] - T_best <= (r["T_error"] or 0.0) + (r["T_ref_error"] or 0.0)


def _rate(flags):
    flags = list(flags)
    return f"{sum(flags)}/{len(flags)}" if flags else "-"


def _median(values, fmt):
    values = [v for v in values if v is not None]
    return format(statistics.median(values), fmt) if values else "-"


def method_table(records, best):
    """Rows (dicts) of the method table, families in first-seen order."""
    rows = []
    for family, runs in _by(records, "family").items():
        random = [r for r in runs if r["guess"] != "default"]
        rows.append({
            "method": family,
            "runs": len(runs),
            "success": _rate(r["success"] for r in runs),
            "right structure": _rate(r["outcome"] in GOOD for r in runs),
            "reached optimum": _rate(reached(r, best) for r in runs),
            "reached optimum (random guesses)": _rate(reached(r, best) for r in random),
            "median |T - T_ref|": _median([abs(r["T_minus_ref"]) for r in runs if r["outcome"] in GOOD], ".1e"),
            "median total time (s)": _median([r["total_time_s"] for r in runs if r["outcome"] != "build error"], ".3f"),
        })
    return rows


def failure_table(records):
    """One row per (family, outcome) of the failing runs: count, the N values, cases, one status."""
    groups = defaultdict(list)
    for r in records:
        if r["outcome"] != "ok":
            groups[(r["family"], r["outcome"])].append(r)
    return [{"method": family, "outcome": outcome, "runs": len(runs),
             "N": " ".join(str(n) for n in sorted({r["N"] for r in runs})),
             "cases": "; ".join(dict.fromkeys(r["case_label"] for r in runs)),
             "status (first)": runs[0]["status"][:160]}
            for (family, outcome), runs in groups.items()]


def outcome_counts(records):
    return dict(Counter(r["outcome"] for r in records))


def _by(records, key):
    out = defaultdict(list)
    for r in records:
        out[r[key]].append(r)
    return out


def markdown(rows):
    """A list of dicts as a Markdown table."""
    if not rows:
        return "(none)\n"
    cols = list(rows[0])
    lines = ["| " + " | ".join(cols) + " |", "|" + "|".join(" --- " for _ in cols) + "|"]
    lines += ["| " + " | ".join(str(row[c]).replace("|", "/") for c in cols) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def _slug(text):
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")


def work_precision(records, out_dir, formats):
    """One chart per case with the default guess; returns the paths."""
    import matplotlib.pyplot as plt

    paths = []
    for case, runs in _by([r for r in records if r["guess"] == "default"], "case_label").items():
        with plotting.style():
            fig, ax = plt.subplots()
            for family, fr in _by(runs, "family").items():
                good = sorted((r for r in fr if r["outcome"] in GOOD), key=lambda r: r["N"])
                failed = len(fr) - len(good)
                note = f"  ({failed} failed)" if failed else ""
                if good:
                    ax.plot([r["total_time_s"] for r in good], [max(abs(r["T_minus_ref"]), 1e-16) for r in good],
                            "o-", ms=3, label=family + note)
                elif failed:
                    ax.plot([], [], "x", label=family + f"  (all {failed} failed)")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("total time per solve, median of repeats (s)")
            ax.set_ylabel("|T - T_ref|")
            ax.set_title(f"work precision: {case}")
            ax.legend(loc="best")
            paths += plotting.save(fig, Path(out_dir) / f"work_precision_{_slug(case)}", formats)
    return paths


def profile_costs(records, budget_s, accuracy):
    """{(kind, family): {case: cost}} for kind "time" (time to reach `accuracy`) and "error" (the
    smallest error within `budget_s`); inf where a family never got there."""
    costs = defaultdict(dict)
    cases = list(dict.fromkeys(r["case"] for r in records))
    for family, runs in _by(records, "family").items():
        for case in cases:
            good = [r for r in runs if r["case"] == case and r["outcome"] in GOOD]
            costs[("time", family)][case] = min((r["total_time_s"] for r in good if abs(r["T_minus_ref"]) <= accuracy),
                                                default=math.inf)
            costs[("error", family)][case] = min((max(abs(r["T_minus_ref"]), 1e-15) for r in good
                                                  if r["total_time_s"] <= budget_s), default=math.inf)
    return costs


def performance_profile(costs, kind):
    """{family: sorted ratios cost/best over cases} (Dolan and More 2002); inf where failed."""
    families = [f for k, f in costs if k == kind]
    cases = list(next(iter(costs.values()))) if costs else []
    ratios = {f: [] for f in families}
    for case in cases:
        best = min(costs[(kind, f)][case] for f in families)
        for f in families:
            c = costs[(kind, f)][case]
            ratios[f].append(c / best if math.isfinite(c) else math.inf)
    return {f: sorted(r) for f, r in ratios.items()}


def profile_chart(ratios, title, out_stem, formats):
    import matplotlib.pyplot as plt

    finite = [x for r in ratios.values() for x in r if math.isfinite(x)]
    top = max(2.0, 1.5 * max(finite, default=2.0))
    with plotting.style():
        fig, ax = plt.subplots()
        for family, r in ratios.items():
            x = np.array([1.0] + [v for v in r if math.isfinite(v)] + [top])
            y = np.array([0.0] + [(i + 1) / len(r) for i in range(len(x) - 2)] + [sum(map(math.isfinite, r)) / len(r)])
            ax.step(x, y, where="post", label=family)
        ax.set_xscale("log", base=2)
        ax.set_ylim(-0.02, 1.02)
        ax.set_xlabel("tau (cost / best cost on the case)")
        ax.set_ylabel("share of cases within tau")
        ax.set_title(title)
        ax.legend(loc="lower right")
        return plotting.save(fig, out_stem, formats)


def report(store_path, out_dir=None, budget_s=1.0, accuracy=1e-4, formats=("png",)):
    """The report of the store at `store_path`: a dict of tables (and, with `out_dir`, the charts,
    summary.md, results.csv and results.json written there). The store is opened read-only and every
    record checked before anything is written; each file is written whole (`ocp.core.files`)."""
    store = Store(store_path, write=False)
    try:
        records, sessions = store.results(), store.sessions()
    finally:
        store.close()
    best = best_known(records)
    tables = {
        "store": str(store_path),
        "runs": len(records),
        "outcomes": outcome_counts(records),
        "methods": method_table(records, best),
        "failures": failure_table(records),
        "timing": sorted({r["timing"]["note"] for r in records}),
        "sessions": sessions,
    }
    if out_dir is None:
        return tables
    out = folder(out_dir)
    costs = profile_costs(records, budget_s, accuracy)
    charts = work_precision(records, out, formats)
    charts += profile_chart(performance_profile(costs, "time"),
                            f"time to reach |T - T_ref| <= {accuracy:g}", out / "profile_time", formats)
    charts += profile_chart(performance_profile(costs, "error"),
                            f"accuracy within {budget_s:g} s", out / "profile_accuracy", formats)
    tables["files"] = [str(p) for p in charts + [to_csv(records, out / "results.csv"),
                                                 to_json(records, out / "results.json")]]
    write_text(out / "summary.md", summary_markdown(tables))
    tables["files"].append(str(out / "summary.md"))
    return tables


def summary_markdown(tables):
    env = tables["sessions"][-1]["environment"] if tables["sessions"] else {}
    lines = [f"# Benchmark report: {tables['runs']} runs from {tables['store']}", "",
             "Timing: " + "; ".join(tables["timing"]), "",
             f"Outcomes: {', '.join(f'{k} {v}' for k, v in tables['outcomes'].items())}", "",
             "## Methods", "", markdown(tables["methods"]), "## Failures", "", markdown(tables["failures"]),
             "## Environment (last session)", "", "```", *(f"{k}: {v}" for k, v in env.items()), "```", ""]
    return "\n".join(lines)
