"""The results store: one SQLite file, written row by row.

    sessions    one row per `ocp bench` invocation: suite, executor, environment (JSON)
    references  one row per problem: the reference T, switch times and structure, and its source
    results     one row per (case, method) pair: the record of `ocp.bench.runner` (JSON)

Each row is committed as soon as it is known, so an interrupted benchmark keeps every finished row,
and a second run skips the pairs already stored (it resumes). Export: `to_csv`, `to_json`.
"""

import csv
import json
import sqlite3
from pathlib import Path

from ..core.errors import InputError

SCHEMA = """
create table if not exists sessions (id integer primary key, suite text, executor text, environment text);
create table if not exists references_ (problem_key text primary key, record text);
create table if not exists results (case_key text, method_key text, session integer, record text,
                                    primary key (case_key, method_key));
"""


class Store:
    """An open results file (created with its tables if absent)."""

    def __init__(self, path, create=True):
        self.path = Path(path)
        if not create and not self.path.is_file():
            raise InputError(f"no results store at {self.path} (run `ocp bench --store {self.path}` first)")
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.db = sqlite3.connect(self.path)
            self.db.executescript(SCHEMA)
        except (OSError, sqlite3.Error) as err:
            raise InputError(f"cannot open the results store {self.path}: {err}") from None

    def close(self):
        self.db.close()

    def open_session(self, suite, executor, environment):
        """Record one benchmark invocation; returns its id."""
        with self.db:
            cur = self.db.execute("insert into sessions (suite, executor, environment) values (?, ?, ?)",
                                  (suite, executor, json.dumps(environment)))
        return cur.lastrowid

    def sessions(self):
        return [{"id": i, "suite": s, "executor": e, "environment": json.loads(env)}
                for i, s, e, env in self.db.execute("select id, suite, executor, environment from sessions order by id")]

    def add_reference(self, problem_key, record):
        with self.db:
            self.db.execute("insert or replace into references_ values (?, ?)", (problem_key, json.dumps(record)))

    def references(self):
        return {k: json.loads(r) for k, r in self.db.execute("select problem_key, record from references_")}

    def add_result(self, case_key, method_key, session, record):
        with self.db:
            self.db.execute("insert or replace into results values (?, ?, ?, ?)",
                            (case_key, method_key, session, json.dumps(record)))

    def done(self):
        """The (case_key, method_key) pairs already stored."""
        return set(self.db.execute("select case_key, method_key from results"))

    def results(self):
        """Every stored record, in insertion order."""
        return [json.loads(r) for (r,) in self.db.execute("select record from results order by rowid")]


def flat(record, prefix=""):
    """A record as one level of columns: nested keys joined by '.', lists as JSON text."""
    out = {}
    for key, value in record.items():
        if isinstance(value, dict):
            out.update(flat(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = json.dumps(value) if isinstance(value, list) else value
    return out


def to_csv(records, path):
    """Write records to a CSV file, one row each, the union of their columns."""
    rows = [flat(r) for r in records]
    columns = list(dict.fromkeys(k for row in rows for k in row))
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, columns)
        writer.writeheader()
        writer.writerows(rows)
    return path


def to_json(records, path):
    Path(path).write_text(json.dumps(records, indent=1, allow_nan=False, default=str) + "\n")
    return path
