"""`ocp verify`: every published value beside the suite's own computation of it.

A module of this package reproduces a paper (`REPRODUCERS`): `reproduce() -> dict[key,
Reproduction]`, the keys those of the paper's file in `data/`. Each computed value carries a bound
of its error (its accuracy), from an error estimate of the computation. The printed number P, with
its last digit of unit q, stands for an interval: [P, P + q) away from zero when truncated
("..."), [P - q/2, P + q/2] when rounded or approximate ("about"). A printed value gets one verdict:

    agrees                  the computed value's whole error interval lies inside the printed interval
    rounding of the print   it lies within one unit q of P (e.g. rounded where truncation is read)
    the paper is wrong      it lies farther from P than q, beyond both the print's rounding and the
                            suite's accuracy; the Reproduction carries the computed evidence
    disagrees               the same without evidence (a defect of the suite, never shipped)
    not reproduced          no computation, one of unknown accuracy, or one not accurate enough
                            to decide
"""

import importlib
import math
from dataclasses import dataclass, asdict
from decimal import Decimal, ROUND_DOWN, ROUND_HALF_EVEN

from ..core.numbers import digits
from . import references

#: paper id -> the modules that reproduce it
REPRODUCERS = {
    "finch2015": "ocp.papers.finch2015",
    "batista2006": "ocp.papers.batista2006",
    "weinstein_tam": "ocp.papers.weinstein_tam",
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


def compare(published, computed, accuracy):
    """(digits agreeing, digits printed, verdict) of `computed` +- `accuracy` against the printed
    `published` (see the module doc)."""
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
    if accuracy is None or not math.isfinite(accuracy):
        return agree, len(a), "not reproduced"
    e = Decimal(repr(float(accuracy)))
    if published.reading == "truncated":
        lo, hi = (printed, printed + q) if printed >= 0 else (printed - q, printed)
    else:
        lo, hi = printed - q / 2, printed + q / 2
    if lo <= exact - e and exact + e <= hi and (exact + e < hi or published.reading != "truncated"):
        verdict = "agrees"
    elif abs(exact - printed) + e <= q:
        verdict = "rounding of the print"
    elif abs(exact - printed) - e > q:
        verdict = "disagrees"
    else:
        verdict = "not reproduced"
    return agree, len(a), verdict


def rows(paper=None, progress=None):
    """The verify table: one Row per published value (of one paper, or of all); a line per paper
    on the stream `progress` as it is computed."""
    out = []
    ids = [paper] if paper else references.papers()
    for n, pid in enumerate(ids, 1):
        if progress is not None:
            print(f"verify: {pid} ({n}/{len(ids)}) ...", file=progress, flush=True)
        published = references.load(pid)
        name = REPRODUCERS[pid]
        computed = importlib.import_module(name).reproduce()
        unknown = set(computed) - set(published)
        if unknown:
            raise KeyError(f"{name}.reproduce(): keys not in data/{pid}.toml: {sorted(unknown)}")
        for key, pub in published.items():
            rep = computed.get(key)
            if rep is None:
                out.append(Row(pid, key, pub.source, pub.meaning, pub.printed, None, None, 0,
                               pub.significant_digits, "not reproduced", "", ""))
                continue
            agree, n, verdict = compare(pub, rep.value, rep.accuracy)
            if verdict == "disagrees" and rep.evidence:
                verdict = "the paper is wrong"
            out.append(Row(pid, key, pub.source, pub.meaning, pub.printed, float(rep.value), float(rep.accuracy), agree, n,
                           verdict, rep.how, rep.evidence, rep.erratum))
    return out


def as_dicts(table):
    return [asdict(r) for r in table]


def format_table(table):
    """The verify table as aligned text, a line per value, grouped by paper."""
    lines, paper = [], None
    head = f"{'key':<28} {'printed':>18} {'computed':>22} {'digits':>7}  verdict"
    for r in table:
        if r.paper != paper:
            paper = r.paper
            citation, where = references.citation(paper)
            lines += ["" if lines else None, f"[{paper}] {citation}", f"  ({where})", head]
        computed = "-" if r.computed is None else digits(r.computed, r.accuracy)
        lines.append(f"{r.key:<28} {r.printed:>18} {computed:>22} {r.digits_agree:>3}/{r.digits_printed:<3}  {r.verdict}")
        if r.evidence:
            lines.append(f"{'':<28} evidence: {r.evidence}")
        if r.erratum:
            lines.append(f"{'':<28} erratum: {r.erratum}")
    counts = {}
    for r in table:
        counts[r.verdict] = counts.get(r.verdict, 0) + 1
    lines += ["", f"{len(table)} printed values: " + ", ".join(f"{n} {v}" for v, n in counts.items())]
    return "\n".join(l for l in lines if l is not None)
