"""The vibrating-pivot papers (Weinstein; Tam), in their convention (SI units, theta from the
upright; `ocp.scenes.kapitza`): the time histories of Tam's Figure 3 and Weinstein's Figures 4 and
5 as they really are, each beside the paper's verdict and the exact (Floquet) one, and the stability
chart of the upright in the (A, w) plane with the three criteria and the papers' examples."""

import math

import matplotlib.pyplot as plt
import numpy as np

from ..papers import references
from ..scenes import kapitza as scene
from .ticks import pi_ticks

VERDICT = {1: "stable", -1: "unstable"}
READING = {"rad_s": "ω = {value:g} rad/s", "2pi": "ω = 2π·{value:g} rad/s"}


def _examples():
    """The papers' examples on the device (A, l, g of `ocp.scenes.kapitza`), name -> dict(omega in
    rad/s, title, label and tag (short), printed: the paper's verdict (+1 stable, -1 unstable; Tam's Figure
    3 is captioned stable, Weinstein's are read from ocp/papers/data/weinstein_tam.toml), floquet: the
    exact verdict, max_abs_mu: the largest modulus of the Floquet multipliers per drive period)."""
    out = {"tam_fig3": {"omega": scene.FIG3_OMEGA, "printed": 1, "tag": "T3",
                        "label": f"Tam Fig. 3, ω = {scene.FIG3_OMEGA:g} rad/s (assumed)",
                        "title": f"Tam Fig. 3 (parameters not printed; assumed: the device at ω = {scene.FIG3_OMEGA:g} rad/s)"}}
    for fig, value in scene.EXAMPLES.items():
        for reading, factor in scene.READINGS.items():
            omega = READING[reading].format(value=value)
            out[f"weinstein_{fig}_{reading}"] = {
                "omega": factor * value, "printed": int(references.value("weinstein_tam", f"{fig}_stable_{reading}")),
                "tag": f"W{fig[-1]}" + ("×2π" if reading == "2pi" else ""),
                "label": f"Weinstein Fig. {fig[-1]}, {omega}",
                "title": f"Weinstein Fig. {fig[-1]}: “{value:g} Hz·rad” read as {omega}"}
    for case in out.values():
        a, q = scene.mathieu_parameters(scene.A, case["omega"])
        case["floquet"] = scene.stability(scene.A, case["omega"])
        case["max_abs_mu"] = float(np.max(np.abs(scene.multipliers(a, q))))
    return out


def histories():
    """`ocp.scenes.kapitza.figures()` (t in s, theta in rad from the upright), each with the
    verdicts of `_examples`."""
    examples = _examples()
    return {name: {**case, **examples[name]} for name, case in scene.figures().items()}


def stability_chart(n=60, n_upper=24):
    """`ocp.scenes.kapitza.chart(n)` (critical frequencies in rad/s against A in m), the upper
    Floquet boundary again at `n_upper` amplitudes from the last one of the chart where it is
    infinite (`A_upper`, `upper`: it rises to infinity at A/l = 0.454), and the papers' examples
    (`points`, as in `_examples`) at the device's amplitude `A_device`."""
    data = scene.chart(n)
    start = data["A"][np.isfinite(data["floquet_upper"]).argmax() - 1]
    A_upper = np.geomspace(start, data["A"][-1], n_upper)
    upper = np.array([scene.critical_frequencies(amp)[1] for amp in A_upper])
    return {**data, "A_upper": A_upper, "upper": upper, "A_device": scene.A, "l": scene.L, "points": _examples()}


def draw_histories(data):
    layout = [["tam_fig3", "tam_fig3"], ["weinstein_fig4_rad_s", "weinstein_fig4_2pi"],
              ["weinstein_fig5_rad_s", "weinstein_fig5_2pi"]]
    fig, axes = plt.subplot_mosaic(layout, figsize=(9.6, 9.0))
    for name, ax in axes.items():
        case = data[name]
        wrong = case["printed"] != case["floquet"]
        ax.plot(case["t"], case["theta"], lw=0.6, color="#d62728" if case["floquet"] < 0 else "#1f77b4")
        ax.set(title=case["title"], xlabel="t (s)", ylabel=r"$\theta$ (rad from the upright)", xlim=(0, case["t"][-1]))
        ax.title.set_fontsize(9)
        if case["floquet"] < 0:
            ax.set_ylim(-math.pi / 2 - 0.3, 3.2 * math.pi)
            pi_ticks(ax.yaxis, -math.pi / 2, 2 * math.pi)
        mu = "|μ| = 1" if case["floquet"] > 0 else f"max |μ| = {case['max_abs_mu']:.4f} per period"
        ax.text(0.02, 0.96, f"printed: {VERDICT[case['printed']]}\nFloquet: {VERDICT[case['floquet']]}, {mu}"
                + ("\nthe caption is wrong" if wrong else ""), transform=ax.transAxes, va="top", fontsize=8,
                bbox=dict(boxstyle="round", fc="#fde0dc" if wrong else "white", ec="0.6"))
    fig.suptitle(f"Pendulum on a vibrating pivot, l = {scene.L:g} m, A = {1e3 * scene.A:g} mm, g = {scene.G:g} m/s², "
                 "from θ = 0.1 rad at rest (papers' convention: θ = 0 upright)\n"
                 "Tam (20) integrated as it stands, no ground: a pendulum that falls swings on through the hanging "
                 "position (θ = π)", fontsize=10)
    fig.tight_layout()
    return fig


def draw_stability_chart(data):
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    A, top = 1e3 * data["A"], 3e4
    upper = np.minimum(data["upper"], top)
    band = np.union1d(A, 1e3 * data["A_upper"])
    ax.fill_between(band, np.interp(band, A, data["floquet_lower"]), np.interp(band, 1e3 * data["A_upper"], upper, left=top),
                    color="#2ca02c", alpha=0.15, lw=0)
    ax.plot(A, data["floquet_lower"], color="black", label="exact boundaries (Floquet): stable in the shaded band")
    ax.plot(1e3 * data["A_upper"], upper, color="black")
    ax.plot(A, data["kapitza"], color="#1f77b4", ls="--", label=r"Kapitza: $A^2\omega^2 = 2 g l$")
    ax.plot(A, data["tam"], color="#d62728", ls="-.", label=r"Tam (31): $\omega^2 = \sqrt{2}\, g/A$")
    device = 1e3 * data["A_device"]
    for p in data["points"].values():
        ax.plot(device, p["omega"], "o", ms=6, mec="black", mfc="black" if p["floquet"] > 0 else "white", zorder=4)
        ax.annotate(p["tag"], (device, p["omega"]), xytext=(7, 0), textcoords="offset points", va="center", fontsize=8)
    key = "\n".join(f"{p['tag']}: {p['label']}, captioned {VERDICT[p['printed']]}"
                    for p in sorted(data["points"].values(), key=lambda p: -p["omega"]))
    ax.text(0.02, 0.02, key, transform=ax.transAxes, fontsize=7, va="bottom",
            bbox=dict(boxstyle="round", fc="white", ec="0.6"))
    ax.plot([], [], "o", mec="black", mfc="black",
            label=f"papers' examples (A = {device:g} mm): filled stable, open unstable (exact)")
    ax.set(xscale="log", yscale="log", xlim=(A[0], A[-1]), ylim=(5, top), xlabel="pivot amplitude A (mm)",
           ylabel="drive frequency ω (rad/s)", title=f"Stability of the upright on a vibrating pivot, l = {data['l']:g} m")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1))
    return fig
