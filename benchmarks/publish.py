"""Regenerate every published table and figure from the current code, in one command:

    python benchmarks/publish.py [--only PART ...] [--time-tests] [--jobs 2]

Parts (all by default, in this order):

    direct-error   python benchmarks/direct_error.py --jobs 2 --markdown
                   -> the N-sweep table in benchmarks/README.md
    bench          ocp bench quick --jobs 2 --store benchmarks/results/quick.sqlite   (a fresh store)
                   ocp report benchmarks/results/quick.sqlite --out benchmarks/results/quick
                   -> the method and failure tables, the charts and the environment in
                      benchmarks/README.md; benchmarks/results/quick/ (charts, summary.md, results.csv)
    standard       ocp bench standard --jobs 2 --store benchmarks/results/standard.sqlite   (fresh)
                   ocp report benchmarks/results/standard.sqlite --out benchmarks/results/standard
                   -> the standard suite's run (its measured duration and the sum of its rows'
                      solver and total times), outcome counts, method and failure tables, charts
                      and environment in benchmarks/README.md; benchmarks/results/standard/
    figures        ocp figures --out docs/figures --format png --only (the six paper figures, two maps)
                   -> the gallery of README.md
    failure-maps   ocp failure-map swing-up --kappa 1 --grid 21 15 --jobs 2 for IPOPT, fatrop and
                   sqpmethod (fair) -> benchmarks/results/failure-maps/, their table in
                   benchmarks/README.md
    speed          python benchmarks/search_speed.py; python benchmarks/search_speed.py --kappa-table
                   --chart docs/figures; python benchmarks/search_cost.py --time-limit 30 --repeats 1;
                   python benchmarks/synthesis_speed.py
                   -> the search against the textbook method, on the standard cases and against
                      kappa (docs/figures/search_cost.png), the search across the accepted range
                      (where it is still slow), the maps against per-state solves (README.md)
    bifurcation    ocp bifurcation --store benchmarks/results/bifurcation.jsonl --jobs 2   (fresh)
                   -> ocp/synthesis/data/bifurcation.jsonl (read by ocp verify) and the table of
                      the values kappa_n in README.md
    completeness   python benchmarks/completeness.py
                   -> the residual assumption of the search's completeness as measured so far (every
                      committed shard of search_residual.py, search_vs_maps.py and
                      search_saddle_audit.py, by commit) in benchmarks/README.md; records the shards'
                      and the search code's hashes
    timings        ocp solve, ocp verify (and, with --time-tests, python -m pytest), timed here,
                   with the times of the parts above (completeness aside: seconds), and python
                   benchmarks/search_speed.py --processes (whole ocp solve processes and the search
                   alone on the standard cases) -> the table "How long things take" in README.md

Each part records, as soon as it ends, in benchmarks/results/published.json, the commit it measured, the command, the
environment (`ocp.bench.environment`), the time, and the code it ran: every project file its
commands imported, keyed by the hash of its code (`benchmarks/measured.py`: docstrings and help
texts do not count), and the package data (`data`). The generated blocks of the two READMEs are
marked and carry the same commit. The measured code must be committed first (the script refuses
uncommitted changes under ocp/ or benchmarks/*.py, so that the commit recorded is the code that
ran); then commit what it wrote. tests/test_published.py fails once the code a part ran, or the
data, differs from what it recorded: rerun this script for that part (`--only PART`).
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from measured import data_hashes

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = ROOT / "benchmarks" / "results" / "published.json"
STORE = "benchmarks/results/quick.sqlite"
REPORT = "benchmarks/results/quick"
PAPER_FIGURES = ("finch-fig1", "finch-fig2", "finch-kappa-3-4", "batista-fig1", "pivot-histories", "pivot-chart",
                 "synthesis-swing-up-circle-0.29", "synthesis-swing-up-plane-1.0")
BIFURCATION_STORE = "benchmarks/results/bifurcation.jsonl"
FAILURE_MAPS = "benchmarks/results/failure-maps"
#: the methods whose failure maps are published: (solver, configuration)
MAPPED = (("ipopt", "default"), ("fatrop", "default"), ("sqpmethod", "fair"))
BIFURCATION_DATA = "ocp/synthesis/data/bifurcation.jsonl"
PARTS = ("direct-error", "bench", "standard", "figures", "failure-maps", "speed", "bifurcation", "completeness",
         "timings")
#: the code the current part's commands ran: file -> code hash (benchmarks/measured.py)
RAN = {}


def git(*args):
    return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True, check=True).stdout.strip()


def ocp_command(*args):
    """The `ocp` command line of this interpreter (what `ocp ...` runs in this environment)."""
    return [sys.executable, "-m", "ocp.cli", *args]


def run(argv, shown, capture=True):
    """Run argv, a Python command line (printed as `shown`), through benchmarks/measured.py, which
    records the code it imports (into RAN); return (seconds, stdout); stderr passes through."""
    print(f"publish: {shown}", file=sys.stderr, flush=True)
    with tempfile.TemporaryDirectory() as folder:
        record = Path(folder) / "ran.json"
        start = time.perf_counter()
        proc = subprocess.run([argv[0], str(ROOT / "benchmarks" / "measured.py"), str(record), "--", *argv[1:]],
                              cwd=ROOT, stdout=subprocess.PIPE if capture else None, text=True,
                              env={**os.environ, "PYTHONPATH": str(ROOT / "benchmarks")})
        seconds = time.perf_counter() - start
        if proc.returncode != 0:
            sys.exit(f"publish: `{shown}` failed (exit {proc.returncode}); nothing recorded for this part")
        RAN.update(json.loads(record.read_text()))
    return seconds, proc.stdout


def replace_block(path, name, text):
    """Put `text` between the markers of block `name` in the Markdown file `path`."""
    begin = f"<!-- BEGIN generated: {name} (benchmarks/publish.py; do not edit by hand) -->"
    end = f"<!-- END generated: {name} -->"
    content = path.read_text()
    if begin not in content or end not in content:
        sys.exit(f"publish: {path.relative_to(ROOT)} has no block {name!r} (markers {begin} ... {end})")
    head, rest = content.split(begin, 1)
    _, tail = rest.split(end, 1)
    path.write_text(f"{head}{begin}\n{text.strip(chr(10)).rstrip()}\n{end}{tail}")      # keep the indentation


def stamp(record):
    """The provenance line of a generated block."""
    env = record["environment"]
    return (f"Generated by `python benchmarks/publish.py` at commit {record['commit']} on {env['time_utc']}: "
            f"Python {env['python']}, {', '.join(f'{k} {v}' for k, v in env['packages'].items() if v)}; "
            f"{env['cpu']}, {env['cores']} cores, load average {', '.join(f'{x:.1f}' for x in env['load_average'])}.")


def environment():
    from ocp.bench.environment import environment as env
    return env()


# --- parts ------------------------------------------------------------------------------------

def direct_error(commit, jobs):
    shown = f"python benchmarks/direct_error.py --jobs {jobs} --markdown"
    seconds, out = run([sys.executable, "benchmarks/direct_error.py", "--jobs", str(jobs), "--markdown"], shown)
    record = {"commit": commit, "command": shown, "seconds": seconds, "environment": environment()}
    replace_block(ROOT / "benchmarks" / "README.md", "direct-error",
                  f"    {shown}\n\n{out.strip()}\n\n{stamp(record)} Wall time {seconds:.0f} s.")
    return record


def run_suite(name, prefix, commit, jobs):
    """`ocp bench NAME` into a fresh store benchmarks/results/NAME.sqlite and `ocp report` into
    benchmarks/results/NAME/; the blocks PREFIX-run, -outcomes, -methods, -failures, -charts and
    -environment of benchmarks/README.md. Returns (record, tables)."""
    from ocp.bench import report
    from ocp.bench.store import Store

    store_name, out_name = f"benchmarks/results/{name}.sqlite", f"benchmarks/results/{name}"
    store = ROOT / store_name
    store.unlink(missing_ok=True)                       # a fresh store: nothing resumed from older code
    shutil.rmtree(ROOT / out_name, ignore_errors=True)  # no chart left from an older run
    shown_bench = f"ocp bench {name} --jobs {jobs} --store {store_name}"
    bench_s, _ = run(ocp_command("bench", name, "--jobs", str(jobs), "--store", store_name), shown_bench)
    shown_report = f"ocp report {store_name} --out {out_name}"
    report_s, out = run(ocp_command("report", store_name, "--out", out_name, "--json"), shown_report)
    tables = json.loads(out)
    env = tables["sessions"][-1]["environment"]
    opened = Store(store, write=False)
    try:
        rows = opened.results()
    finally:
        opened.close()
    solver_s, total_s, cpu_s = (sum((getattr(r, f) or 0.0) * (r.repeats or 1) for r in rows)
                                for f in ("solver_time_s", "total_time_s", "cpu_time_s"))
    record = {"commit": commit, "command": f"{shown_bench} && {shown_report}", "seconds": bench_s,
              "report_seconds": report_s, "runs": tables["runs"], "solver_seconds": solver_s,
              "total_seconds": total_s, "cpu_seconds": cpu_s, "environment": env}
    readme = ROOT / "benchmarks" / "README.md"
    load = ", ".join(f"{x:.1f}" for x in env["load_average"])
    replace_block(readme, f"{prefix}-run", f"""
    {shown_bench}
    {shown_report}

{tables['runs']} runs in {_duration(bench_s)} wall clock on {jobs} workers (the whole `ocp bench` command,
references included; load average {load} as it began, other work included), the report in
{report_s:.0f} s. Summed over the rows (every repeat): solver time (build and NLP solves)
{_duration(solver_s)}, total time (with the suite's checking) {_duration(total_s)}, CPU time
{_duration(cpu_s)}. Timing:
{'; '.join(tables['timing'])}. Outcomes: {', '.join(f'{k} {v}' for k, v in tables['outcomes'].items())}.

{stamp(record)}""")
    replace_block(readme, f"{prefix}-methods", report.markdown(tables["methods"]))
    replace_block(readme, f"{prefix}-failures", report.markdown(tables["failures"]))
    charts = sorted(Path(p).name for p in tables["files"] if p.endswith(".png"))
    replace_block(readme, f"{prefix}-charts", "\n\n".join(f"![{c[:-4]}](results/{name}/{c})" for c in charts))
    replace_block(readme, f"{prefix}-environment", "```\n" + "\n".join(f"{k}: {v}" for k, v in env.items()) + "\n```")
    return record, tables


def bench(commit, jobs):
    record, tables = run_suite("quick", "bench", commit, jobs)
    replace_block(ROOT / "benchmarks" / "README.md", "suites", suites_table(tables["runs"], record["seconds"]))
    return record


def standard(commit, jobs):
    record, tables = run_suite("standard", "standard", commit, jobs)
    counts = ["| outcome | runs |", "| --- | --- |"] + [f"| {k} | {n} |" for k, n in tables["outcomes"].items()]
    replace_block(ROOT / "benchmarks" / "README.md", "standard-outcomes",
                  "\n".join(counts) + f"\n\n(`{record['command']}` at commit {commit[:12]})")
    return record


def suites_table(runs, seconds):
    """The duration of the quick suite as measured, and of the full one estimated from it."""
    from ocp.bench import suite as suite_module

    quick, full = suite_module.load("quick"), suite_module.load("full")
    per_run = seconds / runs / quick.repeats
    estimate = per_run * len(full.pairs()) * full.repeats
    return (f"| suite | pairs | repeats | duration on 2 workers |\n| --- | --- | --- | --- |\n"
            f"| quick | {len(quick.pairs())} | {quick.repeats} | {_duration(seconds)}, measured (the run below) |\n"
            f"| full | {len(full.pairs())} | {full.repeats} | not run here; at the quick suite's "
            f"{per_run:.2g} s per pair and repeat, about {estimate / 3600:.2g} h (more: its N reach 800) |")


def figures(commit):
    only = [a for name in PAPER_FIGURES for a in ("--only", name)]
    shown = "ocp figures --out docs/figures --format png " + " ".join(only)
    seconds, _ = run(ocp_command("figures", "--out", "docs/figures", "--format", "png", *only), shown)
    record = {"commit": commit, "command": shown, "seconds": seconds, "environment": environment()}
    wrapped = shown.replace(" --only finch-kappa-3-4", " \\\n        --only finch-kappa-3-4").replace(
        " --only synthesis-swing-up-circle-0.29", " \\\n        --only synthesis-swing-up-circle-0.29")
    replace_block(ROOT / "README.md", "figures", f"    {wrapped}\n\n{stamp(record)}")
    return record


def failure_maps(commit, jobs):
    shutil.rmtree(ROOT / FAILURE_MAPS, ignore_errors=True)
    record = {"commit": commit, "command": "", "seconds": 0.0, "environment": environment()}
    lines = ["| method | cells | outcomes | wall time |", "| --- | --- | --- | --- |"]
    images = []
    for solver, configuration in MAPPED:
        argv = ["failure-map", "swing-up", "--kappa", "1", "--N", "25", "--solver", solver, "--configuration",
                configuration, "--grid", "21", "15", "--jobs", str(jobs), "--out", FAILURE_MAPS, "--json"]
        shown = "ocp " + " ".join(argv[:-1])
        seconds, out = run(ocp_command(*argv), shown)
        result = json.loads(out)
        record["command"] = f"{record['command']} && {shown}" if record["command"] else shown
        record["seconds"] += seconds
        outcomes = ", ".join(f"{k} {v}" for k, v in result["outcomes"].items())
        lines.append(f"| {result['method']} | {sum(result['outcomes'].values())} | {outcomes} | {seconds:.0f} s |")
        images += [Path(f).name for f in result["files"] if f.endswith(".png")]
    commands = "\n".join(f"    {c}" for c in record["command"].split(" && "))
    charts = "\n\n".join(f"![{name[:-4]}](results/failure-maps/{name})" for name in images)
    replace_block(ROOT / "benchmarks" / "README.md", "failure-maps",
                  f"{commands}\n\n" + "\n".join(lines) + f"\n\n{charts}\n\n{stamp(record)}")
    return record


def speed(commit):
    record = {"commit": commit, "command": "", "seconds": 0.0, "environment": environment()}
    for args, block in ((["search_speed.py"], "search-speed"),
                        (["search_speed.py", "--kappa-table", "--chart", "docs/figures"], "search-cost"),
                        (["search_cost.py", "--time-limit", "30", "--repeats", "1"], "search-range"),
                        (["search_cost.py", "--random", "30", "--seed", "0", "--time-limit", "30", "--repeats", "1"],
                         "search-random"),
                        (["search_cost.py", "--random", "30", "--seed", "0", "--wide", "--time-limit", "30",
                          "--repeats", "1"], "search-wide"),
                        (["synthesis_speed.py"], "synthesis-speed")):
        shown = f"python benchmarks/{' '.join(args)}"
        seconds, out = run([sys.executable, f"benchmarks/{args[0]}", *args[1:]], shown)
        record["command"] = f"{record['command']} && {shown}" if record["command"] else shown
        record["seconds"] += seconds
        replace_block(ROOT / "README.md", block, f"    {shown}\n\n{out.strip()}\n\n{stamp(record)}")
    return record


def bifurcation(commit, jobs):
    store = ROOT / BIFURCATION_STORE
    store.unlink(missing_ok=True)                     # fresh: nothing resumed from older code
    shown = f"ocp bifurcation --store {BIFURCATION_STORE} --jobs {jobs}"
    seconds, out = run(ocp_command("bifurcation", "--store", BIFURCATION_STORE, "--jobs", str(jobs)), shown)
    shutil.copyfile(store, ROOT / BIFURCATION_DATA)
    record = {"commit": commit, "command": shown, "seconds": seconds, "environment": environment()}
    replace_block(ROOT / "README.md", "bifurcation",
                  f"    {shown}\n\n```\n{out.strip()}\n```\n\n(copied to {BIFURCATION_DATA}, which "
                  f"`ocp verify` reads)\n\n{stamp(record)} Wall time {seconds:.0f} s.")
    return record


def timings(commit, records, time_tests, previous):
    rows, outputs = [], {}
    for shown, argv in (("ocp solve swing-up --kappa 0.75", ocp_command("solve", "swing-up", "--kappa", "0.75")),
                        ("ocp solve swing-up --kappa 0.75 --direct",
                         ocp_command("solve", "swing-up", "--kappa", "0.75", "--direct")),
                        ("ocp verify", ocp_command("verify"))):
        seconds, outputs[shown] = run(argv, shown)
        rows.append((shown, seconds, commit))
    example = outputs["ocp solve swing-up --kappa 0.75"].rstrip().splitlines()
    replace_block(ROOT / "README.md", "solve-example",
                  "\n".join(["    $ ocp solve swing-up --kappa 0.75"] + [f"    {line}" for line in example]))
    totals = outputs["ocp verify"].rstrip().splitlines()[-1]
    replace_block(ROOT / "README.md", "verify-totals", f"    {totals}\n\n(`ocp verify` at commit {commit[:12]})")
    for part in ("figures", "bench", "standard", "direct-error", "failure-maps", "speed", "bifurcation"):
        r = records.get(part) or previous.get(part)
        if r:
            suite = part in ("bench", "standard")
            rows.append((r["command"].split(" && ")[0] if suite else r["command"], r["seconds"], r["commit"]))
            if suite:
                rows.append((r["command"].split(" && ")[1], r["report_seconds"], r["commit"]))
    tests = previous.get("timings", {}).get("tests")
    if time_tests:
        seconds, _ = run([sys.executable, "-m", "pytest", "-q", "--deselect", "tests/test_published.py"],
                         "python -m pytest", capture=False)
        tests = {"seconds": seconds, "commit": commit}
    if tests:
        rows.append(("python -m pytest", tests["seconds"], tests["commit"]))
    record = {"commit": commit, "command": "timed by benchmarks/publish.py", "environment": environment(),
              "rows": [list(r) for r in rows], "tests": tests}
    lines = ["| command | wall time | measured at |", "| --- | --- | --- |"]
    lines += [f"| `{c}` | {_duration(s)} | {k[:10]} |" for c, s, k in rows]
    shown = "python benchmarks/search_speed.py --processes"
    _, processes = run([sys.executable, "benchmarks/search_speed.py", "--processes"], shown)
    lines += ["", f"The standard cases, a whole process (its bytecode compiled first, as `pip install` does) and the search alone (`{shown}`):", "", processes.strip()]
    shown = "python benchmarks/search_speed.py --breakdown"
    _, split = run([sys.executable, "benchmarks/search_speed.py", "--breakdown"], shown)
    lines += ["", f"Where the search alone spends that time: the compiled integration of the extremals, and the "
                  f"rest, the scan's Python (`{shown}`):", "", split.strip()]
    replace_block(ROOT / "README.md", "timings", "\n".join(lines) + f"\n\n{stamp(record)}")
    return record


def completeness(commit):
    from completeness import inputs
    shown = "python benchmarks/completeness.py"
    before = inputs()
    seconds, out = run([sys.executable, "benchmarks/completeness.py"], shown)
    if inputs() != before:
        sys.exit("publish: a shard or the search's code changed while the completeness table was read; run it again")
    record = {"commit": commit, "command": shown, "seconds": seconds, "environment": environment(), "inputs": before}
    replace_block(ROOT / "benchmarks" / "README.md", "completeness", f"    {shown}\n\n{out.strip()}\n\n{stamp(record)}")
    return record


def _duration(seconds):
    """A wall time to two significant digits (run-to-run spread on a shared machine is 10-30 %)."""
    return f"{seconds:.2g} s" if seconds < 90 else f"{seconds / 60:.2g} min"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", action="append", choices=PARTS, help="only this part (repeatable)")
    parser.add_argument("--jobs", type=int, default=2, help="worker processes of the bench and the N-sweep")
    parser.add_argument("--time-tests", action="store_true", help="also time the test suite (about 3 min)")
    parser.add_argument("--allow-dirty", action="store_true",
                        help="publish from uncommitted code (recorded as such; tests/test_published.py then fails)")
    args = parser.parse_args()
    dirty = git("status", "--porcelain", "--untracked-files=no", "--", "ocp", "benchmarks/*.py")
    if dirty and not args.allow_dirty:
        sys.exit("publish: commit the measured code first (uncommitted changes under ocp/ or benchmarks/*.py):\n"
                 + dirty)
    commit = git("rev-parse", "HEAD") + ("+dirty" if dirty else "")
    previous = json.loads(MANIFEST.read_text()) if MANIFEST.exists() else {}
    records = {}
    for part in args.only or PARTS:
        RAN.clear()
        if part == "direct-error":
            records[part] = direct_error(commit, args.jobs)
        elif part == "bench":
            records[part] = bench(commit, args.jobs)
        elif part == "standard":
            records[part] = standard(commit, args.jobs)
        elif part == "figures":
            records[part] = figures(commit)
        elif part == "failure-maps":
            records[part] = failure_maps(commit, args.jobs)
        elif part == "speed":
            records[part] = speed(commit)
        elif part == "bifurcation":
            records[part] = bifurcation(commit, args.jobs)
        elif part == "completeness":
            records[part] = completeness(commit)
        else:
            records[part] = timings(commit, records, args.time_tests, previous)
        records[part].update(code=dict(sorted(RAN.items())), data=data_hashes())
        manifest = {**previous, **records}                # written after each part: a later failure keeps it
        MANIFEST.write_text(json.dumps({p: manifest[p] for p in PARTS if p in manifest}, indent=1) + "\n")
        print(f"publish: wrote {MANIFEST.relative_to(ROOT)} ({part} at {commit[:12]}); commit the results",
              file=sys.stderr)


if __name__ == "__main__":
    main()
