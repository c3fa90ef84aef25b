"""The memory and time of a direct NLP over its size: the evidence behind the limits that the
transcriptions declare (`ocp.direct.base.SIZE_MAX`, checked by `Transcription.check_settings`).

    nice python benchmarks/direct_size.py [--out benchmarks/direct_size.jsonl] [--memory-gb 4] [--timeout 150]

Each probe runs in its own process, bounded (address space `--memory-gb` by RLIMIT_AS, wall time
`--timeout`), so that no probe can exhaust a shared machine: it builds the NLP of swing-up
kappa = 1 (a fresh process: nothing cached) and solves one start (ocp's straight guess) with IPOPT at ocp's
quiet defaults. Recorded per probe (one JSON line, appended; a probe already in the file is not
rerun): the peak resident memory (the child's own ru_maxrss; VmHWM when it is stopped at the timeout), the build and solve times, IPOPT's
iterations and status, or how the probe ended ("memory": the address-space limit was hit,
"timeout"). Along a row of growing sizes a probe that ends in memory or timeout ends the row.
A probe of a size that ocp refuses sets the setting past its check (`object.__setattr__`): this
script measures where the limit should be, beyond where it is.
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import time

#: (transcription, fixed settings, the setting that grows, its values) per row
ROWS = [
    ("multiple-shooting", {"integrator": "rk4", "M": 4}, "N", (500, 1000, 2000, 5000)),
    ("multiple-shooting", {"integrator": "rk4", "M": 16}, "N", (500, 1000, 1250, 2000, 5000)),
    ("multiple-shooting", {"integrator": "rk4", "M": 64}, "N", (50, 100, 250, 500, 1000, 2000, 5000)),
    ("multiple-shooting", {"integrator": "collocation", "M": 4}, "N", (250, 500, 1000, 2000, 5000)),
    ("multiple-shooting", {"integrator": "collocation", "M": 16}, "N", (250, 500, 1000, 2000)),
    ("multiple-shooting", {"integrator": "collocation", "M": 64}, "N", (100, 250, 500, 1000)),
    ("multiple-shooting", {"integrator": "cvodes"}, "N", (50, 100, 200, 500, 1000)),
    ("direct-collocation", {"degree": 3}, "N", (500, 1000, 2000, 5000)),
    ("direct-collocation", {"degree": 9}, "N", (500, 1000, 2000, 5000)),
]

CHILD = r"""
import json, sys
import ocp
from ocp.direct import TRANSCRIPTIONS, default_guesses
from ocp.direct import solve
name, settings = sys.argv[1], json.loads(sys.argv[2])
method = TRANSCRIPTIONS[name]()
for key, value in settings.items():
    object.__setattr__(method, key, value)
problem = ocp.swing_up(1.0)
sol = solve(problem, method, guess=default_guesses(problem, method.N)[0])
import resource
print(json.dumps({"peak_rss_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024), "build_s": round(sol.build_time_s, 2),
                  "solve_s": round(sol.solve_time_s, 2), "iterations": sol.iterations, "status": sol.status.name.lower()}))
"""


def _peak_mb(pid):
    """The peak resident memory of a running process (VmHWM, MB), read before it is stopped."""
    with open(f"/proc/{pid}/status") as f:
        return next(round(int(line.split()[1]) / 1024) for line in f if line.startswith("VmHWM"))


def probe(name, settings, memory_gb, timeout):
    """One bounded probe (a dict: the settings, peak RSS in MB, times, or how it ended)."""
    limit = int(memory_gb * 2**30)

    def bound():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        os.nice(10)

    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-c", CHILD, name, json.dumps(settings)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, preexec_fn=bound, text=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        ended = "done" if proc.returncode == 0 else "memory" if ("bad_alloc" in err or "MemoryError" in err) \
            else f"error: {err.strip().splitlines()[-1][:200] if err.strip() else proc.returncode}"
        peak = None
    except subprocess.TimeoutExpired:
        peak = _peak_mb(proc.pid)
        proc.kill()
        proc.communicate()
        out, ended = "", "timeout"
    row = {"transcription": name, **settings, "ended": ended, "wall_s": round(time.perf_counter() - start, 1),
           "memory_gb_limit": memory_gb, "timeout_s": timeout}
    if peak is not None:
        row["peak_rss_mb"] = peak
    if ended == "done":
        row.update(json.loads(out.strip().splitlines()[-1]))
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="benchmarks/direct_size.jsonl")
    parser.add_argument("--memory-gb", type=float, default=4.0)
    parser.add_argument("--timeout", type=float, default=150.0)
    parser.add_argument("--table", action="store_true", help="instead: the rows of --out as a Markdown table")
    args = parser.parse_args(argv)
    if args.table:
        return print(table(args.out))
    done = {}                           # probe key -> how it ended
    if os.path.exists(args.out):
        with open(args.out) as f:
            for row in (json.loads(line) for line in f if line.strip()):
                done[_key(row)] = row["ended"]
    for name, fixed, key, values in ROWS:
        for value in values:
            settings = dict(fixed, **{key: value})
            ended = done.get(_key(dict(settings, transcription=name)))
            if ended is None:
                row = probe(name, settings, args.memory_gb, args.timeout)
                print(json.dumps(row), flush=True)
                with open(args.out, "a") as f:
                    f.write(json.dumps(row) + "\n")
                ended = row["ended"]
            if ended != "done":
                break


def table(path):
    """The probes of `path` as a Markdown table: settings, how each ended, peak RSS, build and
    one start's solve time (two significant digits: the shared machine's noise is larger)."""
    lines = ["| transcription | settings | ended | peak RSS MB | build s | one start s |", "| --- | --- | --- | --- | --- | --- |"]
    with open(path) as f:
        for r in (json.loads(line) for line in f if line.strip()):
            settings = ", ".join(f"{k} = {r[k]}" for k in ("integrator", "M", "degree", "N") if k in r)
            cells = [r["transcription"], settings, r["ended"], r.get("peak_rss_mb", "-"),
                     f"{r['build_s']:.2g}" if "build_s" in r else "-", f"{r['solve_s']:.2g}" if "solve_s" in r else "-"]
            lines.append("| " + " | ".join(map(str, cells)) + " |")
    return "\n".join(lines)


def _key(row):
    return json.dumps({k: row.get(k) for k in ("transcription", "integrator", "M", "degree", "N")}, sort_keys=True)


if __name__ == "__main__":
    main()
