"""The search against the synthesis maps, an independent route to the same optimum: the field of
extremals integrated backwards in time from the target (`ocp.synthesis.field`), on random cells of
random maps. One JSON line per cell (resumable by map seed).

    python benchmarks/search_vs_maps.py OUT.jsonl FIRST_MAP END_MAP [--cells K]    (maps FIRST_MAP to END_MAP - 1)
    python benchmarks/search_vs_maps.py --summary FILE.jsonl...

Map seed s (`map_case`): the kind, the reading (the circle, or the plane with branch 0 pinned),
kappa log-uniform in [0.2, 10], the window theta in [-pi, pi] (the circle) or [-2 pi, 2 pi] (the
plane), omega in [-3, 3], and the horizon HORIZON(kappa). The map is drawn twice: on a grid of
COARSE nodes per axis from the field sampled at SAMPLES times, and on one of 2 COARSE - 1 nodes (every
coarse node is one of it) from the field sampled at 2 SAMPLES times. A map's value at a node is the
linear interpolation of the time-to-go on the field's triangles, which spans a few cells and a
sample time; its error falls about fourfold when both halve, so the fine map's value V is the
reference and SAFETY times its difference from the coarse map's is its error estimate. K random
nodes drawn in both maps, with V at most 0.9 times the horizon, are each solved by the search
alone (`ocp.indirect.search`, the map's reading; TIME_LIMIT s), and compared with the map's own
extremal there, solved exactly (`through`): the extremal of the fine map's final costate angle at
the node (its branch on the circle), by Newton in (psi, s) from the map's (psi, V) to pass through
x0 exactly (PRECISE integration backwards from the target with its variations in psi): its
time-to-go s from x0 is that of an admissible extremal, so s >= T* and the search must find it.

    same extremal  |s - T| <= T_error + EXACT max(1, T)
    search missed  s below that: an extremal faster than the search's answer, not reported by it
    map slower     s above it: the map's strip at the node holds a slower extremal (near a switching
                   or dispersal curve the nearest triangle may be another extremal's)
    unsettled      Newton did not converge, from the map's (psi, V) nor from the closest approach
                   of the map's extremals to x0 (`closest`, Nelder-Mead in (psi, s) from there,
                   tried where it is below POLISH: "settled_by" then says so); then "agree"
                   (|T - V| <= SAFETY |V_coarse - V| + T_error + FLOOR max(1, V)), "search slower"
                   or "map slower" by the maps' values, and "not attained" for a search slower
                   where that approach misses x0 by more than NOT_ATTAINED: the map's value there
                   is no extremal's (a node beside a fold of its field, where V is Hoelder-1/2)
    (status)       the search not proven optimal: "best found", "stopped", "none" (not compared)

    python benchmarks/search_vs_maps.py --settle OUT.jsonl FILE.jsonl...

judges again the cells of FILEs left "unsettled, search slower" by an earlier version of this
script (before `closest`; the search's answer as they recorded it, the maps drawn again): a line
each, with the cell's map and x0, the commit of the search it judges (`of`) and of the code that
judged it (`commit`); benchmarks/completeness.py reads OUT (benchmarks/map_settlements.jsonl) over
those cells' verdicts.

A line: the map seed and case, the state, V, the coarse V, the search's status, T and T_error,
the verdict (with the exact s where settled), seconds, and the commit of the code that ran
(`completeness.shard_commit`: a checkout with uncommitted changes is refused).
"""

import json
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import minimize

from completeness import shard_commit, shard_range
from ocp.core.problem import KINDS, make
from ocp.indirect import search, taylor
from ocp.synthesis.field import Window, synthesize

COARSE, SAMPLES = 81, 400
#: seconds of search per cell (wall: a stopped search is recorded as such)
TIME_LIMIT = 30.0
SAFETY = 3.0
#: relative agreement below which the map's error estimate is not trusted to resolve (rounding of the
#: field's SCAN integration, the raster's float arithmetic)
FLOOR = 1e-7
#: relative agreement of the search's T and the exact time of the map's extremal: the same extremal
EXACT = 1e-9
#: Newton (`through`) is tried again from the `closest` approach of the map's extremals to x0 where it
#: is below this; where it is above NOT_ATTAINED, the map's value is not an extremal's at x0
POLISH, NOT_ATTAINED = 1e-6, 1e-8


def horizon(kappa):
    """The maps' horizon: the time to go of the slowest state of the window, about 6 / kappa from
    rest at the bottom for small kappa, plus room."""
    return min(8.0 + 6.0 / kappa, 40.0)


def map_case(seed):
    """(kind, reading, kappa, window bounds) of map `seed`."""
    rng = np.random.default_rng(seed)
    kind = str(rng.choice(["swing-up", "damping"]))
    reading = str(rng.choice(["circle", "plane"]))
    kappa = float(10 ** rng.uniform(math.log10(0.2), 1))
    span = math.pi if reading == "circle" else 2 * math.pi
    return kind, reading, kappa, (-span, span, -3.0, 3.0)


def through(kind, kappa, x0, psi, s):
    """(s, psi) of the extremal that ends at the target (base, 0) with final costate angle psi and
    passes through x0 (shifted by the map's branch) after the time-to-go s, by Newton in (psi, s) from
    the map's (psi, s0); None if it does not converge in 30 steps or an iterate leaves 0 < s <= 2 s0
    (diverging: on a node of map 86, whose horizon is 23, an iterate reached s = 5.8e7, an integration
    of hours). Backwards from the target (`taylor.extremal_variations`, direction -1, PRECISE), the
    state at elapsed s and its derivative in psi; d/ds of the state is -f(x, u), u = sign(p2) there."""
    tol, order = taylor.PRECISE
    switches, events, s0 = np.empty((512, 8)), np.empty((512, 8)), s
    for _ in range(30):
        y0 = np.array([KINDS[kind].target_base, 0.0, math.cos(psi), math.sin(psi)])
        dy0 = np.array([0.0, 0.0, -math.sin(psi), math.cos(psi)])
        u_end = 1.0 if math.sin(psi) > 0 else -1.0
        n_sw, n_ev, *_, (y, dy) = taylor.extremal_variations(y0, dy0, kappa, u_end, s * 1.001 + 1e-9, -1.0, tol, order,
                                                             switches, events, s)
        if n_sw > len(switches) or n_ev > len(events):
            return None
        u = 1.0 if y[3] > 0 else -1.0
        miss = np.array([y[0] - x0[0], y[1] - x0[1]])
        if np.max(np.abs(miss)) < 1e-12 * max(1.0, abs(x0[0])):
            return s, psi
        jacobian = np.array([[dy[0], -y[1]], [dy[1], -(kappa * u - math.sin(y[0]))]])
        try:
            step = np.linalg.solve(jacobian, -miss)
        except np.linalg.LinAlgError:
            return None
        psi, s = psi + float(step[0]), s + float(step[1])
        if not (0 < s <= 2 * s0 and math.isfinite(psi)):
            return None
    return None


def closest(kind, kappa, x0, psi, s, spread):
    """(miss, psi, s): the least distance from x0 found among the extremals ending at the target with
    final costate angle near psi and time-to-go near s, by Nelder-Mead in (psi, s) from there (its
    first simplex `spread` = (dpsi, ds) wide; CHECK integration backwards from the target, as
    `through` at PRECISE). Where the map's node lies beside a fold of its field (the extremals that do
    not switch before s all follow the one arc of their final control through the target, which
    turns there: the map (psi, s) -> x has rank 1; the value is Hoelder-1/2 across that arc, which
    the maps' linear triangles do not resolve, their coarse and fine values agreeing on a value no
    extremal has) or where the value jumps between the map's neighbouring nodes, Newton from the
    map's (psi, V) diverges; from here it finds the map's extremal through x0 where one is near, or
    this tells how far the family passes from x0."""
    tol, order = taylor.CHECK
    switches, events, samples = np.empty((512, 5)), np.empty((512, 6)), np.empty((1, 3))

    def miss(z):
        psi, s = z
        if not 0 < s < 1e4:
            return math.inf
        y0 = (KINDS[kind].target_base, 0.0, math.cos(psi), math.sin(psi))
        n_sw, n_ev, *_ = taylor.extremal(y0, kappa, 1.0 if math.sin(psi) > 0 else -1.0, s * 1.001 + 1e-9, -1.0, tol,
                                         order, switches, events, np.array([s]), samples)
        if n_sw > len(switches) or n_ev > len(events):
            return math.inf
        return math.hypot(samples[0, 0] - x0[0], samples[0, 1] - x0[1])

    start = np.array([[psi, s], [psi + spread[0], s], [psi, s + spread[1]]])
    found = minimize(miss, start[0], method="Nelder-Mead",
                     options={"initial_simplex": start, "xatol": 1e-13, "fatol": 1e-15, "maxiter": 2000})
    return float(found.fun), float(found.x[0]), float(found.x[1])


def compare(seed, cells, commit):
    """The lines of map `seed`: `cells` random nodes, each searched and compared with the maps."""
    kind, reading, kappa, bounds = map_case(seed)
    T_max = horizon(kappa)
    coarse = synthesize(kind, kappa, reading, Window(*bounds, COARSE, COARSE), T_max, SAMPLES)
    fine = synthesize(kind, kappa, reading, Window(*bounds, 2 * COARSE - 1, 2 * COARSE - 1), T_max, 2 * SAMPLES)
    V_fine = fine.V[::2, ::2]
    usable = np.argwhere(np.isfinite(coarse.V) & np.isfinite(V_fine) & (V_fine <= 0.9 * T_max))
    rng = np.random.default_rng([seed, 1])
    picked = usable[rng.choice(len(usable), size=min(cells, len(usable)), replace=False)] if len(usable) else []
    for i, j in picked:
        x0 = (float(coarse.window.theta[i]), float(coarse.window.omega[j]))
        V, V_coarse = float(V_fine[i, j]), float(coarse.V[i, j])
        begun = time.time()
        found = search(make(kind, kappa, x0, None if reading == "circle" else 0), time_limit=TIME_LIMIT)
        row = {"map": seed, "kind": kind, "reading": reading, "kappa": kappa, "x0": list(x0), "V": V,
               "V_coarse": V_coarse, "status": found.status, "commit": commit}
        if found.status == "optimal":
            T, T_error = found.best.T, found.best.T_error
            branch = int(fine.branch[2 * i, 2 * j])
            row.update(T=T, T_error=T_error, map_branch=branch)
            row.update(judge(kind, kappa, x0, branch, fine.psi[2 * i, 2 * j], V, V_coarse, T, T_error))
        else:
            row.update(verdict=found.status)
        row["seconds"] = time.time() - begun
        yield row


def judge(kind, kappa, x0, branch, psi, V, V_coarse, T, T_error):
    """The verdict of a cell (the module's docstring) and what settled it: the map's extremal through
    x0 by `through` from the map's (psi, V), else from the `closest` approach of its extremals to x0
    where that is below POLISH ("settled_by": "closest"); else unsettled, by the maps' values, with
    the closest approach recorded."""
    x0 = (x0[0] - 2 * math.pi * branch, x0[1])
    psi_lo, psi_hi = float(psi[0]), float(psi[1])
    exact, out = through(kind, kappa, x0, 0.5 * (psi_lo + psi_hi), V), {}
    if exact is None:
        miss, psi_c, s_c = closest(kind, kappa, x0, 0.5 * (psi_lo + psi_hi), V,
                                   (max(psi_hi - psi_lo, 1e-6), max(SAFETY * abs(V - V_coarse), 1e-3)))
        exact = through(kind, kappa, x0, psi_c, s_c) if miss < POLISH else None
        out = {"settled_by": "closest"} if exact is not None else {"closest_miss": miss, "closest_s": s_c}
    if exact is not None:
        tolerance = T_error + EXACT * max(1.0, T)
        verdict = "same extremal" if abs(exact[0] - T) <= tolerance else ("search missed" if exact[0] < T else "map slower")
        return {**out, "exact_s": exact[0], "exact_psi": exact[1], "tolerance": tolerance, "verdict": verdict}
    tolerance = SAFETY * abs(V_coarse - V) + T_error + FLOOR * max(1.0, V)
    verdict = "agree" if abs(T - V) <= tolerance else ("search slower" if T > V else "map slower")
    if verdict == "search slower" and out["closest_miss"] > NOT_ATTAINED:
        verdict = "not attained"
    return {**out, "tolerance": tolerance, "verdict": "unsettled, " + verdict}


def settle(out_path, paths):
    """Judges again, by `judge`, the cells of the shards `paths` left "unsettled, search slower" (the
    search's answer as they recorded it; the maps drawn again): a line each in out_path, with the
    cell's map, x0 and the commit of its search (`of`)."""
    rows = [json.loads(line) for path in paths for line in Path(path).read_text().splitlines()]
    commit = shard_commit()
    with open(out_path, "a") as out:
        for r in rows:
            if r["verdict"] != "unsettled, search slower":
                continue
            kind, reading, kappa, bounds = map_case(r["map"])
            fine = synthesize(kind, kappa, reading, Window(*bounds, 2 * COARSE - 1, 2 * COARSE - 1), horizon(kappa),
                              2 * SAMPLES)
            i, j = (int(np.argmin(np.abs(axis - x))) for axis, x in zip((fine.window.theta, fine.window.omega), r["x0"]))
            if fine.V[i, j] != r["V"]:
                raise RuntimeError(f"map {r['map']} drawn again gives V = {fine.V[i, j]!r} at {r['x0']}, "
                                   f"recorded {r['V']!r}: not the map the cell was compared with")
            judged = judge(kind, kappa, r["x0"], int(fine.branch[i, j]), fine.psi[i, j], r["V"], r["V_coarse"],
                           r["T"], r["T_error"])
            out.write(json.dumps({"map": r["map"], "x0": r["x0"], "of": r["commit"], "was": r["verdict"], **judged,
                                  "commit": commit}) + "\n")


def summary(paths):
    """The cells by verdict, and every cell where the search is slower than the map."""
    rows = [json.loads(line) for path in paths for line in Path(path).read_text().splitlines()]
    verdicts = {}
    for r in rows:
        verdicts[r["verdict"]] = verdicts.get(r["verdict"], 0) + 1
    maps = len({r["map"] for r in rows})
    print(f"{len(rows)} cells of {maps} maps: {', '.join(f'{n} {v}' for v, n in sorted(verdicts.items()))}")
    for r in rows:
        if r["verdict"] in ("search missed", "unsettled, search slower"):
            exact = f", the map's extremal exactly {r['exact_s']:.12g}" if "exact_s" in r else ""
            print(f"  {r['verdict']}: map {r['map']} {r['kind']} {r['reading']} kappa={r['kappa']:.5g} "
                  f"x0=({r['x0'][0]:.6g}, {r['x0'][1]:.6g}): T = {r['T']:.12g}, V = {r['V']:.10g} "
                  f"(coarse {r['V_coarse']:.10g}){exact}")


def main(args):
    if args[:1] == ["--summary"]:
        return summary(args[1:])
    if args[:1] == ["--settle"] and len(args) > 1:
        return settle(args[1], args[2:])
    cells = 100
    if args[-2:-1] == ["--cells"] and args[-1].isdigit():
        args, cells = args[:-2], int(args[-1])
    out_path, seeds = shard_range(args, __doc__, "map")
    commit = shard_commit()
    with open(out_path, "a") as out:
        for seed in seeds:
            for row in compare(seed, cells, commit):
                out.write(json.dumps(row) + "\n")
            out.flush()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
