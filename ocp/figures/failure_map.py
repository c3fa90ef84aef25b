"""Failure maps (`ocp.bench.failure_map`) drawn over the optimal synthesis of the same kappa and
window (`ocp.synthesis.field`): each start a marker coloured by its outcome class, on the optimal
switch counts with the switching and dispersal curves, so that failures are seen where they
gather; and the sweep over kappa: the direct T and the search's optimum against kappa, each point
coloured by its class."""

import math

import matplotlib.pyplot as plt
import numpy as np

from ..bench import failure_map
from ..bench.outcomes import OUTCOMES
from ..bench.suite import Method
from ..synthesis.field import Window, synthesize
from .synthesis import draw_layers

#: the maps of `ocp figures`: (name, kind, kappa, method, window, grid of starts, horizon of the synthesis)
MAPS = (
    ("failure-map-swing-up-1.0-ipopt", "swing-up", 1.0, Method(settings=(("N", 25),)),
     (-math.pi, math.pi, -3.0, 3.0), (13, 9), 12.0),
)


def map_data(kind, kappa, method, window, grid, horizon):
    """(FailureMap over the starts of `window` at `grid`, Synthesis of the same window) of a map."""
    return (failure_map.grid(kind, kappa, method, Window(*window, *grid)),
            synthesize(kind, kappa, "circle", Window(*window, 401, 301), horizon))


def _cells(ax, outcome, x, y):
    """One marker per cell at (x, y) by its outcome (indices into OUTCOMES); the legend's (handles,
    labels) with the counts of the cells drawn."""
    handles, labels = [], []
    for index, count in enumerate(np.bincount(outcome.ravel(), minlength=len(OUTCOMES))):
        if not count:
            continue
        name = OUTCOMES[index]
        at = outcome == index
        handles.append(ax.plot(x[at], y[at], name.marker, ls="none", color=name.colour,
                               mec="white" if name.marker in FILLED else name.colour, mew=0.5 if name.marker in FILLED
                               else 1.5, ms=6)[0])
        labels.append(f"{name} ({count})")
    return handles, labels


#: the filled markers of the outcomes (edged in white); the others are strokes
FILLED = "osDdPXv^"


def _once(theta):
    """The columns of a grid's theta axis that are distinct starts: theta = pi is theta = -pi on the
    circle, so a window spanning 2 pi drops its last column."""
    return len(theta) - 1 if len(theta) > 1 and math.isclose(theta[-1] - theta[0], 2 * math.pi) else len(theta)


def _curve_handles():
    """Legend handles drawn as the synthesis draws its curves (`draw_layers`): the dispersal curve a
    run of faint black pixels, the switching curve a run of small dark blue dots."""
    from matplotlib.lines import Line2D

    return ([Line2D([], [], ls=(0, (1, 1.5)), lw=0.7, color="black", alpha=0.6),
             Line2D([], [], ls=(0, (0.5, 1.5)), lw=2.0, color="#08306b", dash_capstyle="round")],
            ["dispersal curve (two optimal controls tie)", "switching curve (switch points of optimal extremals)"])


def draw_grid(fmap, synthesis):
    """The FailureMap over a window `fmap`, over the Synthesis of the same kappa and window; the
    column theta = pi of a window spanning 2 pi is theta = -pi's, drawn and counted once."""
    fig, ax = plt.subplots(figsize=(7.2, 5.2))
    draw_layers(fig, ax, synthesis)
    n = _once(fmap.axes["theta"])
    theta, omega = np.meshgrid(fmap.axes["theta"][:n], fmap.axes["omega"], indexing="ij")
    cells = _cells(ax, fmap.outcome[:n], theta, omega)
    curves = _curve_handles()
    once = "" if n == len(fmap.axes["theta"]) else " (θ = ±π drawn once)"
    ax.set_title(f"{fmap.label}: outcome from each start, {fmap.kind}, κ = {fmap.kappa:g}{once}", fontsize=9)
    ax.legend(cells[0] + curves[0], cells[1] + curves[1], loc="upper center", bbox_to_anchor=(0.5, -0.14),
              fontsize=7, ncol=3)
    return fig


def draw_sweep(fmap):
    """The FailureMap over kappa `fmap`: T of the direct answer (where there is one) and the optimum."""
    fig, ax = plt.subplots(figsize=(7.2, 4.2))
    kappa = fmap.axes["kappa"]
    ax.plot(kappa, fmap.T_ref, "-", color="#444444", lw=1.0, label="optimum (complete search of extremals)")
    handles, labels = _cells(ax, fmap.outcome, kappa, np.where(np.isfinite(fmap.T), fmap.T, fmap.T_ref))
    start = "the standard start" if fmap.x0 is None else f"({fmap.x0[0]:g}, {fmap.x0[1]:g})"
    ax.set(xlabel="κ", ylabel="T (direct answer; the optimum where there is none)",
           title=f"{fmap.label}: outcome against κ, {fmap.kind} from {start}")
    ax.legend(ax.get_legend_handles_labels()[0] + handles, ["optimum (complete search of extremals)"] + labels,
              fontsize=7, ncol=2)
    return fig
