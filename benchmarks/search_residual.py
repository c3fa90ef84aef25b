"""The residual assumption of the search's completeness, measured: the search against the brute force
of tests/test_search.py (a uniform grid of costate angles, each sign change of a turning point's angle
less a target between neighbours solved where it moves less than 1 rad) on random states and kappa,
both kinds, both readings, one JSON line per state (resumable by seed).

    python benchmarks/search_residual.py [--fast | --small | --large] OUT.jsonl FIRST_SEED END_SEED  (seeds FIRST_SEED to END_SEED - 1)
    python benchmarks/search_residual.py --summary FILE.jsonl...

The states: theta0 in [-4, 4], omega0 in [-3, 3] (0 one time in five), kappa log-uniform in
[0.2, 10]; with --fast, the fast starts of benchmarks/search_cost.py (`random_cases`, one per seed:
|omega0| in [5, 30], kappa in [0.1, 3], the circle or a plane branch -2..2), where the family turns
many times per radian of phi: there a pair of neighbouring angles between which a turning point's
angle moves 1 rad or more is bisected for it down to FAST_FINEST (tests/test_search.py's
`brute_force`; a uniform grid of 40,000 angles, this script's first fast shards, found none of the
arrivals of one state in five, and the bisection from 4,000 finds some of those at a fifth of its
cost). With --small, the box's states at kappa log-uniform in [0.05, 0.2], the rest of the range
the command line accepts (the extremals there pass near the upright many times before an arrival:
steep pairs bisected as on the fast starts; a seed's state is not the box's at another kappa);
with --large, kappa log-uniform in [10, 1e4] and omega0 in [-50, 50] (0 one time in five), the
accepted range's other end, bisected alike.
A line records the brute force it ran (`brute`: angles per half-circle, finest width) and the kind
of its states (`states`: box, fast, small or large).

Shards are seed ranges (run them in parallel, under nice, each into its own file); --summary counts
the states of every file given, by status, and the brute-force arrivals missed, and the brute
force's own reach: the states where its best is the search's, and those where it found none (a
check that can only find misses among the arrivals it sees).

A line: the problem, the search's status and reading, its best T, the brute force's best and count,
`missing`: the brute-force arrivals (before the search's horizon) that the search did not find, and
the commit of the code that ran (`completeness.shard_commit`, at the start: a checkout with
uncommitted changes is refused).
"""

import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from completeness import same_arrival, shard_commit, shard_range  # noqa: E402
from search_cost import random_cases  # noqa: E402
from test_search import BRUTE, brute_force  # noqa: E402

from ocp.core.problem import make  # noqa: E402
from ocp.indirect import searching as S  # noqa: E402

#: CPU seconds of search per state (a start moving near the upright may take longer: then "stopped");
#: the search's limit is wall time, so a search stopped with less CPU than this (a niced run starved
#: by the machine's load) is run again with STARVED times the limit
TIME_LIMIT = 60.0
STARVED = 20
#: the width down to which the brute force bisects a steep pair (but in the box)
FAST_FINEST = 1e-9
#: the range of kappa (log-uniform) of the box's states and of those of --small and --large
KAPPAS = {"box": (0.2, 10), "small": (0.05, 0.2), "large": (10, 1e4)}


def state(seed, states="box"):
    """The problem of `seed` among `states` (box, fast, small or large: the module's docstring)."""
    if states == "fast":
        return make(*random_cases(1, seed)[0])
    rng = np.random.default_rng(seed if states == "box" else [seed, 2 if states == "small" else 3])
    kind = str(rng.choice(["swing-up", "damping"]))
    kappa = float(10 ** rng.uniform(*np.log10(KAPPAS[states])))
    speed = 50 if states == "large" else 3
    x0 = (float(rng.uniform(-4, 4)), float(rng.uniform(-speed, speed)) * (rng.random() < 0.8))
    return make(kind, kappa, x0, None if rng.random() < 0.5 else int(rng.integers(-1, 2)))


def summary(paths):
    """The states by status, those compared with the brute force, and the arrivals missed (with their seeds)."""
    rows = [json.loads(line) for path in paths for line in Path(path).read_text().splitlines()]
    statuses = {}
    for r in rows:
        statuses[r["status"]] = statuses.get(r["status"], 0) + 1
    compared = [r for r in rows if "missing" in r]
    missed = [(r["seed"], T) for r in compared for T in r["missing"]]
    # the brute force's own reach: the states where it found the search's best, and where it found none
    same_best = sum(r["brute_best"] is not None and same_arrival(r["brute_best"], r["best"]) for r in compared)
    blind = sum(r["n_brute"] == 0 for r in compared)
    print(f"{len(rows)} states ({', '.join(f'{n} {s}' for s, n in sorted(statuses.items()))}); {len(compared)} compared "
          f"with the brute force ({sum(r['n_brute'] for r in compared)} arrivals; its best the search's in {same_best}, "
          f"none found in {blind}): {len(missed)} missed {missed}")


def main(args):
    if args[:1] == ["--summary"]:
        return summary(args[1:])
    states = {"--fast": "fast", "--small": "small", "--large": "large"}.get(args[0] if args else "", "box")
    out_path, seeds = shard_range(args[states != "box":], __doc__, "seed")
    commit = shard_commit()
    with open(out_path, "a") as out:
        for seed in seeds:
            problem = state(seed, states)
            begun, cpu = time.time(), time.process_time()
            result = S.search(problem, time_limit=TIME_LIMIT)
            if result.coverage.stopped and time.process_time() - cpu < TIME_LIMIT:
                result = S.search(problem, time_limit=STARVED * TIME_LIMIT)
            row = {"seed": seed, "problem": problem.to_dict(), "status": result.status, "commit": commit,
                   "states": states}
            if result.arrivals and result.coverage.complete:
                horizon = result.coverage.horizon
                finest = 0.0 if states == "box" else FAST_FINEST
                brute = [T for T in brute_force(problem, horizon, BRUTE, finest) if T <= horizon * 0.999]
                found = [a.T for a in result.arrivals]
                row.update(brute=[BRUTE, finest], reading=result.coverage.reading, best=found[0],
                           brute_best=min(brute, default=None), n_brute=len(brute),
                           missing=[T for T in brute if not any(same_arrival(T, F) for F in found)],
                           seconds=time.time() - begun)
            out.write(json.dumps(row) + "\n")
            out.flush()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
