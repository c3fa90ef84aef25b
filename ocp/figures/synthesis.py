"""Maps of the optimal synthesis (`ocp.synthesis.field`): the optimal switch count N(theta, omega)
coloured, the switching curves (switch points of optimal extremals) and the dispersal curves
(where two optimal controls tie), for kappa just below and just above a bifurcation value; where
the value's region of n + 1 switches is born, a zoom beside the map (a finer synthesis of the zoom
window) shows the attaining state, the region outlined and its size, or says that it is absent."""

import math
from dataclasses import dataclass, replace

import matplotlib.pyplot as plt
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.patches import Rectangle
from matplotlib.ticker import MaxNLocator, ScalarFormatter
import numpy as np
from scipy.ndimage import label

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


#: the grid of a zoom's own synthesis (`map_data`)
ZOOM_GRID = (161, 161)


def map_data(kind, reading, kappa, window, horizon, resolution=(601, 361)):
    """The data of a map figure: the Synthesis on the window, and one on the zoom of each region
    born near it (`born_regions`) at ZOOM_GRID, finer than the map's."""
    s = synthesize(kind, kappa, reading, Window(*window, *resolution), horizon)
    return s, tuple(synthesize(kind, kappa, reading, Window(*b.zoom, *ZOOM_GRID), horizon) for b in born_regions(s))


#: a region is the attaining state's when one of its cells is within REACH cells of it; a zoom
#: shows at least LEAST (theta, omega) or LEAST_CELLS cells about the state, whichever is larger
REACH, LEAST, LEAST_CELLS = 3, (0.12, 0.12), 8
ZOOM_COLOUR = "#d62728"


@dataclass(frozen=True)
class Born:
    """Where the region of `switches` switches is born at a bifurcation value `kappa_n` (`label`),
    in a Synthesis: the attaining `state` (theta, omega) in the window and its `mirror` image (the
    same region by the symmetry (theta, omega) -> (-theta, -omega); None outside the window), the
    `region`: the connected cells (8 neighbours) of that count within REACH cells of the state and
    of its mirror image (a boolean array of the grid), the `cells` and `area` (rad^2 per time
    unit) of the state's part, the grid's `steps` (d theta, d omega), and the `zoom` (theta_lo,
    theta_hi, omega_lo, omega_hi) that shows the state and its part."""

    label: str
    kappa_n: float
    switches: int
    state: tuple
    mirror: tuple | None
    region: np.ndarray
    cells: int
    area: float
    steps: tuple
    zoom: tuple

    def describe(self):
        grid = f"cells {self.steps[0]:.2g} × {self.steps[1]:.2g}"
        if self.cells:
            return f"N = {self.switches} at the state: {self.cells} cells ({grid}), about {self.area:.2g} rad²/time unit"
        return f"no cell with N = {self.switches} at the state ({grid})"


def born_regions(s):
    """[Born] of the stored bifurcation values kappa_n within 10 % of s.kappa (same problem and
    reading) whose attaining state is in the window."""
    from ..synthesis.results import stored

    w, out = s.window, []
    for row in stored().values():
        if (row["kind"], row["reading"]) != (s.kind, s.reading) or row["kappa"] is None or \
                abs(row["kappa"] - s.kappa) > 0.1 * row["kappa"]:          # a plane row has no value
            continue
        th, om = row["state"]
        if s.reading == "circle":
            th = math.remainder(th, 2 * math.pi)
        inside = [(a, b) for a, b in ((th, om), (-th, -om))
                  if w.theta_lo <= a <= w.theta_hi and w.omega_lo <= b <= w.omega_hi]
        if inside:
            out.append(_born(s, f"κ_{row['n']} = {row['kappa']:.6f}", row["kappa"], row["n"] + 1, inside))
    return out


def _born(s, label, kappa_n, n, inside):
    """The Born of the states `inside` (the attaining state, its mirror image if in the window)."""
    w = s.window
    dt, dw = w.steps
    theta, omega = np.meshgrid(w.theta, w.omega, indexing="ij")
    (th, om) = inside[0]
    own = _region(s.N == n, (theta - th) / (REACH * dt), (omega - om) / (REACH * dw))
    region = own.copy()
    for a, b in inside[1:]:
        region |= _region(s.N == n, (theta - a) / (REACH * dt), (omega - b) / (REACH * dw))
    ht, hw = max(LEAST[0], LEAST_CELLS * dt), max(LEAST[1], LEAST_CELLS * dw)
    t_lo, t_hi, w_lo, w_hi = th - ht, th + ht, om - hw, om + hw
    if own.any():
        pad_t, pad_w = 0.25 * np.ptp(theta[own]) + 2 * dt, 0.25 * np.ptp(omega[own]) + 2 * dw
        t_lo, t_hi = min(t_lo, theta[own].min() - pad_t), max(t_hi, theta[own].max() + pad_t)
        w_lo, w_hi = min(w_lo, omega[own].min() - pad_w), max(w_hi, omega[own].max() + pad_w)
    zoom = (max(t_lo, w.theta_lo), min(t_hi, w.theta_hi), max(w_lo, w.omega_lo), min(w_hi, w.omega_hi))
    return Born(label, kappa_n, n, (th, om), inside[1] if len(inside) > 1 else None, region, int(own.sum()),
                float(own.sum() * dt * dw), (dt, dw), zoom)


def _region(mask, x, y):
    """The connected part (8 neighbours) of `mask` nearest the origin of the scaled offsets (x, y),
    if any cell of it lies within |x|, |y| <= 1; else nothing."""
    parts, count = label(mask, structure=np.ones((3, 3)))
    distance = np.where(mask, np.maximum(abs(x), abs(y)), np.inf)
    nearest = np.unravel_index(np.argmin(distance), mask.shape)
    if not count or distance[nearest] > 1:
        return np.zeros_like(mask)
    return parts == parts[nearest]


def draw_map(s, zooms=()):
    """The figure of a Synthesis `s`; where the region of n + 1 switches is born at a stored
    bifurcation value kappa_n within 10 % of s.kappa (`born_regions`), a zoom beside the map on
    the attaining state (drawn from `zooms`, the finer syntheses of `map_data`, where given), its
    frame on the map (and at the mirror image), the region outlined and its size said, or that it
    is absent on this side of kappa_n."""
    regions = born_regions(s)
    fig = plt.figure(figsize=(7.2 + 3.4 * bool(regions), 4.8))
    grid = fig.add_gridspec(max(len(regions), 1), 2, width_ratios=(7.2, 3.0), wspace=0.5)
    ax = fig.add_subplot(grid[:, 0]) if regions else fig.add_subplot()
    handles, labels = draw_layers(fig, ax, s)
    for k, born in enumerate(regions):
        n = born.switches
        side = "below" if s.kappa < born.kappa_n else "above"
        z = born.zoom
        frames = [z] + ([] if born.mirror is None or (z[0] <= born.mirror[0] <= z[1] and z[2] <= born.mirror[1] <= z[3])
                        else [(-z[1], -z[0], -z[3], -z[2])])
        for lo_t, hi_t, lo_w, hi_w in frames:
            ax.add_patch(Rectangle((lo_t, lo_w), hi_t - lo_t, hi_w - lo_w, fill=False, ec=ZOOM_COLOUR, lw=1.4, zorder=5))
        zoom_ax = fig.add_subplot(grid[k, 1])
        if born.region.any():
            ax.contour(s.window.theta, s.window.omega, born.region.T.astype(float), levels=[0.5], colors=ZOOM_COLOUR,
                       linewidths=1.0, zorder=6)
        fine = zooms[k] if zooms else s
        if zooms:                                    # the zoom's own synthesis: its cells counted there
            w = fine.window
            inside = [x for x in (born.state, born.mirror)
                      if x is not None and w.theta_lo <= x[0] <= w.theta_hi and w.omega_lo <= x[1] <= w.omega_hi]
            born = replace(_born(fine, born.label, born.kappa_n, n, inside), zoom=born.zoom)
        draw_layers(fig, zoom_ax, fine, colorbar=False)
        if born.region.any():
            zoom_ax.contour(fine.window.theta, fine.window.omega, born.region.T.astype(float), levels=[0.5],
                            colors=ZOOM_COLOUR, linewidths=1.2, zorder=6)
        handles.append(ax.plot([], [], "s", mfc="none", mec=ZOOM_COLOUR, ms=9, mew=1.4)[0])
        labels.append(f"{born.label}: where {n} switches are born (+, and its mirror image), zoomed at the right")
        zoom_ax.plot(*born.state, "+", color="black", ms=12, mew=1.6, zorder=6)
        zoom_ax.set(xlim=born.zoom[:2], ylim=born.zoom[2:], xlabel=r"$\theta$", ylabel=r"$\omega$")
        zoom_ax.xaxis.set_major_locator(MaxNLocator(4))
        zoom_ax.xaxis.set_major_formatter(ScalarFormatter())
        for spine in zoom_ax.spines.values():
            spine.set(edgecolor=ZOOM_COLOUR, linewidth=1.4)
        zoom_ax.set_title(f"zoom: κ = {s.kappa:g} is {side} {born.label}\n{born.describe()}", fontsize=8)
    ax.set_title(f"{s.kind}, κ = {s.kappa:g}, on the {s.reading}: optimal switch count")
    ax.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, -0.14), fontsize=7)
    return fig


def draw_layers(fig, ax, s, colorbar=True):
    """The switch counts of a Synthesis `s` coloured on `ax` (with their colour bar), its dispersal and
    switching curves, the axes; returns the legend's (handles, labels) of the curves."""
    w = s.window
    top = max(3, int(s.N.max()) + 1)
    extra = top + 2 - len(COUNT_COLOURS)         # more switches than the named colours: darker purples
    cmap = ListedColormap(COUNT_COLOURS[:top + 2] + [plt.get_cmap("Purples")(0.85 + 0.15 * k / extra)
                                                     for k in range(1, extra + 1)])
    norm = BoundaryNorm(np.arange(-1.5, top + 1.5), cmap.N)
    image = ax.imshow(s.N.T, origin="lower", extent=(w.theta_lo, w.theta_hi, w.omega_lo, w.omega_hi),
                      aspect="auto", cmap=cmap, norm=norm, interpolation="nearest")
    if colorbar:
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
