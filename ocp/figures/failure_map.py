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


def _cells(ax, fmap, x, y):
    """One marker per cell at (x, y) by outcome; the legend's (handles, labels) with the counts."""
    handles, labels = [], []
    for name, count in fmap.counts().items():
        colour, marker = name.colour, name.marker
        at = fmap.outcome == OUTCOMES.index(name)
        handles.append(ax.plot(x[at], y[at], marker, ls="none", color=colour, mec="white" if marker in "osDPXv" else colour,
                               mew=0.5, ms=6)[0])
        labels.append(f"{name} ({count})")
    return handles, labels


def draw_grid(fmap, synthesis):
    """The FailureMap over a window `fmap`, over the Synthesis of the same kappa and window."""
    fig, ax = plt.subplots(figsize=(7.2, 5.2))
    curves = draw_layers(fig, ax, synthesis)
    theta, omega = np.meshgrid(fmap.axes["theta"], fmap.axes["omega"], indexing="ij")
    cells = _cells(ax, fmap, theta, omega)
    ax.set_title(f"{fmap.label}: outcome from each start, {fmap.kind}, κ = {fmap.kappa:g}", fontsize=9)
    ax.legend(cells[0] + curves[0], cells[1] + curves[1], loc="upper center", bbox_to_anchor=(0.5, -0.14),
              fontsize=7, ncol=3)
    return fig


def draw_sweep(fmap):
    """The FailureMap over kappa `fmap`: T of the direct answer (where there is one) and the optimum."""
    fig, ax = plt.subplots(figsize=(7.2, 4.2))
    kappa = fmap.axes["kappa"]
    ax.plot(kappa, fmap.T_ref, "-", color="#444444", lw=1.0, label="optimum (complete search of extremals)")
    handles, labels = _cells(ax, fmap, kappa, np.where(np.isfinite(fmap.T), fmap.T, fmap.T_ref))
    start = "the standard start" if fmap.x0 is None else f"({fmap.x0[0]:g}, {fmap.x0[1]:g})"
    ax.set(xlabel="κ", ylabel="T (direct answer; the optimum where there is none)",
           title=f"{fmap.label}: outcome against κ, {fmap.kind} from {start}")
    ax.legend(ax.get_legend_handles_labels()[0] + handles, ["optimum (complete search of extremals)"] + labels,
              fontsize=7, ncol=2)
    return fig
