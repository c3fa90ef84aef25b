"""One look for every chart of the suite, and deterministic files (same data, same bytes).

    with plotting.style():
        fig, ax = plt.subplots()
        ...
        paths = plotting.save(fig, out_dir / "name", formats=("png", "pdf"))
"""

import contextlib
from pathlib import Path

from .files import replacing

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend is chosen first)

RC = {
    "figure.figsize": (6.4, 4.4),
    "figure.dpi": 100,
    "savefig.dpi": 150,
    "font.size": 10,
    "axes.titlesize": 11,
    "axes.labelsize": 10,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.fontsize": 8,
    "legend.frameon": False,
    "lines.linewidth": 1.4,
    "axes.prop_cycle": matplotlib.cycler(color=["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                                                 "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"]),
    "svg.hashsalt": "ocp",
    "pdf.compression": 6,
}
#: colours of the two control arcs in phase portraits
U_PLUS, U_MINUS = "#d62728", "#1f77b4"
FORMATS = ("png", "pdf", "svg")


@contextlib.contextmanager
def style():
    with plt.rc_context(RC):
        yield


def save(fig, stem, formats=("png", "pdf")):
    """Write fig to stem.<format> for each format (no timestamps, so the bytes are reproducible;
    each file written whole, `ocp.core.files`: Fault if it cannot be); close it; return the paths."""
    stem = Path(stem)
    paths = []
    try:
        for fmt in formats:
            if fmt not in FORMATS:
                raise ValueError(f"unknown figure format {fmt!r}; accepted: {', '.join(FORMATS)}")
            path = stem.with_name(f"{stem.name}.{fmt}")          # a dot inside the name is not a suffix
            metadata = {"png": {"Software": None}, "pdf": {"CreationDate": None, "ModDate": None, "Producer": None},
                        "svg": {"Date": None}}[fmt]
            with replacing(path, "wb") as f:
                fig.savefig(f, format=fmt, metadata=metadata, bbox_inches="tight")
            paths.append(path)
    finally:
        plt.close(fig)
    return paths
