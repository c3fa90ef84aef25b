"""Maps of the optimal synthesis (`ocp.synthesis.field`): the optimal switch count N(theta, omega)
coloured, the switching curves (switch points of optimal extremals) and the dispersal curves
(where two optimal controls tie), the state where a bifurcation value's region of n + 1
switches is born marked, for kappa just below and just above the value."""

import math

import matplotlib.pyplot as plt
from matplotlib.colors import BoundaryNorm, ListedColormap
import numpy as np

from ..synthesis.field import Window, synthesize
from .ticks import pi_ticks

#: one colour per switch count (uncovered: white)
COUNT_COLOURS = ["#ffffff", "#f0f0f0", "#c6dbef", "#6baed6", "#fdae6b", "#e6550d", "#a63603", "#54278f", "#3f007d"]
#: the maps of `ocp figures`: (name, kind, reading, kappa, window (theta_lo, theta_hi, omega_lo, omega_hi), horizon)
MAPS = (
    ("synthesis-swing-up-circle-0.79", "swing-up", "circle", 0.79, (-math.pi, math.pi, -3.0, 3.0), 10.0),
    ("synthesis-swing-up-circle-0.81", "swing-up", "circle", 0.81, (-math.pi, math.pi, -3.0, 3.0), 10.0),
    ("synthesis-swing-up-circle-0.42", "swing-up", "circle", 0.42, (-math.pi, math.pi, -3.0, 3.0), 16.0),
    ("synthesis-swing-up-circle-0.45", "swing-up", "circle", 0.45, (-math.pi, math.pi, -3.0, 3.0), 16.0),
    ("synthesis-swing-up-circle-0.29", "swing-up", "circle", 0.29, (-math.pi, math.pi, -3.0, 3.0), 20.0),
    ("synthesis-swing-up-circle-0.31", "swing-up", "circle", 0.31, (-math.pi, math.pi, -3.0, 3.0), 20.0),
    ("synthesis-damping-circle-1.0", "damping", "circle", 1.0, (-math.pi, math.pi, -12.0, 12.0), 14.0),
    ("synthesis-damping-circle-1.1", "damping", "circle", 1.1, (-math.pi, math.pi, -12.0, 12.0), 14.0),
    ("synthesis-swing-up-plane-1.0", "swing-up", "plane", 1.0, (-3 * math.pi, 5 * math.pi, -6.0, 6.0), 12.0),
    ("synthesis-damping-plane-1.0", "damping", "plane", 1.0, (-4 * math.pi, 4 * math.pi, -6.0, 6.0), 12.0),
)


def map_data(kind, reading, kappa, window, horizon, resolution=(601, 361)):
    """The Synthesis of a map (the data of the figure)."""
    return synthesize(kind, kappa, reading, Window(*window, *resolution), horizon)


def draw_map(s, marked=None):
    """The figure of a Synthesis `s`; `marked`: states (theta, omega, label) to ring, by default
    where the region of n + 1 switches is born for each stored bifurcation value kappa_n of the
    same problem and reading within 0.05 of s.kappa (the state and its mirror image)."""
    marked = born_states(s) if marked is None else marked
    fig, ax = plt.subplots(figsize=(7.2, 4.8))
    handles, labels = draw_layers(fig, ax, s)
    for theta, omega, label in marked:
        ring = ax.plot(theta, omega, "o", mfc="none", mec="#d62728", ms=11, mew=1.6)[0]
        if label:
            handles.append(ring)
            labels.append(label)
    ax.set_title(f"{s.kind}, κ = {s.kappa:g}, on the {s.reading}: optimal switch count")
    ax.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, -0.14), fontsize=7)
    return fig


def born_states(s):
    """[(theta, omega, label)]: the attaining states of the stored values near s.kappa, in its window."""
    from ..synthesis.results import stored

    w, out = s.window, []
    for row in stored().values():
        if (row["kind"], row["reading"]) != (s.kind, s.reading) or row["kappa"] is None or \
                abs(row["kappa"] - s.kappa) > 0.05:
            continue
        theta, omega = row["state"]
        if s.reading == "circle":
            theta = math.remainder(theta, 2 * math.pi)
        label = f"κ_{row['n']} = {row['kappa']:.6f}: {row['n'] + 1} switches are born here (and at the mirror image)"
        for th, om in ((theta, omega), (-theta, -omega)):
            if w.theta_lo <= th <= w.theta_hi and w.omega_lo <= om <= w.omega_hi:
                out.append((th, om, label if not out or out[-1][2] != label else None))
    return out


def draw_layers(fig, ax, s):
    """The switch counts of a Synthesis `s` coloured on `ax`, its dispersal and switching curves, the
    axes; returns the legend's (handles, labels) of the curves."""
    w = s.window
    top = max(3, int(s.N.max()) + 1)
    extra = top + 2 - len(COUNT_COLOURS)         # more switches than the named colours: darker purples
    cmap = ListedColormap(COUNT_COLOURS[:top + 2] + [plt.get_cmap("Purples")(0.85 + 0.15 * k / extra)
                                                     for k in range(1, extra + 1)])
    norm = BoundaryNorm(np.arange(-1.5, top + 1.5), cmap.N)
    image = ax.imshow(s.N.T, origin="lower", extent=(w.theta_lo, w.theta_hi, w.omega_lo, w.omega_hi),
                      aspect="auto", cmap=cmap, norm=norm, interpolation="nearest")
    bar = fig.colorbar(image, ax=ax, ticks=range(-1, top + 1))
    bar.ax.set_yticklabels(["not reached"] + [str(n) for n in range(0, top + 1)])
    bar.set_label("optimal number of switches N")
    d = np.argwhere(s.dispersal)
    ax.plot(w.theta[d[:, 0]], w.omega[d[:, 1]], ",", color="black", alpha=0.6)
    if len(s.switch_points):
        ax.plot(s.switch_points[:, 0], s.switch_points[:, 1], ".", color="#08306b", ms=1.0)
    handles = [ax.plot([], [], "s", color="black", ms=3)[0], ax.plot([], [], ".", color="#08306b")[0]]
    labels = ["dispersal curve (two optimal controls tie)", "switching curve (switch points of optimal extremals)"]
    pi_ticks(ax.xaxis, w.theta_lo, w.theta_hi)
    ax.set(xlim=(w.theta_lo, w.theta_hi), ylim=(w.omega_lo, w.omega_hi), xlabel=r"$\theta$ (rad; 0 hanging, π upright)",
           ylabel=r"$\omega$")
    return handles, labels
