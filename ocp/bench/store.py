"""The results store: one SQLite file, written row by row by `ocp bench`, read by `ocp report`.

    sessions    one row per `ocp bench` invocation: suite, executor, environment (JSON), and the
                process writing (pid, host, started, last seen, ended)
    references  one row per problem: the reference T, switch times and structure, and its source
    results     one row per (case, method) pair: the record of `ocp.bench.runner` (JSON), the key
                of the suite settings it was run with (`settings_key`), and when it ran
    claims      the pairs being run now, each by one session

A store is marked as ocp's (SQLite `application_id`) with its schema version (`user_version`);
any other file is refused, and a store is read through a read-only connection (`Store(path,
write=False)`): reading never changes a byte of it. Each row is committed as soon as it is
known, so an interrupted benchmark keeps every finished row, and a second run skips the pairs
already stored with the same settings (it resumes). Several `ocp bench` processes may write one
store: a pair is claimed in a transaction before it runs and skipped by the others while its
claimer lives (a claim of a dead process, same host: its pid is gone; another host: not seen for
STALE_S, is taken over). Export: `to_csv`, `to_json`.
"""

import contextlib
import csv
import json
import math
import os
import socket
import sqlite3
import time
from pathlib import Path

from ..core.errors import Fault, InputError
from ..core.files import replacing
from ..core.output import plain
from .suite import SEARCH_FAMILY

APPLICATION_ID = 0x6F637062     # "ocpb": the SQLite header field that marks an ocp results store
VERSION = 1                     # the schema below
BUSY_S = 60.0                   # how long a writer waits for another's transaction
STALE_S = 3600.0                # a claim from another host not seen for this long is taken over
HOST = socket.gethostname()

SCHEMA = """
create table sessions (id integer primary key, suite text, executor text, environment text,
                       pid integer, host text, started real, seen real, ended real);
create table references_ (problem_key text primary key, record text);
create table results (case_key text, method_key text, settings_key text, session integer, record text,
                      started real, finished real, primary key (case_key, method_key));
create table claims (case_key text, method_key text, session integer, primary key (case_key, method_key));
"""

#: what every stored record holds, as `ocp report` and `ocp figures` read it: key -> accepted types
_NUMBER, _MAYBE = (float, int), (float, int, type(None))
RECORD = {"case": (str,), "case_label": (str,), "problem": (str,), "family": (str,), "label": (str,),
          "outcome": (str,), "status": (str,), "success": (bool,), "guess": (str, int), "N": (int, type(None)),
          "T_ref": _MAYBE, "T_ref_error": _MAYBE, "T_minus_ref": _MAYBE, "total_time_s": _NUMBER, "timing": (dict,)}
#: and what a record of the right structure (outcome in GOOD, `ocp.bench.report.GOOD`) holds besides
GOOD, GOOD_RECORD = ("ok", "inaccurate"), {"T": _NUMBER, "T_error": _MAYBE, "T_minus_ref": _NUMBER}


def _reject(constant):
    raise ValueError(f"{constant} is not a number ocp bench stores")


def process_alive(pid):
    """Whether the process `pid` of this host runs (a zombie has ended; POSIX)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return True


def _alive(pid, host, seen, ended, now):
    """Whether a session's process may still be writing: not ended and, on this host, running; on
    another host (or where a pid cannot be checked), seen within STALE_S."""
    if ended is not None:
        return False
    if host != HOST or os.name != "posix" or not isinstance(pid, int):
        return seen is not None and now - seen < STALE_S
    return process_alive(pid)


class Store:
    """An ocp results store: `write=True` opens it for `ocp bench` (created if absent or empty),
    `write=False` read-only for reports (InputError if absent). Fault for a file that is not an
    ocp store of this version, or that cannot be read or written."""

    def __init__(self, path, write=True):
        self.path = Path(path)
        if not write and not self.path.is_file():
            raise InputError(f"no results store at {self.path} (run `ocp bench --store {self.path}` first)")
        if self.path.is_file() and self.path.stat().st_size > 0:
            self.db = self._connect(write=False)
            with self._guard("read"):
                self._check()
            if not write:
                return
            self.db.close()
        if not write:
            raise Fault(f"{self.path} is not an ocp results store (an empty file)")
        with self._guard("create"):
            self.path.parent.mkdir(parents=True, exist_ok=True)
        self.db = self._connect(write=True)
        with self._transaction("create"):
            if self.db.execute("select count(*) from sqlite_master").fetchone()[0] == 0:
                for statement in filter(str.strip, SCHEMA.split(";")):
                    self.db.execute(statement)
                self.db.execute(f"pragma application_id = {APPLICATION_ID}")
                self.db.execute(f"pragma user_version = {VERSION}")
            self._check()

    def _connect(self, write):
        try:
            if write:
                return sqlite3.connect(self.path, timeout=BUSY_S, isolation_level=None)
            return sqlite3.connect(self.path.resolve().as_uri() + "?mode=ro", uri=True, timeout=BUSY_S)
        except (OSError, sqlite3.Error) as err:
            raise Fault(f"cannot open the results store {self.path}: {err}") from None

    def _check(self):
        """Fault unless this is an ocp store of this version."""
        app, version = (self.db.execute(f"pragma {p}").fetchone()[0] for p in ("application_id", "user_version"))
        if app != APPLICATION_ID:
            raise Fault(f"{self.path} is not an ocp results store (a SQLite file of another kind, or written by an "
                        f"ocp older than schema versions); it is left untouched")
        if version != VERSION:
            raise Fault(f"{self.path} is an ocp results store of schema version {version}; this ocp reads version "
                        f"{VERSION} (run the suite into a new store)")

    @contextlib.contextmanager
    def _guard(self, what):
        """sqlite and OS errors as a Fault naming the store."""
        try:
            yield
        except sqlite3.DatabaseError as err:
            raise Fault(f"cannot {what} the results store {self.path}: {err} (a corrupted or foreign file?)") from None
        except (sqlite3.Error, OSError, ValueError) as err:
            raise Fault(f"cannot {what} the results store {self.path}: {err}") from None

    @contextlib.contextmanager
    def _transaction(self, what="write"):
        """One write transaction, taken before anything is read (BEGIN IMMEDIATE)."""
        with self._guard(what):
            self.db.execute("begin immediate")
            try:
                yield
                self.db.execute("commit")
            except BaseException:
                self.db.execute("rollback")
                raise

    def _rows(self, sql, *args):
        with self._guard("read"):
            return self.db.execute(sql, args).fetchall()

    def close(self):
        self.db.close()

    # --- sessions and claims --------------------------------------------------------------------

    def open_session(self, suite, executor, environment):
        """Record one benchmark invocation by this process; returns its id."""
        now = time.time()
        with self._transaction():
            cur = self.db.execute("insert into sessions (suite, executor, environment, pid, host, started, seen) "
                                  "values (?, ?, ?, ?, ?, ?, ?)",
                                  (suite, executor, json.dumps(plain(environment)), os.getpid(), HOST, now, now))
        return cur.lastrowid

    def end_session(self, session):
        """The session's end: its claims released."""
        with self._transaction():
            self.db.execute("update sessions set ended = ? where id = ?", (time.time(), session))
            self.db.execute("delete from claims where session = ?", (session,))

    def sessions(self):
        try:
            return [{"id": i, "suite": s, "executor": e, "environment": json.loads(env)}
                    for i, s, e, env in self._rows("select id, suite, executor, environment from sessions order by id")]
        except (TypeError, ValueError) as err:
            raise Fault(f"the results store {self.path} is corrupted: a session's environment is not JSON ({err})")

    def _live_sessions(self, now):
        rows = self.db.execute("select id, pid, host, seen, ended, started from sessions").fetchall()
        return {i: (started, seen) for i, pid, host, seen, ended, started in rows
                if _alive(pid, host, seen, ended, now)}

    def claim(self, case_key, method_key, settings_key, session):
        """Claim the pair for `session`, in one transaction: "stored" if it is stored with these
        settings, "claimed" if another live session runs it (the claim is left), else "mine"."""
        now = time.time()
        with self._transaction():
            self.db.execute("update sessions set seen = ? where id = ?", (now, session))
            stored = self.db.execute("select 1 from results where case_key = ? and method_key = ? and settings_key = ?",
                                     (case_key, method_key, settings_key)).fetchone()
            if stored:
                return "stored"
            owner = self.db.execute("select session from claims where case_key = ? and method_key = ?",
                                    (case_key, method_key)).fetchone()
            if owner and owner[0] != session and owner[0] in self._live_sessions(now):
                return "claimed"
            self.db.execute("insert or replace into claims values (?, ?, ?)", (case_key, method_key, session))
            return "mine"

    def concurrent(self, session, since):
        """The other sessions that were writing to this store at some time since `since` (a
        time.time()); a dead one's writing ended when it was last seen."""
        now = time.time()
        with self._guard("read"):
            live = self._live_sessions(now)
            rows = self.db.execute("select id, started, seen, ended from sessions where id != ? and started <= ?",
                                   (session, now)).fetchall()
        return [i for i, started, seen, ended in rows
                if (now if i in live else (ended if ended is not None else seen)) >= since]

    # --- rows -----------------------------------------------------------------------------------

    def add_reference(self, problem_key, record):
        with self._transaction():
            self.db.execute("insert or replace into references_ values (?, ?)",
                            (problem_key, json.dumps(plain(record), allow_nan=False)))

    def references(self):
        try:
            return {k: json.loads(r) for k, r in self._rows("select problem_key, record from references_")}
        except (TypeError, ValueError) as err:
            raise Fault(f"the results store {self.path} is corrupted: a reference is not JSON ({err})")

    def add_result(self, case_key, method_key, session, record, settings_key="", started=None):
        """Store the pair's record (replacing a row of other settings) and release its claim."""
        now = time.time()
        with self._transaction():
            self.db.execute("insert or replace into results values (?, ?, ?, ?, ?, ?, ?)",
                            (case_key, method_key, settings_key, session, json.dumps(plain(record), allow_nan=False),
                             now if started is None else started, now))
            self.db.execute("delete from claims where case_key = ? and method_key = ?", (case_key, method_key))
            self.db.execute("update sessions set seen = ? where id = ?", (now, session))

    def done(self, settings_key=None):
        """The (case_key, method_key) pairs stored (with `settings_key` if given)."""
        if settings_key is None:
            return set(self._rows("select case_key, method_key from results"))
        return set(self._rows("select case_key, method_key from results where settings_key = ?", settings_key))

    def results(self):
        """Every stored record, in insertion order; Fault for a row that is not a record of ocp bench
        (`RECORD`), before any is returned."""
        records = []
        for rowid, text in self._rows("select rowid, record from results order by rowid"):
            try:
                record = json.loads(text, parse_constant=_reject)
                problem = _invalid(record)
            except (TypeError, ValueError, RecursionError) as err:
                problem = f"not JSON ({err})"
            if problem:
                raise Fault(f"the results store {self.path} is corrupted: row {rowid} {problem}")
            records.append(record)
        return records


def _invalid(record):
    """What is wrong with a stored record (None when it has every RECORD field, well typed)."""
    if not isinstance(record, dict):
        return f"is a {type(record).__name__}, not a record"
    schema = dict(RECORD, **(GOOD_RECORD if record.get("outcome") in GOOD else {}))
    for key, types in schema.items():
        if key not in record:
            return f"has no {key!r}"
        value = record[key]
        if (bool in types) != isinstance(value, bool) or not isinstance(value, types) or (
                isinstance(value, float) and not math.isfinite(value)):
            return f"has {key} = {str(value)[:40]!r}, not of the type ocp bench writes"
    if (record["N"] is None) != (record["family"] == SEARCH_FAMILY):
        return f"has N = {record['N']} for the family {record['family'][:40]!r}"
    if not isinstance(record["timing"].get("note"), str):
        return "has no timing note"
    return None


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
    """Write records to a CSV file (whole, `ocp.core.files`), one row each, the union of their columns."""
    rows = [flat(r) for r in records]
    columns = list(dict.fromkeys(k for row in rows for k in row))
    with replacing(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, columns)
        writer.writeheader()
        writer.writerows(rows)
    return path


def to_json(records, path):
    """Write records to a JSON file (whole)."""
    text = json.dumps(records, indent=1, allow_nan=False, default=str) + "\n"
    with replacing(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path
