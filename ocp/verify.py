"""`ocp verify`: every published value beside the suite's own computation of it.

A module that reproduces a paper exposes `reproduce() -> dict[key, Reproduction]`; the keys are
those of the paper's file in `reference/`. A paper may have several such modules (exact formulas
in one, claims that need a solve in another). A printed value gets one verdict:

    agrees                  every printed digit is reproduced (truncated or rounded as printed)
    rounding of the print   off by one unit in the last printed digit (e.g. rounded, not truncated)
    the paper is wrong      off by more; the Reproduction carries the independent evidence
    disagrees               off by more and no evidence given (a defect of the suite, never shipped)
    not reproduced          the suite has no computation of this value (yet)
"""

import importlib
import math
from dataclasses import dataclass, asdict
from decimal import Decimal, ROUND_DOWN, ROUND_HALF_EVEN

from . import references

#: paper id -> the modules that reproduce it
REPRODUCERS = {
    "finch2015": ("ocp.analytic", "ocp.examples"),
    "batista2006": ("ocp.scenes.falling",),
    "weinstein_tam": ("ocp.scenes.kapitza",),
}


@dataclass(frozen=True)
class Reproduction:
    """The suite's value of a published quantity: `value`, a bound on its absolute error
    (`accuracy`), how it was computed (`how`), for a printed value that is wrong the independent
    computation that shows it (`evidence`), and for a printed formula that is wrong although the
    values printed from it stand, what is wrong with it (`erratum`)."""

    value: float
    accuracy: float
    how: str
    evidence: str = ""
    erratum: str = ""


@dataclass(frozen=True)
class Row:
    paper: str
    key: str
    source: str
    meaning: str
    printed: str
    computed: float | None
    accuracy: float | None
    digits_agree: int
    digits_printed: int
    verdict: str
    how: str
    evidence: str
    erratum: str = ""


def _digits(d, q):
    """Significant digits of |d| at quantum q, as a string."""
    return format(abs(d.quantize(q)), "f").replace(".", "").lstrip("0")


def compare(published, computed):
    """(digits agreeing, digits printed, verdict) of `computed` against the printed `published`."""
    printed = Decimal(published.digits)
    q = Decimal(1).scaleb(printed.as_tuple().exponent)
    exact = Decimal(repr(float(computed)))
    shown = exact.quantize(q, rounding=ROUND_DOWN if published.reading == "truncated" else ROUND_HALF_EVEN)
    a, b = _digits(printed, q), _digits(shown, q)
    agree = 0
    if (printed < 0) == (shown < 0):
        for x, y in zip(a, b):
            if x != y:
                break
            agree += 1
    if published.reading == "approximate":
        verdict = "agrees" if abs(exact - printed) <= q / 2 else "disagrees"
    elif shown == printed:
        verdict = "agrees"
    elif abs(exact - printed) <= q:
        verdict = "rounding of the print"
    else:
        verdict = "disagrees"
    return agree, len(a), verdict


def rows(paper=None):
    """The verify table: one Row per published value (of one paper, or of all)."""
    out = []
    for pid in [paper] if paper else references.papers():
        published = references.load(pid)
        computed = {}
        for name in REPRODUCERS[pid]:
            part = importlib.import_module(name).reproduce()
            unknown, twice = set(part) - set(published), set(part) & set(computed)
            if unknown or twice:
                raise KeyError(f"{name}.reproduce(): keys not in reference/{pid}.toml {sorted(unknown)}, "
                               f"or reproduced twice {sorted(twice)}")
            computed.update(part)
        for key, pub in published.items():
            rep = computed.get(key)
            if rep is None:
                out.append(Row(pid, key, pub.source, pub.meaning, pub.printed, None, None, 0,
                               pub.significant_digits, "not reproduced", "", ""))
                continue
            agree, n, verdict = compare(pub, rep.value)
            if verdict == "disagrees" and rep.evidence:
                verdict = "the paper is wrong"
            out.append(Row(pid, key, pub.source, pub.meaning, pub.printed, float(rep.value), float(rep.accuracy), agree, n,
                           verdict, rep.how, rep.evidence, rep.erratum))
    return out


def as_dicts(table):
    return [asdict(r) for r in table]


def defended(value, accuracy):
    """`value` with no more decimals than its absolute `accuracy` supports (at most 16 digits);
    6 significant digits, marked, when the accuracy is unknown (NaN)."""
    if not math.isfinite(accuracy):
        return f"{value:.6g} (accuracy unknown)"
    if accuracy == 0 and float(value).is_integer():
        return str(int(value))
    decimals = 16 if accuracy <= 0 else max(0, math.floor(-math.log10(accuracy)))
    magnitude = math.floor(math.log10(abs(value))) + 1 if value else 1
    return f"{value:.{max(0, min(decimals, 16 - magnitude))}f}"


def format_table(table):
    """The verify table as aligned text, a line per value, grouped by paper."""
    lines, paper = [], None
    head = f"{'key':<28} {'printed':>18} {'computed':>22} {'digits':>7}  verdict"
    for r in table:
        if r.paper != paper:
            paper = r.paper
            lines += ["" if lines else None, f"[{paper}]", head]
        computed = "-" if r.computed is None else defended(r.computed, r.accuracy)
        lines.append(f"{r.key:<28} {r.printed:>18} {computed:>22} {r.digits_agree:>3}/{r.digits_printed:<3}  {r.verdict}")
        if r.evidence:
            lines.append(f"{'':<28} evidence: {r.evidence}")
        if r.erratum:
            lines.append(f"{'':<28} erratum: {r.erratum}")
    return "\n".join(l for l in lines if l is not None)
