"""The reference set on disk: `reference/instances.jsonl` (a JSON line per instance, schema in
`reference/schema.json`), `reference/index.csv` (a row per instance, for a glance), found at the top
of a source checkout or, in an installed wheel, in `<prefix>/share/ocp/reference`.

    folder()          where the set is read from
    load()            {id: row} of every row (solved and skipped)
    lookup(problem)   the solved row of an ocp Problem, or None
"""

import csv
import io
import json
import math
import sysconfig
from pathlib import Path

from ..core.errors import Fault, InputError
from ..core.files import read_rows, write_text

INSTANCES = "instances.jsonl"
INDEX = "index.csv"
INDEX_COLUMNS = ("id", "status", "kind", "reading", "kappa", "theta0", "omega0", "branch", "T", "T_error",
                 "switches", "arc_signs", "ties", "runner_up_T", "relative_gap", "local_optima", "tags")


def folder():
    """The reference folder: the checkout's `reference/`, else the wheel's `share/ocp/reference`."""
    checkout = Path(__file__).resolve().parents[2] / "reference"
    if (checkout / INSTANCES).is_file():
        return checkout
    installed = Path(sysconfig.get_path("data")) / "share" / "ocp" / "reference"
    if (installed / INSTANCES).is_file():
        return installed
    raise Fault(f"the reference set is missing: neither {checkout / INSTANCES} nor {installed / INSTANCES} exists")


def read(path):
    """{id: row} of the JSON lines at `path` (empty if absent); a malformed line is a Fault."""
    return read_rows(path, "id", "a row of the reference set")


_cache = {}


def load(path=None):
    """{id: row} of the reference set (read once per path)."""
    path = Path(path) if path else folder() / INSTANCES
    if path not in _cache:
        _cache[path] = read(path)
    return _cache[path]


def instance(instance_id, path=None):
    """The solved row with this id, or InputError naming a few ids that exist."""
    rows = load(path)
    row = rows.get(instance_id)
    if row is None or row["status"] != "solved":
        near = [i for i in rows if i.split("/")[:2] == str(instance_id).split("/")[:2]][:3] or list(rows)[:3]
        why = "is skipped in" if row else "is not in"
        raise InputError(f"instance {str(instance_id)[:80]!r} {why} the reference set; ids look like {', '.join(near)} "
                         f"(see reference/index.csv)")
    return row


def _same(a, b):
    return a == b or (math.isfinite(a) and abs(a - b) <= 1e-15 * max(1.0, abs(a)))


def lookup(problem, path=None):
    """The solved row of the reference set for an ocp Problem (kind, kappa, x0 and branch equal to
    rounding), or None."""
    for row in load(path).values():
        if (row["status"] == "solved" and row["kind"] == problem.kind and row["branch_pinned"] == problem.branch
                and _same(row["kappa"], problem.kappa) and all(map(_same, row["x0"], problem.x0))):
            return row
    return None


def append(path, row):
    """One row appended to the JSON lines at `path` (an interruption keeps the rows before it)."""
    from ..synthesis.results import append as append_line

    append_line(path, row)
    _cache.pop(Path(path), None)


def index_row(row):
    """The index.csv row of a reference row."""
    out = {"id": row["id"], "status": row["status"], "kind": row["kind"], "reading": row["reading"],
           "kappa": repr(row["kappa"]), "theta0": repr(row["x0"][0]), "omega0": repr(row["x0"][1]),
           "branch": "" if row["branch_pinned"] is None else row["branch_pinned"]}
    if row["status"] == "solved":
        o, h = row["optimum"], row["hardness"]
        out.update(T=o["refined"]["T"], T_error=o["refined"]["T_error"], switches=h["switches"],
                   arc_signs=" ".join(f"{s:+d}" for s in o["arc_signs"]), ties=h["ties"],
                   runner_up_T="" if row["runner_up"] is None else repr(row["runner_up"]["T"]),
                   relative_gap="" if h["relative_gap_to_runner_up"] is None else f"{h['relative_gap_to_runner_up']:.3g}",
                   local_optima=h["local_optima"], tags=" ".join(row["tags"]))
    else:
        out["tags"] = "skipped: " + row["reason"]
    return out


def write_sorted(path, order, transform=lambda row: row):
    """Rewrite the JSON lines at `path` in the order of the ids `order` (ids not in it last), each row
    through `transform`, and the index.csv beside it."""
    rows = {i: transform(r) for i, r in read(path).items()}
    position = {i: n for n, i in enumerate(order)}
    ranked = sorted(rows.values(), key=lambda r: position.get(r["id"], len(position)))
    write_text(path, "".join(json.dumps(r) + "\n" for r in ranked))
    text = io.StringIO()
    writer = csv.DictWriter(text, INDEX_COLUMNS, restval="", lineterminator="\n")
    writer.writeheader()
    for r in ranked:
        writer.writerow(index_row(r))
    write_text(Path(path).with_name(INDEX), text.getvalue())
    _cache.pop(Path(path), None)
    return ranked
