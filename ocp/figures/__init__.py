"""`ocp figures`: every figure of the suite, in one style (`ocp.core.plotting`), as PNG and PDF.

Each figure is a data function (plain arrays and points, tested in tests/test_figures.py) and a
drawing. The papers' figures are computed by the suite itself: the swing-up phase portraits from
certified solutions (Finch 2015), the falling integral (Batista and Peternelj 2006), the
vibrating-pivot time histories and stability chart (Weinstein; Tam). The suite's own figures are
drawn from a benchmark results store (`ocp bench`) by `ocp.bench.report`.
"""

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ..core import plotting
from ..core.errors import InputError
from ..core.heartbeat import heartbeat
from . import batista, failure_map, finch, suite, synthesis, vibrating_pivot


@dataclass(frozen=True)
class Figure:
    """`data()` (or `data(store)` when `from_store`) and `write(data, stem, formats) -> paths`."""

    about: str
    data: Callable
    write: Callable
    from_store: bool = False


def _drawn(draw):
    """write() for a drawing function draw(data) -> matplotlib figure."""
    def write(data, stem, formats):
        with plotting.style():
            return plotting.save(draw(data), stem, formats)
    return write


FIGURES = {
    "finch-fig1": Figure("swing-up phase portrait, kappa = 1, one switch (Finch 2015, Fig. 1)",
                         finch.figure1, _drawn(finch.draw_figure1)),
    "finch-fig2": Figure("swing-up phase portrait, kappa = 1/2, two switches (Finch 2015, Fig. 2)",
                         finch.figure2, _drawn(finch.draw_figure2)),
    "finch-kappa-3-4": Figure("swing-up phase portrait, kappa = 3/4: the two-switch and the one-switch extremals",
                              finch.three_quarters, _drawn(finch.draw_three_quarters)),
    "batista-fig1": Figure("falling integral I(theta0) and its asymptote (18) (Batista and Peternelj 2006, Fig. 1)",
                           batista.figure1, _drawn(batista.draw_figure1)),
    "pivot-histories": Figure("time histories of Tam's Fig. 3 and Weinstein's Figs. 4 and 5, both unit readings",
                              vibrating_pivot.histories, _drawn(vibrating_pivot.draw_histories)),
    "pivot-chart": Figure("stability chart of the upright on a vibrating pivot: Tam, Kapitza, exact Floquet",
                          vibrating_pivot.stability_chart, _drawn(vibrating_pivot.draw_stability_chart)),
    **{name: Figure(f"optimal synthesis: switch counts, switching and dispersal curves ({kind}, {reading}, kappa = {kappa:g})",
                    lambda k=kind, r=reading, kp=kappa, w=window, h=horizon: synthesis.map_data(k, r, kp, w, h),
                    _drawn(lambda d: synthesis.draw_map(*d)))
       for name, kind, reading, kappa, window, horizon in synthesis.MAPS},
    **{name: Figure(f"failure map: the outcome of {method.label} from a grid of starts over the optimal synthesis "
                    f"({kind}, kappa = {kappa:g})",
                    lambda k=kind, kp=kappa, m=method, w=window, g=grid, h=horizon: failure_map.map_data(k, kp, m, w, g, h),
                    _drawn(lambda d: failure_map.draw_grid(*d)))
       for name, kind, kappa, method, window, grid, horizon in failure_map.MAPS},
    "work-precision": Figure("work-precision charts, one a benchmark case (from a results store)",
                             suite.records, suite.write_work_precision, from_store=True),
    "profiles": Figure("performance profiles across the benchmark cases (from a results store): profile_time "
                       "and profile_accuracy, the names of `ocp report`",
                       suite.profiles, lambda data, stem, formats: suite.write_profiles(data, stem.with_name("profile"),
                                                                                        formats),
                       from_store=True),
}


def listing():
    """The figures' names and what each shows, a line each (`ocp figures --help`)."""
    width = max(map(len, FIGURES))
    return "figures (--only NAME):\n" + "\n".join(f"  {name:<{width}}  {fig.about}" for name, fig in FIGURES.items())


def write(out_dir, only=None, formats=("png", "pdf"), store=None, progress=None):
    """Write the figures named in `only` (default: all) to out_dir; returns {name: paths or the
    reason it was skipped}. The store figures need `store`, an `ocp bench` results file: without
    one they are skipped, unless named in `only` (then InputError). `progress`: a stream that gets
    a line per figure as it is done, with its time, and one every few seconds while a long one runs
    (`ocp.core.heartbeat`; a failure leaves only its one-line error)."""
    names = list(FIGURES) if not only else list(dict.fromkeys(only))
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        raise InputError(f"unknown figure {unknown[0]!r}; accepted: {', '.join(FIGURES)}")
    for fmt in formats:
        if fmt not in plotting.FORMATS:
            raise InputError(f"unknown figure format {fmt!r}; accepted: {', '.join(plotting.FORMATS)}")
    out = {}
    for n, name in enumerate(names, 1):
        fig = FIGURES[name]
        begun = time.perf_counter()
        if fig.from_store and (store is None or not Path(store).is_file()):
            if only:
                raise InputError(f"figure {name!r} needs a results store: --store PATH (written by `ocp bench`)"
                                 + (f"; there is none at {store}" if store else ""))
            out[name] = f"skipped: no results store{f' at {store}' if store else ''} (run `ocp bench`, then --store PATH)"
            if progress:
                print(f"[{n}/{len(names)}] {name}: skipped (no results store)", file=progress, flush=True)
            continue
        with heartbeat(progress, lambda: f"[{n}/{len(names)}] {name}: running"):
            data = fig.data(store) if fig.from_store else fig.data()
            out[name] = fig.write(data, Path(out_dir) / name, formats)
        if progress:
            print(f"[{n}/{len(names)}] {name}: {time.perf_counter() - begun:.1f} s", file=progress, flush=True)
    return out
