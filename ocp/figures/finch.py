"""Phase portraits of the minimum-time swing-up (Finch 2015, Figures 1 and 2, and kappa = 3/4),
drawn from the suite's own solutions (`ocp.solve`: the optimum of the complete search of
extremals, and the fastest extremal of another switch count), with Finch's formulas
(`ocp.exact.finch`) marked at the switches.

The paper's convention is the suite's (theta = 0 hanging, nondimensional time), so nothing is
converted. Around the trajectories, the phase-plane context: the equilibria of the free pendulum,
its separatrix omega^2/2 - cos(theta) = 1, and the arcs of u = +1 and u = -1 that end at the
target (pi, 0), the level sets of the arc invariant omega^2/2 - cos(theta) - kappa*u*theta
through it (`ocp.core.model.arc_invariant`).
"""

import math
from dataclasses import dataclass

import matplotlib.pyplot as plt
from matplotlib.legend_handler import HandlerTuple
import numpy as np

from ..core import model, plotting, problem as problems, simulate
from ..core.numbers import digits
from ..exact import finch as analytic
from ..indirect import certify
from ..solving import solve
from .ticks import pi_ticks

XLIM = (-math.pi, 3 * math.pi / 2)
YLIM = (-2.4, 2.4)


@dataclass(frozen=True)
class Trajectory:
    """A refined bang-bang extremal of the swing-up and its dense re-simulation: `arcs` is a list
    of (u, states (m, 2)), `state_error` bounds the error of the switch states (the switch-time
    error estimate times the larger phase speed at the switch), `analytic` is Finch's formula for
    the same structure (`ocp.exact.finch.BangBang`, None where the paper has none)."""

    signs: tuple
    T: float
    T_error: float
    switch_states: np.ndarray
    state_error: float
    certified: bool
    arcs: list
    analytic: object

    @property
    def n_switches(self):
        return len(self.signs) - 1


def trajectory(problem, extremal, samples):
    """The Trajectory of an extremal of `problem` (`ocp.indirect.Extremal`): its error estimate,
    certificate and arcs re-simulated independently (`ocp.core.simulate`) at `samples` points each."""
    x0, kappa = np.asarray(problem.x0, float), problem.kappa
    states = np.array(extremal.switch_states)
    speed = max(np.hypot(*model.rhs(x, u, kappa)) for x in states for u in (-1, 1))
    arcs, x = [], x0
    for u, d in zip(extremal.signs, extremal.durations):
        xs = simulate.piecewise(x, np.linspace(0.0, d, samples), np.full(samples - 1, u), kappa)
        arcs.append((u, xs))
        x = xs[-1]
    return Trajectory(extremal.signs, extremal.T, extremal.T_error, states, extremal.switch_time_error * speed,
                      certify(extremal, x0, kappa).certified, arcs,
                      analytic.formula_for(problem, extremal.branch, extremal.n_switches, extremal.signs[0]))


def level_set(theta, through, u, kappa):
    """omega >= 0 on the level set of the arc invariant of u (u = 0: the energy) through the
    state `through`, at the angles `theta` (nan where the level set does not reach)."""
    w2 = 2 * (model.arc_invariant(through, u, kappa) - model.arc_invariant((theta, 0.0 * theta), u, kappa))
    return np.sqrt(np.where(w2 >= 0, w2, np.nan))


def portrait(kappa, switch_counts, samples=80):
    """Data of a phase portrait: the swing-up from (0, 0) to (pi, 0) for `kappa` solved by
    `ocp.solve`, and for each number of switches in `switch_counts` the fastest extremal of the
    search with that many (a Trajectory); the free pendulum's separatrix (upper branch), the
    arcs into the target for u = +1 (theta > pi, omega < 0) and u = -1 (theta < pi, omega > 0),
    and the equilibria in view."""
    problem = problems.swing_up(kappa, branch=0)
    result = solve(problem)
    trajectories = []
    for n in switch_counts:
        best = next((e for e in result.extremals if e.n_switches == n), None)
        if best is None:
            raise RuntimeError(f"swing-up, kappa = {kappa}: no extremal with {n} switch(es) before the horizon")
        trajectories.append(trajectory(problem, best, samples))
    theta = np.linspace(*XLIM, 721)
    target = problem.target(0)
    below, above = theta[theta <= math.pi], theta[theta >= math.pi]
    angles = np.arange(math.ceil(XLIM[0] / math.pi), math.floor(XLIM[1] / math.pi) + 1) * math.pi
    return {
        "kappa": kappa, "x0": problem.x0, "target": target, "trajectories": trajectories,
        "separatrix": (theta, level_set(theta, target, 0, kappa)),
        "target_arcs": {-1: (below, level_set(below, target, -1, kappa)),
                        +1: (above, -level_set(above, target, +1, kappa))},
        "equilibria": {"stable": [(a, 0.0) for a in angles if round(a / math.pi) % 2 == 0],
                       "unstable": [(a, 0.0) for a in angles if round(a / math.pi) % 2 == 1]},
    }


def figure1():
    """Finch's Figure 1: kappa = 1, one switch."""
    return portrait(1.0, (1,))


def figure2():
    """Finch's Figure 2: kappa = 1/2, two switches."""
    return portrait(0.5, (2,))


def three_quarters():
    """kappa = 3/4: the minimal two-switch transfer and the slower one-switch extremal."""
    return portrait(0.75, (2, 1))


def _fmt(value, error):
    """value with at most 4 decimals, fewer if its error does not defend them; a true minus sign."""
    return digits(value, max(error, 1e-4)).replace("-", "−")


def _signs(signs):
    return " ".join(f"{s:+d}".replace("-", "−") for s in signs)


def _outward(x, u, centre):
    """Unit offset for a label at the switch x: normal to the velocity after the switch (control
    u), on the side away from `centre` (the middle of the trajectory)."""
    f = model.rhs(x, u, 1.0)
    normal = np.array([-f[1], f[0]]) / np.hypot(*f)
    return normal if np.dot(normal, x - centre) >= 0 else -normal


def draw(data, title):
    """The phase portrait of `portrait` data."""
    fig, ax = plt.subplots(figsize=(6.4, 5.6))
    colour = {+1: plotting.U_PLUS, -1: plotting.U_MINUS}
    theta, omega = data["separatrix"]
    separatrix, = ax.plot(theta, omega, color="0.55", ls="--", lw=1.0)
    ax.plot(theta, -omega, color="0.55", ls="--", lw=1.0)
    into = tuple(ax.plot(*data["target_arcs"][u], color=colour[u], ls=":", lw=1.3)[0] for u in (+1, -1))
    stable, = ax.plot(*np.transpose(data["equilibria"]["stable"]), "o", ms=7, mfc="0.6", mec="0.3", zorder=2)
    unstable, = ax.plot(*np.transpose(data["equilibria"]["unstable"]), "o", ms=7, mfc="white", mec="0.3", zorder=2)
    handles = [(separatrix, r"separatrix of the free pendulum, $\omega^2/2 - \cos\theta = 1$"),
               (into, r"u = +1 / −1 arcs into the target, $\omega^2/2 - \cos\theta - \kappa u\theta$ = const"),
               ((stable, unstable), "equilibria of the free pendulum (u = 0): stable, unstable")]
    on = tuple(ax.plot([], [], color=colour[u], lw=2.0)[0] for u in (+1, -1))
    handles.append((on, "trajectory arcs of u = +1 / −1"))
    formulas = []
    for traj, ls in zip(data["trajectories"], ("-", "--")):
        states = np.concatenate([xs for _, xs in traj.arcs])
        centre = 0.5 * (states.min(axis=0) + states.max(axis=0))
        for u, xs in traj.arcs:
            ax.plot(xs[:, 0], xs[:, 1], color=colour[u], ls=ls, lw=2.0, zorder=3)
            mid = len(xs) // 2
            ax.annotate("", xy=xs[mid + 1], xytext=xs[mid - 1],
                        arrowprops=dict(arrowstyle="-|>", color=colour[u], lw=0, mutation_scale=14))
        for x, u in zip(traj.switch_states, traj.signs[1:]):
            dx, dy = _outward(x, u, centre)
            ax.annotate(f"({_fmt(x[0], traj.state_error)}, {_fmt(x[1], traj.state_error)})", x,
                        xytext=(14 * dx, 14 * dy), textcoords="offset points", fontsize=8,
                        ha="left" if dx > 0.3 else "right" if dx < -0.3 else "center",
                        va="bottom" if dy > 0.3 else "top" if dy < -0.3 else "center")
        n = traj.n_switches
        status = "certified extremal" if traj.certified else "NOT certified"
        handles.append((ax.plot([], [], color="black", ls=ls, lw=2.0)[0],
                        f"{n} switch{'es' if n > 1 else ''}, u = {_signs(traj.signs)}: "
                        f"T = {digits(traj.T, max(traj.T_error, 1e-6))} ({status})"))
        if traj.analytic is not None:
            formulas.extend(traj.analytic.switch_states)
    switches = np.concatenate([t.switch_states for t in data["trajectories"]])
    handles.append((ax.plot(*switches.T, "o", color="black", ms=4, zorder=4)[0],
                    "switch (suite: refined, labelled (θ, ω))"))
    if formulas:
        handles.append((ax.plot(*np.transpose(formulas), "o", mfc="none", mec="black", ms=10, zorder=4)[0],
                        "switch by Finch's formula (ocp.exact.finch)"))
    for x, text in ((data["x0"], "start (0, 0)"), (data["target"], "end (π, 0)")):
        ax.annotate(text, x, xytext=(9, 0), textcoords="offset points", fontsize=8, va="center")
    pi_ticks(ax.xaxis, *XLIM)
    ax.set(xlim=XLIM, ylim=YLIM, title=title, xlabel=r"$\theta$ (rad; 0 hanging, π upright)",
           ylabel=r"$\omega = d\theta/dt$ (rad per time unit $\sqrt{I/mg\ell}$)")
    ax.legend(*zip(*handles), handler_map={tuple: HandlerTuple(ndivide=None)},
              loc="upper center", bbox_to_anchor=(0.5, -0.12))
    return fig


def draw_figure1(data):
    return draw(data, "Finch (2015) Fig. 1: minimum-time swing-up, κ = 1")


def draw_figure2(data):
    return draw(data, "Finch (2015) Fig. 2: minimum-time swing-up, κ = 1/2")


def draw_three_quarters(data):
    return draw(data, "Swing-up, κ = 3/4: two switches (the faster) and one switch")
