"""The results of `ocp bifurcation`: a JSON line per value, resumed, and the table.

Each row: the Bifurcation (`ocp.synthesis.bifurcation`), its case id, the asymptote G/(2n) of
Ovseevich (2014) (G = Si(pi)) beside it, the value Finch (2015) prints for it where he prints one
(quoting Reshmin), the commit of the code and the time it took.
"""

import json
import math
import time

from ..core.errors import Fault, InputError
from ..core.numbers import plus_minus
from ..core.provenance import git_commit
from .bifurcation import bifurcation
from .cases import CASES, find

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
    b = bifurcation(case.kind, case.reading, case.n, case.kappa_lo, case.kappa_hi, case.psi_lo, case.psi_hi)
    row = dict(b.to_dict(), case=case.id, asymptote=gibbs_constant() / (2 * case.n),
               published=PUBLISHED.get(case.id, (None, None))[1], located=case.located,
               commit=git_commit(), time_s=time.perf_counter() - start)
    return row


def load(path):
    """{case id: row} of the store at path (empty if absent); a malformed line is a Fault."""
    rows = {}
    try:
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                if line.strip():
                    try:
                        row = json.loads(line)
                        rows[row["case"]] = row
                    except (json.JSONDecodeError, KeyError, TypeError):
                        raise Fault(f"{path}, line {number}: not a result of ocp bifurcation") from None
    except FileNotFoundError:
        pass
    except (OSError, UnicodeDecodeError) as err:
        raise Fault(f"cannot read {path}: {err}") from None
    return rows


def append(path, row):
    try:
        with open(path, "a", encoding="utf-8") as f:
            f.write(json.dumps(row) + "\n")
    except OSError as err:
        raise Fault(f"cannot write {path}: {err}") from None


def format_table(rows):
    """The values as aligned text, a line each, then the attaining states and mechanisms."""
    lines = [f"{'case':<20} {'kappa_n':>24} {'G/(2n)':>8} {'published':>10}  attained at (theta mod 2 pi, omega)"]
    for r in rows:
        theta, omega = r["state"]
        if r["reading"] == "circle":
            theta = math.remainder(theta, 2 * math.pi)
        lines.append(f"{r['case']:<20} {plus_minus(r['kappa'], r['error']):>24} {r['asymptote']:>8.4f} "
                     f"{r['published'] or '-':>10}  ({theta:.4f}, {omega:.4f})")
    for r in rows:
        lines.append(f"  {r['case']}: {r['mechanism']} (time-to-go {r['time_to_go']:.4f}); computed at "
                     f"{r['commit'] or 'an unknown commit'}")
    return "\n".join(lines)
