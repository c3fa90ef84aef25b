"""`ocp report`: tables and charts drawn from a results store only (nothing is solved here).

    method table        per method family (a method without its N): runs, rate verified (the
                        re-simulated control within the suite's miss_tol), rate of the optimal
                        structure (discretisation results and inaccurate ones included), rate of
                        reaching the best known optimum (all guesses; random guesses alone; runs
                        of a method that states no accuracy cannot be judged and are counted
                        apart), median |T - T_ref|, median solver time (`Measurement.solver_time_s`:
                        build and NLP solves, not the suite's checking) and median peak
                        resident memory of the worker during a run (`measurement.peak_rss`)
    failure table       per family and outcome class (`ocp.bench.outcomes.Outcome`), with the
                        cases and a status; every failing row is counted, none is left out
    work precision      per case (default guess): |T - T_ref| against the solver time, one curve
                        per family as N varies, points labelled with their N where a label fits
                        without overprinting another; answers of another extremal than the
                        optimum (local optimum, wrong structure, beyond horizon) are open markers,
                        their class in the legend; the axes span the direct methods' points (the
                        search, far below, is given in the note under the chart); a family
                        without a point is not in the legend but listed in that note with its
                        outcomes; failed runs are counted in the legend and listed in the
                        failure table
    profiles            Dolan-More performance profiles across cases: every case counted (one
                        that no direct method reaches caps every curve: drawn as a ceiling),
                        identical curves drawn once and named together ("A = B"), the axis
                        fitted to the ratios

Performance profiles (Dolan and More 2002): their costs and ratios in `ocp.bench.profiles`, drawn
here.

The best known optimum of a problem is its reference T (the complete search's optimum, or Finch's
formula where one applies); a run reaches it when its outcome is "ok" or "inaccurate" (the optimal
structure) and T - T_best <= its stated error (`T_error`: h^2/2 for a direct answer where measured,
the search's estimate) plus the reference's. Colours: one per method family in every chart
(`family_style`: fixed slots for the families of the shipped suites, in suite order, then the
others by name).
"""

import hashlib
import math
import re
import statistics
from collections import Counter, defaultdict
from pathlib import Path

from ..core import plotting
from ..core.files import folder, write_text
from ..core.numbers import order
from ..core.output import printable
from .outcomes import ANOTHER, GOOD, Outcome
from .profiles import ACCURACIES, BUDGETS, error, performance_profile, profile_costs, unreached
from .store import Store, to_csv, to_json
from .suite import SEARCH_FAMILY as SEARCH


def best_known(records):
    """{problem: best known T}: the reference, or an ok run of the extremal search below it."""
    best = {}
    for r in records:
        candidates = [r.T_ref] if r.T_ref is not None else []
        if r.family == SEARCH and r.outcome == Outcome.OK:
            candidates.append(r.T)
        if candidates:
            best[r.problem] = min(candidates + [best.get(r.problem, math.inf)])
    return best


def reached(r, best):
    """Whether run r reached the best known optimum of its problem (module doc): True, False, or
    None where it cannot be judged (the optimal structure, but the method states no accuracy)."""
    T_best = best.get(r.problem)
    if T_best is None or r.outcome not in GOOD:
        return False
    if r.T_error is None:
        return None
    return r.T - T_best <= r.T_error + (r.T_ref_error or 0.0)


def _rate(flags):
    """"k/n" of the flags that are True among those judged; those that cannot be judged (None) said apart."""
    flags = list(flags)
    judged = [f for f in flags if f is not None]
    if not flags:
        return "-"
    text = f"{sum(judged)}/{len(judged)}" if judged else "-"
    unjudged = len(flags) - len(judged)
    return text + (f" (+{unjudged} right structure, no stated accuracy)" if unjudged else "")


def _median(values, fmt):
    values = [v for v in values if v is not None]
    return format(statistics.median(values), fmt) if values else "-"


def method_table(records, best):
    """Rows (dicts) of the method table, families in first-seen order."""
    rows = []
    for family, runs in _by(records, "family").items():
        random = [r for r in runs if r.guess != "default"]
        rows.append({
            "method": family,
            "runs": len(runs),
            "verified (miss <= tol)": _rate(r.success for r in runs),
            "right structure": _rate(r.outcome in GOOD for r in runs),
            "reached optimum": _rate(reached(r, best) for r in runs),
            "reached optimum (random guesses)": _rate(reached(r, best) for r in random),
            "median |T - T_ref|": _median([abs(r.T_minus_ref) for r in runs if r.outcome in GOOD], ".1e"),
            "median solver time (s)": _median([r.solver_time_s for r in runs if r.outcome != Outcome.BUILD_ERROR],
                                              ".3f"),
            "median peak memory (MiB)": _median([r.peak_rss_mib for r in runs], ".0f"),
        })
    return rows


def failure_table(records):
    """One row per (family, outcome) of the failing runs: count, the N values, cases, one status."""
    groups = defaultdict(list)
    for r in records:
        if not r.outcome.success:
            groups[(r.family, r.outcome)].append(r)
    return [{"method": family, "outcome": outcome, "runs": len(runs),
             "N": " ".join(str(n) for n in sorted({r.N for r in runs})),
             "cases": "; ".join(dict.fromkeys(r.case_label for r in runs)),
             "status (first)": reason(runs[0], outcome)[:160]}
            for (family, outcome), runs in groups.items()]


def reason(m, outcome):
    """How the Measurement `m` of outcome `outcome` ended, in words: the solver's own message and the
    suite's (with the re-simulated miss when the control misses the target)."""
    parts = [m.solver_message, m.message or m.status]
    if outcome == Outcome.MISSES_TARGET and m.resim_miss is not None:
        parts.append(f"by {order(m.resim_miss)}")
    return ": ".join(p for p in parts if p)


def outcome_counts(records):
    """{outcome label: rows}, in the order first seen."""
    return {str(k): n for k, n in Counter(r.outcome for r in records).items()}


def _by(records, key):
    out = defaultdict(list)
    for r in records:
        out[getattr(r, key)].append(r)
    return out


#: a table cell is cut to this many characters, a label in a chart to LABEL
CELL, LABEL = 1000, 80


def markdown(rows):
    """A list of dicts as a Markdown table (cells printable, cut to CELL characters)."""
    if not rows:
        return "(none)\n"
    cols = list(rows[0])
    cell = lambda v: printable(str(v).replace("|", "/").replace("\n", " "))[:CELL]
    lines = ["| " + " | ".join(map(cell, cols)) + " |", "|" + "|".join(" --- " for _ in cols) + "|"]
    lines += ["| " + " | ".join(cell(row[c]) for c in cols) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def slug(text):
    """`text` as a file name: lower-case letters and digits, runs of anything else one "-"; past 80
    characters, cut to 71 and ended by 8 hex digits of its SHA-256 (names stay distinct and legal)."""
    name = re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")
    return name if len(name) <= 80 else f"{name[:71]}-{hashlib.sha256(name.encode()).hexdigest()[:8]}"


#: colours of the method families: the dark then the light shades of matplotlib's tab20
PALETTE = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
           "#17becf", "#aec7e8", "#ffbb78", "#98df8a", "#ff9896", "#c5b0d5", "#c49c94", "#f7b6d2", "#c7c7c7",
           "#dbdb8d", "#9edae5")
MARKERS = ("o", "s", "^", "D", "v")


def _shipped_families():
    """The method families of the shipped suites (quick, then full), in suite order."""
    from . import suite as suite_module

    families = []
    for name in ("quick", "full"):
        families += [m.family for m in suite_module.load(name).methods]
    return [f for f in dict.fromkeys(families) if f != SEARCH]


def family_style(families):
    """{family: (colour, marker)}, the same in every chart: the extremal search black; the families
    of the shipped suites in fixed slots of PALETTE (in suite order), then the other families given,
    by name; past the palette the colours repeat with the next marker."""
    order = _shipped_families()
    order += sorted(set(families) - set(order) - {SEARCH})
    styles = {SEARCH: ("#000000", "*")}
    for i, family in enumerate(order):
        styles[family] = (PALETTE[i % len(PALETTE)], MARKERS[i // len(PALETTE) % len(MARKERS)])
    return styles


def work_precision_points(records):
    """{case label: {family: {"curve": [point], "another": [point], "failed": n, "outcomes": Counter}}}
    of the runs with the default guess: a point is (N, solver time, |T - T*|, label); "curve" holds
    the answers with the optimal structure (by N), "another" those on another extremal, labelled
    with N and their class (local optimum, wrong structure, beyond horizon); "outcomes" counts the
    failed runs' outcomes."""
    out = {}
    for case, runs in _by([r for r in records if r.guess == "default"], "case_label").items():
        out[case] = {}
        for family, fr in _by(runs, "family").items():
            good = sorted((r for r in fr if r.outcome in GOOD), key=lambda r: r.N or 0)
            other = [r for r in fr if r.outcome in ANOTHER and r.T_minus_ref is not None]
            point = lambda r: (r.N, r.solver_time_s, error(r), ("search" if r.N is None else f"N={r.N}")
                               + ("" if r.outcome == Outcome.OK else f" ({r.outcome})"))
            failed = Counter(str(r.outcome) for r in fr if r not in good and r not in other)
            out[case][family] = {"curve": [point(r) for r in good], "another": [(*point(r), r.outcome) for r in other],
                                 "failed": sum(failed.values()), "outcomes": failed}
    return out


def _span(values, factor):
    """(lo, hi) of positive `values` widened by `factor` each way on a log axis."""
    return min(values) / factor, max(values) * factor


def place_labels(candidates, obstacles, size, offsets=((4, 3), (4, -9), (-4, 3), (-4, -9), (4, 10), (4, -16))):
    """Where to print the labels of `candidates` [(x, y, text)] (display points) so that no two
    overlap and none covers a point of `obstacles` [(x, y)]: {index: ((dx, dy), ha)} of those that
    fit, first come first served; `size` the font size in points (a character at most 0.65 of it wide)."""
    taken = [(x - 3, y - 3, x + 3, y + 3) for x, y in obstacles]
    placed = {}
    for i, (x, y, text) in enumerate(candidates):
        w, h = 0.65 * size * len(text) + 1, size
        for dx, dy in offsets:
            x0 = x + dx if dx >= 0 else x + dx - w
            box = (x0, y + dy, x0 + w, y + dy + h)
            if not any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in taken):
                taken.append(box)
                placed[i] = ((dx, dy), "left" if dx >= 0 else "right")
                break
    return placed


def _plain_ticks(axis, lo, hi):
    """Tick labels of a log axis as plain numbers (2, 0.5, 100): the minor ticks too where the axis
    spans less than a decade, else those at 2 and 5."""
    from matplotlib.ticker import FuncFormatter

    axis.set_major_formatter(FuncFormatter(lambda x, _: f"{x:g}"))
    short = hi <= 10 * lo                                     # under a decade: every minor tick named, else 2 and 5
    axis.set_minor_formatter(FuncFormatter(lambda x, _: f"{x:g}" if short or f"{x:e}"[0] in "25" else ""))


def work_precision(records, out_dir, formats):
    """One chart per case with the default guess (`work_precision_points`); returns the paths."""
    import textwrap

    import matplotlib.pyplot as plt

    styles = family_style({r.family for r in records})
    paths = []
    for case, families in work_precision_points(records).items():
        order = sorted(families, key=list(styles).index)
        drawn = [f for f in order if families[f]["curve"] or families[f]["another"]]
        direct = [p for f in drawn if f != SEARCH for p in families[f]["curve"] + families[f]["another"]]
        shown = direct or [p for f in drawn for p in families[f]["curve"] + families[f]["another"]]
        notes = []
        with plotting.style():
            fig, ax = plt.subplots(figsize=(9.0, 4.6))
            ax.set_xscale("log")
            ax.set_yscale("log")
            if shown:
                ax.set(xlim=_span([max(p[1], 1e-4) for p in shown], 1.5), ylim=_span([p[2] for p in shown], 3.0))
            else:                                                                   # every run failed
                ax.set(xlim=(1e-2, 1e2), ylim=(1e-12, 1.0))
                ax.text(0.5, 0.5, "no answer on this case", transform=ax.transAxes, ha="center")
            (x_lo, x_hi), (y_lo, y_hi) = ax.get_xlim(), ax.get_ylim()
            classes, labels = set(), []
            for family in drawn:
                d = families[family]
                colour, marker = styles[family]
                n = len(d["curve"]) + len(d["another"]) + d["failed"]
                label = printable(family)[:LABEL] + (f"  ({d['failed']} of {n} failed)" if d["failed"] else "")
                points = d["curve"] + d["another"]
                off = [p for p in points if not (x_lo <= p[1] <= x_hi and y_lo <= p[2] <= y_hi)]
                if off:
                    notes.append(f"off the axes, {printable(family)[:LABEL]}: " + ", ".join(
                        f"{p[3]}: |T - T*| = {p[2]:.0e} in {p[1]:.2g} s" for p in off))
                    label = label if len(off) < len(points) else "_nolegend_"     # no entry without a point
                ax.plot([p[1] for p in d["curve"]], [p[2] for p in d["curve"]], "-", marker=marker, ms=4,
                        color=colour, label=label)
                for _, t, e, _, outcome in d["another"]:
                    classes.add(outcome)
                    ax.plot(t, e, Outcome(outcome).open_marker, mfc="none", ms=6, color=colour)
                labels += [(p, colour) for p in points]
            for name in sorted(classes):
                ax.plot([], [], Outcome(name).open_marker, mfc="none", color="0.3",
                        label=f"open {Outcome(name).open_marker}: {name} (another extremal)")
            at = [(*ax.transData.transform((p[1], p[2])) * 72 / fig.dpi, p[3].split(" (")[0]) for p, _ in labels]
            for i, (offset, ha) in place_labels(at, [(x, y) for x, y, _ in at], 6).items():
                (_, t, e, *_), colour = labels[i]
                ax.annotate(at[i][2], (t, e), textcoords="offset points", xytext=offset, fontsize=6, ha=ha, va="bottom",
                            color=colour)
            for family in order:
                d = families[family]
                if family not in drawn:
                    notes.append(f"no answer, {printable(family)[:LABEL]}: "
                                 + ", ".join(f"{k} {n}" for k, n in d["outcomes"].items()))
            _plain_ticks(ax.xaxis, *ax.get_xlim())
            ax.set_xlabel("solver time per solve (build and NLP solves), median of repeats, cold (s)")
            ax.set_ylabel("|T - T*|   (T*: the complete search's optimum)")
            ax.set_title(f"work precision: {printable(case)[:LABEL]}")
            if ax.get_legend_handles_labels()[0]:          # no legend for a chart of no direct answer
                ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
            if notes:
                fig.text(0.01, -0.02, "\n".join(textwrap.fill(n, 150) for n in notes[:40])[:CELL * 4], fontsize=6,
                         va="top")
            paths += plotting.save(fig, Path(out_dir) / f"work_precision_{slug(case)}", formats)
    return paths


def profiles(records, accuracies=ACCURACIES, budgets=BUDGETS):
    """{"time": [(eps, ratios, unreached)], "error": [(beta, ratios, unreached)], "styles":
    family_style}: the data of the two profile charts (`ocp.bench.profiles`; `unreached` the cases
    no family gets through), among the direct methods (the extremal search is the reference they
    are measured against, not one of them: it is in the work-precision charts)."""
    costs = profile_costs([r for r in records if r.family != SEARCH], accuracies, budgets)
    return {"time": [(eps, performance_profile(costs[("time", eps)]), unreached(costs[("time", eps)]))
                     for eps in accuracies],
            "error": [(beta, performance_profile(costs[("error", beta)]), unreached(costs[("error", beta)]))
                      for beta in budgets],
            "styles": family_style({r.family for r in records})}


def merged_curves(ratios, styles):
    """[(families, ratios)] with the families whose ratios are equal merged into one curve (in
    the order of `styles`), the families that never get there left out."""
    curves = {}
    for family in sorted(ratios, key=list(styles).index):
        r = ratios[family]
        if r and any(map(math.isfinite, r)):
            curves.setdefault(tuple(r), []).append(family)
    return [(families, list(r)) for r, families in curves.items()]


def profile_chart(panels, title, xlabel, out_stem, formats, styles=None):
    """One panel per (subtitle, ratios, unreached) of `panels`, side by side: rho(tau) per family, a
    step function, over every case; identical curves drawn once, their families named together; the
    share of cases no family reaches drawn as a ceiling; the families that never get there named
    under the panels."""
    import textwrap

    import matplotlib.pyplot as plt

    styles = styles or family_style({f for _, ratios, _ in panels for f in ratios})
    never = defaultdict(list)
    with plotting.style():
        fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels) + 2.4, 4.4), sharey=True, squeeze=False)
        for ax, (subtitle, ratios, none) in zip(axes[0], panels):
            finite = [x for r in ratios.values() for x in r if math.isfinite(x)]
            top = max(1.25, 1.25 * max(finite, default=1.0))
            n_cases = max((len(r) for r in ratios.values()), default=0)
            never_here = [f for f, r in ratios.items() if not any(map(math.isfinite, r))]
            for family in never_here:
                never[family].append(subtitle)
            for families, r in merged_curves(ratios, styles):
                taus = [1.0] + sorted({x for x in r if math.isfinite(x)}) + [top]
                rho = [sum(x <= tau for x in r) / len(r) for tau in taus]
                label = "\n  = ".join(printable(f)[:LABEL] for f in families) + (
                    f"  ({len(r)} cases)" if len(r) < n_cases else "")
                ax.step(taus, rho, where="post", color=styles[families[0]][0], label=label)
            if none and n_cases:
                ceiling = 1 - none / n_cases
                ax.axhline(ceiling, color="0.4", ls=":", lw=1.0)
                ax.text(0.02, ceiling + 0.015, f"{none} of {n_cases} cases: no direct method gets there", fontsize=6,
                        color="0.3", transform=ax.get_yaxis_transform())          # above it no curve can rise
            ax.set_xscale("log")
            ax.set_xlim(1.0, top)
            _plain_ticks(ax.xaxis, 1.0, top)
            ax.set_ylim(-0.02, 1.02)
            ax.set_title(f"{subtitle}  ({n_cases} cases)", fontsize=9)
            ax.set_xlabel(xlabel)
        axes[0][0].set_ylabel("share of cases within tau of the best")
        handles = {h.get_label(): h for ax in axes[0] for h in ax.get_lines() if not h.get_label().startswith("_")}
        fig.legend(handles.values(), handles.keys(), loc="upper left", bbox_to_anchor=(1.0, 0.9), fontsize=7)
        fig.suptitle(title)
        if never:
            everywhere = [f for f, where in never.items() if len(where) == len(panels)]
            somewhere = [f"{f} ({', '.join(w)})" for f, w in never.items() if len(w) < len(panels)]
            note = "; ".join(([f"never, in any panel: {', '.join(everywhere)}"] if everywhere else [])
                             + ([f"not in: {'; '.join(somewhere)}"] if somewhere else []))
            fig.text(0.01, -0.02, textwrap.fill(printable(note)[:CELL], 160), fontsize=6, va="top")
        return plotting.save(fig, out_stem, formats)


def write_profiles(data, out_stem_time, out_stem_error, formats):
    """The time and the accuracy profile of `profiles(...)` data; returns the paths."""
    paths = profile_chart([(f"|T - T*| <= {eps:g}", r, none) for eps, r, none in data["time"]],
                          "performance profile of the direct methods: time to reach an accuracy (Dolan and More 2002)",
                          "tau (solver time / the best family's on the case)", out_stem_time, formats, data["styles"])
    paths += profile_chart([(f"budget {beta:g} x the fastest answer", r, none) for beta, r, none in data["error"]],
                           "performance profile of the direct methods: accuracy within a time budget relative to "
                           "the fastest answer",
                           "tau (|T - T*| / the best family's on the case)", out_stem_error, formats, data["styles"])
    return paths


def report(store_path, out_dir=None, budgets=BUDGETS, accuracies=ACCURACIES, formats=("png",)):
    """The report of the store at `store_path`: a dict of tables (and, with `out_dir`, the charts,
    summary.md, results.csv and results.json written there). `budgets`: the accuracy profile's time
    budgets, multiples of the fastest answer on each case; `accuracies`: the time profile's targets
    of |T - T_ref| (each a number or a sequence). The store is opened read-only and every record
    checked before anything is written; each file is written whole (`ocp.core.files`)."""
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
        "timing": sorted({r.timing.note for r in records}),
        "sessions": sessions,
    }
    if out_dir is None:
        return tables
    out = folder(out_dir)
    budgets = tuple(budgets) if isinstance(budgets, (list, tuple)) else (budgets,)
    accuracies = tuple(accuracies) if isinstance(accuracies, (list, tuple)) else (accuracies,)
    charts = work_precision(records, out, formats)
    charts += write_profiles(profiles(records, accuracies, budgets), out / "profile_time", out / "profile_accuracy",
                             formats)
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
             "## Environment (last session)", "", "```", *(f"{k}: {v}"[:CELL] for k, v in env.items()), "```", ""]
    return printable("\n".join(lines), lines=True)
