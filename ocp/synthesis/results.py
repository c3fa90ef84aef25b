"""The results of `ocp bifurcation`: a JSON line per value, resumed, and the table.

Each row: the Bifurcation (`ocp.synthesis.bifurcation`), its case id, the asymptote G/(2n) of
Ovseevich (2014) (G = Si(pi)) beside it, the value Finch (2015) prints for it where he prints one
(quoting Reshmin), the commit of the code and the time it took. A row of the plane
(`ocp.synthesis.limit`) has kappa None (the value does not exist: N_kappa >= 2 at every kappa), the
tongues' lower edge speeds ("edges") and the complete search's switch counts on either side of the
candidate's zero ("confirmations") instead.
"""

import json
import math
import time
from dataclasses import dataclass

from ..core.errors import Fault
from ..core.files import read_rows
from ..core.numbers import plus_minus
from ..core.provenance import git_commit
from .bifurcation import ordinal, bifurcation, fold_and_tie
from .cases import CASES, TieCase, find

#: what Finch (2015) prints for a case: (key in ocp/papers/data/finch2015.toml, the text printed)
PUBLISHED = {"swing-up/circle/1": ("bifurcation_swing_n1", "about 0.80"),
             "swing-up/circle/2": ("bifurcation_swing_n2", "about 0.44"),
             "damping/circle/1": ("bifurcation_damping_n1", "about 1.04")}


def cases(ids=None):
    """The Cases named by ids (all located cases by default)."""
    return list(CASES) if not ids else [find(i) for i in dict.fromkeys(ids)]


def compute(case):
    """The row of one case (run in a worker)."""
    from ..exact.finch import gibbs_constant

    start = time.perf_counter()
    if case.reading == "plane":
        return dict(plane(case), located=case.located, commit=git_commit(), time_s=time.perf_counter() - start)
    extra = {}
    if isinstance(case, TieCase):
        b = fold_and_tie(case.kind, case.reading, case.n, case.kappa_lo, case.kappa_hi, case.psi_lo, case.psi_hi,
                         case.competitor)
        extra = evidence(case, b) if case.above is not None else {"bound": "lower"}
    else:
        b = bifurcation(case.kind, case.reading, case.n, case.kappa_lo, case.kappa_hi, case.psi_lo, case.psi_hi)
    row = dict(b.to_dict(), case=case.id, asymptote=gibbs_constant() / (2 * case.n), bound=None,
               published=PUBLISHED.get(case.id, (None, None))[1], located=case.located,
               commit=git_commit(), time_s=time.perf_counter() - start)
    row.update(extra)
    if row["bound"] == "lower":
        row["mechanism"] += f" (a lower bound of kappa_{case.n}: other regions of {case.n + 1} switches are not excluded)"
    elif extra:
        w, near = extra["sweep"], ", ".join(f"{r['G']:+.2g} at {abs(r['dpsi']):g}" for r in extra["beside"])
        row["mechanism"] += (f" (the gap beside the fold on its crossed side: {near} away in psi)"
                             f"; no other region of {case.n + 1} switches remains: at kappa = {case.above:g} every crossed "
                             f"{ordinal(case.n + 1)} switch of {w['angles']} final costate angles over (0, pi) (the "
                             f"mirror image carries the rest) with time-to-go up to {case.s_max:g} has a positive gap, "
                             f"the least {w['least_gap']:.3g} at psi = {w['least_psi']:.4f}: kappa_{case.n} lies in "
                             f"[{b.kappa:#.12g}, {case.above:g}], and is this value unless a region of {case.n + 1} "
                             f"switches is born and dies again between the two")
    return row


def sweep_rows(case):
    """The stored sweep of a TieCase (data/CASE.sweep_file): {psi: row} of `bifurcation.scan`."""
    from importlib import resources

    return read_rows(resources.files("ocp.synthesis") / "data" / case.sweep_file, "psi", "a row of a sweep")


def sweep(case, path):
    """Compute (resumed) the sweep of a TieCase into path: `bifurcation.scan` of the (n + 1)-th switch
    at kappa = case.above over psi = pi (i + 1/2) / case.angles, i < case.angles."""
    from .bifurcation import scan

    done = read_rows(path, "psi", "a row of a sweep")
    psis = [p for p in (math.pi * (i + 0.5) / case.angles for i in range(case.angles)) if p not in done]
    for row in scan(case.kind, case.above, case.reading, case.n + 1, psis, case.s_max):
        append(path, row)


def evidence(case, b):
    """Whether the fold-and-tie value b of a TieCase is kappa_n itself: the stored sweep at case.above
    (every crossed (n + 1)-th switch up to the time-to-go case.s_max has G > 0 there, its least gap,
    swept at the Taylor accuracy CHECK, re-computed at PRECISE), and the complete search just upstream
    of the (n + 1)-th switch at case.below (n + 1 switches expected) and at the sweep's least gap
    (n at most); and at the value itself the gap beside the fold, on its crossed side (offsets 0.003
    and 0.01 in psi), positive: the fold is the least gap there, and the region ends at it.
    {"bound": None or "lower", "upper": case.above, "beside": ..., "sweep": ..., "confirmations": ...}."""
    from .bifurcation import confirm, crossing, gap

    n = case.n + 1
    beside = {d: gap(case.kind, b.kappa, case.reading, b.psi + d, n)[0] for d in (-0.01, -0.003, 0.003, 0.01)
              if math.prod(crossing(case.kind, b.kappa, b.psi + d, n)) > 0}
    rows = sweep_rows(case)
    crossed = [r for r in rows.values() if r["crossed_and_found"]]
    least = min(crossed, key=lambda r: r["G"]) if crossed else None
    recheck = gap(case.kind, case.above, case.reading, least["psi"], n)[0] if least else None
    below = confirm(case.kind, case.below[0], case.reading, case.below[1], n)
    above = confirm(case.kind, case.above, case.reading, least["psi"], n) if least else None
    complete = set(rows) == {math.pi * (i + 0.5) / case.angles for i in range(case.angles)}
    holds = (complete and least is not None and least["G"] > 0 and abs(recheck - least["G"]) < 1e-6
             and b.kappa < case.above and below["switches"] == n and above["switches"] < n
             and len(beside) >= 2 and min(beside.values()) > 0)
    return {"bound": None if holds else "lower", "upper": case.above,
            "beside": [{"dpsi": d, "G": g} for d, g in beside.items()],
            "sweep": {"kappa": case.above, "angles": case.angles, "s_max": case.s_max, "rows": len(rows),
                      "crossed": len(crossed), "least_gap": least and least["G"], "least_psi": least and least["psi"],
                      "least_state": least and least["state"], "recheck": recheck},
            "confirmations": [below, above]}


def plane(case):
    """The row of a PlaneCase: the Edge (`limit.edge`) at each of its kappas, and the complete
    search at the states 0.2 time units downstream and upstream of the zero of p_omega of the
    candidate turning at each (kappa, theta_s) of case.confirm (expected: 1 and 2 switches)."""
    from . import limit

    edges = [limit.edge(k, case.kind).to_dict() for k in case.kappas]
    checks = []
    for kappa, theta_s in case.confirm:
        c, solves = limit.confirm(case.kind, kappa, theta_s)
        checks.append({"kappa": kappa, "theta_s": theta_s, "zero": list(c.zero), "states": [r["x0"] for r in solves],
                       "switches": [r["switches"] for r in solves], "arc_signs": [r["arc_signs"] for r in solves]})
    agree = all(ch["switches"][0] <= 1 < ch["switches"][1] for ch in checks)
    edge_text = ", ".join(f"{plus_minus(e['omega_min'], e['error'])} at kappa = {e['kappa']:g}" for e in edges)
    at = ", ".join(f"{ch['kappa']:g}" for ch in checks)
    counts = "; ".join(f"{ch['switches'][0]} and {ch['switches'][1]}" for ch in checks)
    mechanism = (f"kappa_1 does not exist on the plane: N_kappa >= 2 at every kappa. States beyond the pinned target "
                 f"moving away from it turn far away; there the costate's kick reverses p_theta and the one-switch "
                 f"candidate's p_omega vanishes again on its first arc, so states upstream of that zero need two "
                 f"switches (+1 -1 +1), at speeds down to omega_min = {edge_text} (the limit problem; "
                 f"~ (kappa + 0.71)^1.5 / sqrt(2 pi)); the complete search {'confirms' if agree else 'DISAGREES'} "
                 f"at kappa = {at}: {counts} switches just downstream and upstream of the zero")
    return {"case": case.id, "kind": case.kind, "reading": "plane", "n": case.n, "kappa": None, "error": None,
            "exists": False, "edges": edges, "confirmations": checks, "confirmed": agree, "mechanism": mechanism,
            "asymptote": None, "published": None}


def stored():
    """{case id: row} of the values stored with the package (data/bifurcation.jsonl, regenerated by
    `python benchmarks/publish.py --only bifurcation`)."""
    from importlib import resources

    return load(resources.files("ocp.synthesis") / "data" / "bifurcation.jsonl")


def load(path):
    """{case id: row} of the store at path (empty if absent); a malformed line is a Fault."""
    return read_rows(path, "case", "a result of ocp bifurcation")


def append(path, row):
    try:
        with open(path, "a", encoding="utf-8") as f:
            f.write(json.dumps(row) + "\n")
    except OSError as err:
        raise Fault(f"cannot write {path}: {err}") from None


def departures(rows):
    """{kind: [(n, d_n)]}: d_n = 1 - kappa_n / (G/(2n)) of each circle sequence's values (not its
    lower bounds), by n; negative where kappa_n lies above the asymptote, as the damping's do."""
    seqs = {}
    for r in rows:
        if r["reading"] == "circle" and r["kappa"] is not None and r.get("bound") != "lower":
            seqs.setdefault(r["kind"], []).append((r["n"], 1 - r["kappa"] / r["asymptote"]))
    return {kind: sorted(seq) for kind, seq in seqs.items()}


def local_exponents(seq):
    """[(n, m, p)]: the exponent of d_n ~ n^(-p) through each two successive values (n, d_n), (m, d_m),
    p = ln(d_n / d_m) / ln(m / n) (nan where they differ in sign)."""
    return [(n, m, math.log(d / e) / math.log(m / n) if d * e > 0 else math.nan)
            for (n, d), (m, e) in zip(seq, seq[1:])]


def approach(rows, n_min=2):
    """{kind: Approach}: the fits of d_n = 1 - kappa_n / (G/(2n)) over each circle sequence's values
    with n >= n_min (three at least, of one sign): the power law d_n = a n^(-p) (least squares of
    ln |d_n| against ln n, a carrying the sign) and, with the exponent 3/2 the power law's local
    exponents approach, d_n = n^(-3/2) (c + e / n) (linear least squares); standard errors from the
    covariance (nan with fewer than four values)."""
    import numpy as np

    fits = {}
    for kind, seq in departures(rows).items():
        seq = [(k, d) for k, d in seq if k >= n_min]
        if len(seq) < 3 or len({math.copysign(1, d) for _, d in seq}) > 1:
            continue
        n, d = np.array(seq).T
        sign = math.copysign(1, d[0])
        if len(seq) > 3:
            (slope, log_a), cov = np.polyfit(np.log(n), np.log(sign * d), 1, cov=True)
            se = np.sqrt(np.diag(cov))
        else:
            (slope, log_a), se = np.polyfit(np.log(n), np.log(sign * d), 1), (math.nan, math.nan)
        a = sign * math.exp(log_a)
        basis = np.vstack([n ** -1.5, n ** -2.5]).T
        ce = np.linalg.lstsq(basis, d, rcond=None)[0]
        sigma2 = float(np.sum((basis @ ce - d) ** 2)) / (len(seq) - 2) if len(seq) > 2 else math.nan
        ce_se = np.sqrt(np.diag(sigma2 * np.linalg.inv(basis.T @ basis))) if len(seq) > 3 else (math.nan, math.nan)
        fits[kind] = Approach(a, abs(a) * se[1], -slope, se[0], float(np.max(np.abs(a * n ** slope - d))),
                              float(ce[0]), float(ce_se[0]), float(ce[1]), float(ce_se[1]),
                              float(np.max(np.abs(basis @ ce - d))), tuple(int(k) for k in n))
    return fits


@dataclass(frozen=True)
class Approach:
    """The fits of `approach`: a n^(-p) with its largest residual, n^(-3/2) (c + e / n) with its, and
    the n fitted."""

    a: float
    a_error: float
    p: float
    p_error: float
    residual: float
    c: float
    c_error: float
    e: float
    e_error: float
    residual_32: float
    ns: tuple


def format_table(rows):
    """The values as aligned text, a line each (with kappa_n / (G/(2n))), the fit of the approach to
    the asymptote, then the attaining states and mechanisms."""
    lines = [f"{'case':<20} {'kappa_n':>24} {'G/(2n)':>8} {'ratio':>7} {'published':>10}  "
             f"attained at (theta mod 2 pi, omega)"]
    for r in rows:
        if r["kappa"] is None:
            lines.append(f"{r['case']:<20} {'none (N >= 2 always)':>24} {'-':>8} {'-':>7} {'-':>10}  "
                         f"far turnarounds (the limit of high energy)")
            continue
        theta, omega = r["state"]
        if r["reading"] == "circle":
            theta = math.remainder(theta, 2 * math.pi)
        value = (">= " if r.get("bound") == "lower" else "") + plus_minus(r["kappa"], r["error"])
        lines.append(f"{r['case']:<20} {value:>24} {r['asymptote']:>8.4f} "
                     f"{r['kappa'] / r['asymptote']:>7.4f} {r['published'] or '-':>10}  ({theta:.4f}, {omega:.4f})")
    fits = approach(rows)
    for kind, seq in departures(rows).items():
        local = ", ".join(f"{p:.2f}" for *_, p in local_exponents(seq))
        f = fits.get(kind)
        if f is not None:
            lines.append(f"  {kind}/circle: 1 - kappa_n/(G/(2n)) = a n^-p with a = {plus_minus(f.a, f.a_error)}, "
                         f"p = {plus_minus(f.p, f.p_error)} (largest residual {f.residual:.1e}); = n^-1.5 (c + e/n) "
                         f"with c = {plus_minus(f.c, f.c_error)}, e = {plus_minus(f.e, f.e_error)} (largest residual "
                         f"{f.residual_32:.1e}); least squares over n = {', '.join(map(str, f.ns))}; local exponents "
                         f"between successive n from n = {seq[0][0]}: {local}")
        elif len(seq) > 1:
            lines.append(f"  {kind}/circle: 1 - kappa_n/(G/(2n)) = {', '.join(f'{d:+.4f}' for _, d in seq)} at n = "
                         f"{', '.join(str(k) for k, _ in seq)}, local exponents {local} between successive n; no fit "
                         f"(three values of one sign with n >= 2 needed)")
    for r in rows:
        where = "" if r["kappa"] is None else f" (time-to-go {r['time_to_go']:.4f})"
        lines.append(f"  {r['case']}: {r['mechanism']}{where}; computed at {r['commit'] or 'an unknown commit'}")
    return "\n".join(lines)
