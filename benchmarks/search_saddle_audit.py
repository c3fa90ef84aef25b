"""Where the residual assumption of the search is most exposed, audited: the halves its scan settles by
the bound on omega(t_a, .) (no zero, or one: monotone; its turns following the samples:
`searching._turns_follow`) while the energy of an arc before t_a may be at
a saddle's level there (`searching._may_pass_saddle`; the bound on e(t_a, .) is not trusted there, the
one on omega is). Inside each such half, AUDIT angles evenly spaced are integrated and their turning
points before t_a compared with the half's ends': one that none of the ends sees is hidden from the
scan (it takes every label absent at the ends as after t_a on the half). Where some are, DENSE angles
look for a hidden turning point on an allowed target before the search's best time: an arrival the
search may have missed.

    python benchmarks/search_saddle_audit.py OUT.jsonl FIRST_SEED END_SEED   (the states of
        search_residual.py's seeds, both kinds and readings; resumable by seed)
    python benchmarks/search_saddle_audit.py --summary FILE.jsonl...

A line: the seed, the problem, the search's status and best T, the halves audited, those hiding a
turning point, the hidden arrivals found (phi bracket, label, branch, time), and the commit of the code
that ran (`completeness.shard_commit`, at the start: a checkout with uncommitted changes is
refused).
"""

import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from completeness import shard_commit, shard_range  # noqa: E402
from search_residual import state  # noqa: E402

from ocp.indirect import searching as S  # noqa: E402

AUDIT, DENSE = 48, 2000


class Audit:
    """Wraps `searching._examine`: each half it settles by omega(t_a, .) by a saddle, sampled inside."""

    def __init__(self):
        self.halves, self.hiding, self.suspects = 0, 0, []

    def examine(self, problem, family, a, m, b, accept, extended, arrive=None):
        outcome = EXAMINE(problem, family, a, m, b, accept, extended, arrive)
        if family is not None:
            self.audit(problem, family, a, m, b, accept, extended)
        return outcome

    def audit(self, problem, family, a, m, b, accept, extended):
        h = 0.5 * (b.phi - a.phi)
        later = [t for t in a.ends.keys() & m.ends.keys() & b.ends.keys() if accept <= t <= extended / S.EXTEND]
        end = min(later, default=accept)
        (wa, dwa, *_), (wm, dwm, *_), (wb, dwb, *_) = (s.omega(family, end) for s in (a, m, b))
        curvatures = S._curvatures(wa, wm, wb, dwa, dwm, dwb, h)
        saddle = S._may_pass_saddle(problem.kappa, a.u0, a, m, b, max(a.arc(end), m.arc(end), b.arc(end)), h)
        follow = S._turns_follow(a, m, b, end, h)
        for half, (x0, x1, w0, w1, s0, s1) in enumerate(((a, m, wa, wm, dwa, dwm), (m, b, wm, wb, dwm, dwb))):
            reach = S.CURVATURE * curvatures[half] * h * h / 8           # as `_examine` judges omega's bound
            calm = (min(w0, w1) - reach > 0 or max(w0, w1) + reach < 0
                    or (s0 * s1 > 0 and abs(s0 + s1) > S.CURVATURE * curvatures[half] * h))
            before = x0.seen(end)
            if not (calm and follow[half] and saddle[half] and before == x1.seen(end)):
                continue
            self.halves += 1
            if any(self.hidden(family, phi, a.u0, end, before) for phi in np.linspace(x0.phi, x1.phi, AUDIT + 2)[1:-1]):
                self.hiding += 1
                self.suspects.append((problem, family, x0.phi, x1.phi, a.u0, end, before))

    @staticmethod
    def hidden(family, phi, u0, end, before):
        """The turning points before `end` of the extremal phi that none of the half's ends sees there."""
        sample = S._Sample(family, float(phi), u0, end * (1 + 1e-9))
        return {label: sample.events[label] for label in sample.seen(end) - before}

    def arrivals(self, best):
        """Hidden turning points whose angle less an allowed target changes sign between neighbouring
        DENSE angles of a hiding half, both before `best`: (phi_lo, phi_hi, label, branch, time)."""
        found = []
        for problem, family, lo, hi, u0, end, before in self.suspects:
            previous = None
            for phi in np.linspace(lo, hi, DENSE + 2)[1:-1]:
                events = self.hidden(family, phi, u0, end, before)
                for label, (t, theta) in events.items():
                    if previous is None or label not in previous[1] or max(t, previous[1][label][0]) > best:
                        continue
                    theta_before = previous[1][label][1]
                    for k in S._targets(problem, min(theta, theta_before), max(theta, theta_before)):
                        found.append((previous[0], float(phi), list(label), k, t))
                previous = (float(phi), events)
        return found


EXAMINE = S._examine


def summary(paths):
    rows = [json.loads(line) for path in paths for line in Path(path).read_text().splitlines()]
    halves, hiding = sum(r["halves"] for r in rows), sum(r["hiding"] for r in rows)
    arrivals = [(r["seed"], a) for r in rows for a in r["hidden_arrivals"]]
    print(f"{len(rows)} states, {sum(r['halves'] > 0 for r in rows)} with a half settled by omega by a saddle: "
          f"{halves} such halves, {hiding} hiding a turning point ({AUDIT} angles each), "
          f"{len(arrivals)} hidden arrivals before the search's best {arrivals}")


def main(args):
    if args[:1] == ["--summary"]:
        return summary(args[1:])
    out_path, seeds = shard_range(args, __doc__, "seed")
    commit = shard_commit()
    with open(out_path, "a") as out:
        for seed in seeds:
            problem, audit = state(seed), Audit()
            S._examine = audit.examine
            start = time.process_time()
            try:
                found = S.search(problem)
            finally:
                S._examine = EXAMINE
            best = found.best.T if found.best is not None else float("inf")
            row = {"seed": seed, **problem.to_dict(), "status": found.status, "best": found.best and found.best.T,
                   "halves": audit.halves, "hiding": audit.hiding, "hidden_arrivals": audit.arrivals(best),
                   "seconds": time.process_time() - start, "commit": commit}
            out.write(json.dumps(row) + "\n")
            out.flush()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
