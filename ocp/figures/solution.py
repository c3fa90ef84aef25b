"""One solution drawn and exported (`ocp solve ... --sample DT --csv FILE --plot FILE`): the phase
portrait (arcs coloured by u, the switch points, the start and the target) beside theta, omega and
u against t, the direct answer overlaid on the optimum when there is one; the samples
(`Solution.sample`) as CSV or in the JSON."""

from dataclasses import dataclass
from pathlib import Path

from matplotlib.legend_handler import HandlerTuple
import matplotlib.pyplot as plt
import numpy as np

from ..core import plotting
from ..core.errors import InputError, finite
from ..core.problem import angle_text
from ..core.numbers import digits, order, plus_minus
from ..direct.structure import pattern
from ..result import Source, sample_direct
from .ticks import pi_ticks

#: points drawn per trajectory (the switches and the final time added)
DRAWN = 600
DIRECT_COLOUR = "#ff7f0e"


def _u_text(signs):
    return pattern(signs).replace("-", "−")


def draw(sol):
    """The figure of a successful Solution: its answer, and its direct answer when that is another."""
    best = sol.sample(every=sol.T / DRAWN) if sol.T > 0 else sol.sample(t=[0.0])     # T = 0: a start on the target
    other = None
    if sol.direct is not None and sol.direct.success and sol.best.source is Source.SEARCH:
        other = sample_direct(sol.problem, sol.direct, every=sol.direct.T / DRAWN)
    fig = plt.figure(figsize=(11.0, 5.4))
    grid = fig.add_gridspec(3, 2, width_ratios=(1.15, 1.0), hspace=0.12, wspace=0.22)
    ax = fig.add_subplot(grid[:, 0])
    panels = [fig.add_subplot(grid[0, 1])]
    panels += [fig.add_subplot(grid[k, 1], sharex=panels[0]) for k in (1, 2)]
    colour = {+1: plotting.U_PLUS, -1: plotting.U_MINUS}
    answer = sol.best
    # the phase portrait: each arc in its control's colour
    for key, sel in _arcs(best):
        c = colour.get(key, "black")
        th, om = best.theta[sel], best.omega[sel]
        ax.plot(th, om, color=c, lw=2.0, zorder=3)
        mid = len(th) // 2
        if len(th) > 4:
            ax.annotate("", xy=(th[mid + 1], om[mid + 1]), xytext=(th[mid - 1], om[mid - 1]),
                        arrowprops=dict(arrowstyle="-|>", color=c, lw=0, mutation_scale=14), zorder=3)
    handles = [(tuple(ax.plot([], [], color=colour[u], lw=2.0)[0] for u in (+1, -1)),
                f"{'optimum' if sol.optimal else 'answer'} ({answer.source}): u = {_u_text(answer.arc_signs)}, "
                f"T = {digits(answer.T, answer.T_error) if answer.source is Source.SEARCH else _direct_T(sol.direct)}")]
    if answer.switch_states:
        switches = np.array(answer.switch_states)
        handles.append((ax.plot(*switches.T, "o", color="black", ms=5, zorder=5)[0], "switch points"))
        for i, (th, om) in enumerate(switches, 1):
            ax.annotate(str(i), (th, om), xytext=(6, 6), textcoords="offset points", fontsize=8)
    if other is not None:
        d = sol.direct
        handles.append((ax.plot(other.theta, other.omega, color=DIRECT_COLOUR, ls="--", lw=1.3, zorder=4)[0],
                        f"direct ({d.method['transcription']}, N = {len(d.u)}, {d.method['solver']}): "
                        f"u = {_u_text(d.structure.arc_signs)}, T = {_direct_T(d)}"
                        + ("" if sol.direct_class is None else f": {str(sol.direct_class).replace('_', ' ')}")))
        end = sol.problem.target(d.branch)
        if tuple(end) != tuple(sol.target):
            ax.plot(*end, "*", mfc="white", mec=DIRECT_COLOUR, mew=1.4, ms=13, zorder=6)
    x0, target = sol.problem.x0, sol.target
    handles.append((ax.plot(*x0, "s", mfc="white", mec="black", ms=7, zorder=6)[0], f"start ({x0[0]:g}, {x0[1]:g})"))
    handles.append((ax.plot(*target, "*", color="#2ca02c", mec="black", ms=13, zorder=6)[0],
                    f"target (θ, ω) = ({angle_text(target[0]).replace('pi', 'π').replace('-', '−')}, 0)"
                    + ("" if other is None or sol.direct.branch == answer.branch else "; hollow: the direct answer's")))
    lo, hi = _span(best, other, target, x0)
    theta = np.linspace(lo - 0.3, hi + 0.3, 721)
    w = np.sqrt(np.maximum(2 * (1 + np.cos(theta)), 0.0))
    sep, = ax.plot(theta, w, color="0.6", ls=":", lw=1.0, zorder=1)
    ax.plot(theta, -w, color="0.6", ls=":", lw=1.0, zorder=1)
    handles.append((sep, r"separatrix of the free pendulum, $\omega^2/2 - \cos\theta = 1$"))
    pi_ticks(ax.xaxis, lo - 0.3, hi + 0.3)
    ax.set(xlim=(lo - 0.3, hi + 0.3), xlabel=r"$\theta$ (rad; 0 hanging, π upright)", ylabel=r"$\omega$ (rad per time unit)",
           title="phase portrait")
    ax.legend(*zip(*handles), handler_map={tuple: HandlerTuple(ndivide=None)}, loc="upper center",
              bbox_to_anchor=(0.5, -0.11), fontsize=8)
    # against t
    labels = (r"$\theta$", r"$\omega$", "u")
    for panel, name, label in zip(panels, ("theta", "omega", "u"), labels):
        values = getattr(best, name)
        if name == "u":
            panel.step(best.t, values, where="post", color="black", lw=1.5)
        else:
            panel.plot(best.t, values, color="black", lw=1.5)
        if other is not None:
            v = getattr(other, name)
            (panel.step(other.t, v, where="post", color=DIRECT_COLOUR, ls="--", lw=1.2) if name == "u"
             else panel.plot(other.t, v, color=DIRECT_COLOUR, ls="--", lw=1.2))
        for tau in answer.switch_times:
            panel.axvline(tau, color="0.5", lw=0.8, ls=":")
        panel.set_ylabel(label)
    panels[0].axhline(target[0], color="#2ca02c", lw=0.8, ls="--")
    pi_ticks(panels[0].yaxis, *panels[0].get_ylim())
    panels[2].set(ylim=(-1.25, 1.25), yticks=(-1, 0, 1), xlabel="t (time units; dotted: the switches)")
    for panel in panels[:2]:
        panel.tick_params(labelbottom=False)
    panels[0].set_title("against time" + ("" if other is None else " (dashed: the direct answer)"))
    p = sol.problem
    fig.suptitle(f"{p.kind}, κ = {p.kappa:g}, on the {p.reading}: {str(sol.status).replace('_', ' ')}, "
                 f"{answer.n_switches} switch{'es' if answer.n_switches != 1 else ''}", y=0.99)
    return fig


def _arcs(samples):
    """(+1, -1 or 0, boolean mask) of each run of u = +1, u = -1 (within 1e-3) or interior u, each
    run closed by the next run's first sample."""
    key = np.where(np.abs(np.abs(samples.u) - 1) < 1e-3, np.sign(samples.u), 0).astype(int)
    change = np.flatnonzero(np.diff(key)) + 1
    bounds = np.r_[0, change, len(samples.t)]
    for a, b in zip(bounds[:-1], bounds[1:]):
        sel = np.zeros(len(samples.t), bool)
        sel[a:min(b + 1, len(samples.t))] = True
        yield int(key[a]), sel


def _span(best, other, target, x0):
    """The theta range of everything drawn."""
    values = [best.theta, [target[0], x0[0]]] + ([] if other is None else [other.theta])
    return min(np.min(v) for v in values), max(np.max(v) for v in values)


def _direct_T(d):
    return plus_minus(d.T, d.T_bound) if d.T_bound else digits(d.T, None)


@dataclass(frozen=True)
class Export:
    """What `ocp solve` is asked to export, checked before the solve: a sample spacing (None: no
    samples), a CSV path, a figure path (its suffix the format)."""

    every: float | None
    csv: Path | None
    plot: Path | None

    @classmethod
    def of(cls, sample, csv, plot, json):
        """From the command line's --sample DT, --csv FILE, --plot FILE and --json (InputError if they
        do not go together)."""
        every = None if sample is None else finite("sample", sample, "a spacing from 1e-4 to 10 time units", 1e-4, 10)
        if csv is not None and every is None:
            raise InputError("--csv FILE writes the samples: add --sample DT (the spacing, e.g. 0.01)")
        if every is not None and csv is None and not json:
            raise InputError("--sample DT: add --csv FILE (the samples as CSV) or --json (the samples in the object)")
        if plot is not None and Path(plot).suffix.lstrip(".") not in plotting.FORMATS:
            raise InputError(f"--plot {plot!r}: the file name must end in one of .{', .'.join(plotting.FORMATS)}")
        return cls(every, None if csv is None else Path(csv), None if plot is None else Path(plot))

    def write(self, sol):
        """({"samples": ...} for the JSON, lines to print) of the exports of a Solution; a failed
        solve has nothing to export (one line says so)."""
        if self.every is None and self.plot is None:
            return {}, []
        if not sol.success:
            return {}, [f"nothing exported: {sol.message}"]
        out, lines = {}, []
        if self.every is not None:
            samples = sol.sample(every=self.every)
            out["samples"] = samples.to_dict()
            lines.append(f"sampled at {len(samples.t)} time{'s' if len(samples.t) != 1 else ''} ({samples.source}): state error below "
                         f"{order(samples.state_error)} (estimate), its end {order(samples.miss)} from the target")
            if self.csv is not None:
                lines.append(f"samples written to {samples.write_csv(self.csv)}")
        if self.plot is not None:
            with plotting.style():
                path, = plotting.save(draw(sol), self.plot.with_suffix(""), (self.plot.suffix.lstrip("."),))
            lines.append(f"figure written to {path}")
        return out, lines
