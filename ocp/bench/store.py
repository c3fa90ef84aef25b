"""The results store: one SQLite file, written row by row by `ocp bench`, read by `ocp report`.

    sessions    one row per `ocp bench` invocation: suite, executor, environment (JSON), and the
                process writing (pid, host, started, last seen, ended)
    references  one row per problem: the reference T, switch times and structure, and its source
    results     one row per (case, method) pair: its `ocp.bench.row.Row` (JSON), the key
                of the suite settings it was run with (`settings_key`), and when it ran
    claims      the pairs being run now, each by one session

A store is marked as ocp's (SQLite `application_id`) with its schema version (`user_version`);
any other file is refused (InputError: bad input), and a store is read without changing a byte of
it or adding a file beside it (`Store(path, write=False)`): through a read-only connection, or,
where SQLite would have to write to read it (a hot journal left by a killed writer, a WAL-mode
store), from a private copy of the file and its journal in a temporary folder, recovered there.
Opened for writing, SQLite recovers a hot journal itself (rolls the interrupted transaction back),
so the same `ocp bench` command always resumes. Rows are `ocp.bench.row.Row` values, stored as
JSON and validated field by field when read: a row that is not a Row of this version is a Fault
naming it. Each row is committed as soon as it is
known, so an interrupted benchmark keeps every finished row, and a second run skips the pairs
already stored with the same settings (it resumes). Several `ocp bench` processes may write one
store: a pair is claimed in a transaction before it runs and skipped by the others while its
claimer lives (a claim of a dead process, same host: its pid is gone; another host: not seen for
STALE_S, is taken over). Export: `to_csv`, `to_json`.

`merge(out, stores)` joins stores (the shards of a suite, `ocp bench --shard I/N`, run apart) into
one: their sessions kept (renumbered, each once: a session is its process and start), references
merged (those of one problem must agree within their errors), rows of one suite's settings, each
pair once (a pair in two stores must be the same row; two runs of it are refused). It checks
everything before it writes, then writes in one transaction.
"""

import contextlib
import csv
import dataclasses
import json
import os
import shutil
import socket
import sqlite3
import tempfile
import time
from pathlib import Path

from ..core.errors import Fault, InputError
from ..core.files import replacing
from ..core.output import plain
from ..core.parallel import process_alive, timing_note
from .row import Reference, Row, from_dict, to_dict

APPLICATION_ID = 0x6F637062     # "ocpb": the SQLite header field that marks an ocp results store
VERSION = 2                     # the schema below, with rows of `ocp.bench.row` (1: untyped records)
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

#: the files SQLite may keep beside a store: a rollback journal, a write-ahead log
SIDECARS = ("-journal", "-wal")


def _reject(constant):
    raise ValueError(f"holds {constant}, not a number ocp bench stores")


def _wal(path):
    """Whether the SQLite file at `path` is in WAL mode (header bytes 18-19 are 2: SQLite's file format)."""
    with contextlib.suppress(OSError):
        with open(path, "rb") as f:
            return f.read(20)[18:20] == b"\x02\x02"
    return False


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
    `write=False` read-only for reports (module doc). InputError if absent or not an ocp store of
    this version, Fault if it cannot be read or written."""

    def __init__(self, path, write=True):
        self.path, self.copy = Path(path), None
        if not write and not self.path.is_file():
            raise InputError(f"no results store at {self.path} (run `ocp bench --store {self.path}` first)")
        if not write:
            if self.path.stat().st_size == 0:
                raise InputError(f"{self.path} is not an ocp results store (an empty file)")
            self.db = self._reader()
            with self._guard("read"):
                self._check()
            return
        with self._guard("create"):
            self.path.parent.mkdir(parents=True, exist_ok=True)
        self.db = self._connect(self.path, write=True)
        with self._guard("open"):
            if not self._check(empty_too=True):
                return
        with self._transaction("create"):
            if self.db.execute("select count(*) from sqlite_master").fetchone()[0] == 0:
                for statement in filter(str.strip, SCHEMA.split(";")):
                    self.db.execute(statement)
                self.db.execute(f"pragma application_id = {APPLICATION_ID}")
                self.db.execute(f"pragma user_version = {VERSION}")
            self._check()

    def _reader(self):
        """A connection that reads the store without writing to it or beside it: read-only, or on a
        private copy (module doc) when a journal is beside it or it is in WAL mode."""
        sidecars = [self.path.with_name(self.path.name + s) for s in SIDECARS]
        if not any(p.exists() for p in sidecars) and not _wal(self.path):
            return self._connect(self.path, write=False)
        self.copy = tempfile.TemporaryDirectory(prefix="ocp-store-")
        copy = Path(self.copy.name) / self.path.name
        with self._guard("copy"):
            shutil.copyfile(self.path, copy)
            for p in sidecars:
                with contextlib.suppress(FileNotFoundError):
                    shutil.copyfile(p, copy.with_name(p.name))
        return self._connect(copy, write=True)

    def _connect(self, path, write):
        try:
            if write:
                return sqlite3.connect(path, timeout=BUSY_S, isolation_level=None)
            return sqlite3.connect(path.resolve().as_uri() + "?mode=ro", uri=True, timeout=BUSY_S)
        except (OSError, sqlite3.Error) as err:
            raise Fault(f"cannot open the results store {self.path}: {err}") from None

    def _check(self, empty_too=False):
        """InputError unless this is an ocp store of this version (or, with `empty_too`, a database
        without tables: then True)."""
        try:
            if empty_too and self.db.execute("select count(*) from sqlite_master").fetchone()[0] == 0:
                return True
            app, version = (self.db.execute(f"pragma {p}").fetchone()[0] for p in ("application_id", "user_version"))
        except sqlite3.DatabaseError as err:
            if "not a database" not in str(err):
                raise
            raise InputError(f"{self.path} is not an ocp results store (not a SQLite file); it is left untouched") \
                from None
        if app != APPLICATION_ID:
            raise InputError(f"{self.path} is not an ocp results store (a SQLite file of another kind, or written by "
                             f"an ocp older than schema versions); it is left untouched")
        if version != VERSION:
            raise InputError(f"{self.path} is an ocp results store of schema version {version}; this ocp reads "
                             f"version {VERSION} (run the suite into a new store)")

    @contextlib.contextmanager
    def _guard(self, what):
        """sqlite and OS errors as a Fault naming the store."""
        try:
            yield
        except InputError:
            raise
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
                # SQLite may have rolled back already (a full disk does): the first error is the one to tell
                if self.db.in_transaction:
                    with contextlib.suppress(sqlite3.Error):
                        self.db.execute("rollback")
                raise

    def _rows(self, sql, *args):
        with self._guard("read"):
            return self.db.execute(sql, args).fetchall()

    def close(self):
        self.db.close()
        if self.copy is not None:
            self.copy.cleanup()

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
        """[{id, suite, executor, environment}] of every session; Fault naming one that is not as ocp
        bench writes it (its environment a JSON object)."""
        sessions = []
        for i, suite, executor, env in self._rows("select id, suite, executor, environment from sessions order by id"):
            try:
                environment = json.loads(env, parse_constant=_reject)
            except (TypeError, ValueError, RecursionError) as err:
                raise Fault(f"the results store {self.path} is corrupted: session {i}'s environment is not JSON "
                            f"({err})") from None
            if not isinstance(environment, dict) or not isinstance(suite, str) or not isinstance(executor, str):
                raise Fault(f"the results store {self.path} is corrupted: session {i} is not as ocp bench writes it "
                            f"(its suite and executor text, its environment a JSON object)")
            sessions.append({"id": i, "suite": suite, "executor": executor, "environment": environment})
        return sessions

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

    def add_reference(self, problem_key, reference):
        """Store the Reference of a problem."""
        with self._transaction():
            self.db.execute("insert or replace into references_ values (?, ?)",
                            (problem_key, json.dumps(to_dict(reference), allow_nan=False)))

    def references(self):
        """{problem key: Reference}; Fault naming one that is not a Reference."""
        refs = {}
        for key, text in self._rows("select problem_key, record from references_"):
            refs[key] = self._read(Reference, text, f"the reference of {key!r}")
        return refs

    def add_result(self, case_key, method_key, session, row, settings_key="", started=None):
        """Store the pair's Row (or its plain data, `ocp.bench.row.to_dict`), replacing a row of
        other settings, and release its claim."""
        record = to_dict(row) if isinstance(row, Row) else row
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
        """Every stored Row, in insertion order; Fault for one that is not a Row of this version, before
        any is returned."""
        return [self._read(Row, text, f"row {rowid}")
                for rowid, text in self._rows("select rowid, record from results order by rowid")]

    def dump(self):
        """Everything `merge` copies: {sessions: [row tuples], references: {key: Reference},
        results: [(row tuple, Row)]}, each validated (Fault for one that is not as ocp bench writes it)."""
        self.sessions()
        return {"sessions": self._rows("select id, suite, executor, environment, pid, host, started, seen, ended "
                                       "from sessions order by id"),
                "references": self.references(),
                "results": [(r, self._read(Row, r[4], f"row {r[0]} | {r[1]}"))
                            for r in self._rows("select case_key, method_key, settings_key, session, record, started, "
                                                "finished from results order by rowid")]}

    def _read(self, kind, text, what):
        """The value of dataclass `kind` stored as JSON `text`, or Fault naming `what` and its fault."""
        try:
            return from_dict(kind, json.loads(text, parse_constant=_reject))
        except (TypeError, ValueError, RecursionError) as err:
            problem = str(err) if isinstance(err, ValueError) and not isinstance(err, json.JSONDecodeError) else \
                f"is not JSON ({err})"
            raise Fault(f"the results store {self.path} is corrupted: {what} {problem}") from None


def merge(out, paths):
    """Merge the stores at `paths` into the store `out` (created if absent; module doc). Returns
    {stores, sessions, references, rows: how many added, total: rows in `out`}. InputError, before
    anything is written, for rows of different suite settings, a pair with different rows in two
    stores, references of a problem that disagree, or `out` among `paths`."""
    out = Path(out)
    for path in paths:
        if out.exists() and Path(path).exists() and os.path.samefile(out, path):
            raise InputError(f"{out} is both the merged store and a store to merge; name a new file (or another store)")
    names = [str(out), *map(str, paths)] if out.is_file() and out.stat().st_size else list(map(str, paths))
    dumps = []
    for name in names:
        store = Store(name, write=False)
        try:
            dumps.append(store.dump())
        finally:
            store.close()
    base = dumps.pop(0) if len(names) > len(paths) else {"sessions": [], "references": {}, "results": []}
    plan = _plan(base, dumps, names[len(names) - len(paths):], names[0])
    target = Store(out)
    with target._transaction("merge into"):
        target.db.executemany("insert into sessions values (?, ?, ?, ?, ?, ?, ?, ?, ?)", plan["sessions"])
        target.db.executemany("insert into references_ values (?, ?)", plan["references"])
        target.db.executemany("insert into results values (?, ?, ?, ?, ?, ?, ?)", plan["results"])
    total = len(target.done())
    target.close()
    return {"stores": len(paths), "sessions": len(plan["sessions"]), "references": len(plan["references"]),
            "rows": len(plan["results"]), "total": total}


def _plan(base, dumps, names, base_name):
    """The sessions, references and rows (tuples of the tables) that merging `dumps` (of the stores
    `names`) adds to a store holding `base` (named `base_name`); InputError for a conflict."""
    identity = {(s[1], s[2], s[4], s[5], s[6]): s[0] for s in base["sessions"]}     # suite, executor, pid, host, start
    next_id = max(identity.values(), default=0) + 1
    refs = {key: (ref, base_name) for key, ref in base["references"].items()}
    rows = {(r[0], r[1]): (row, base_name) for r, row in base["results"]}
    settings = {r[2]: base_name for r, _ in base["results"]}
    plan = {"sessions": [], "references": [], "results": []}
    for name, dump in zip(names, dumps):
        ids = {}
        for i, suite, executor, env, pid, host, started, seen, ended in dump["sessions"]:
            key = (suite, executor, pid, host, started)
            if key not in identity:
                identity[key], next_id = next_id, next_id + 1
                plan["sessions"].append((identity[key], suite, executor, env, pid, host, started, seen,
                                         seen if ended is None else ended))     # a merged session writes no more
            ids[i] = identity[key]
        for key, ref in dump["references"].items():
            if key not in refs:
                refs[key] = ref, name
                plan["references"].append((key, json.dumps(to_dict(ref), allow_nan=False)))
            elif not _agree(ref, refs[key][0]):
                raise InputError(f"the references of {key} in {refs[key][1]} (T = {refs[key][0].T}) and in {name} "
                                 f"(T = {ref.T}) disagree beyond their errors: merge stores run by the same code")
        for (case, method, settings_key, session, record, started, finished), row in dump["results"]:
            settings.setdefault(settings_key, name)
            if len(settings) > 1:
                (a, a_name), (b, b_name) = list(settings.items())[:2]
                raise InputError(f"{a_name} and {b_name} hold rows of different suite settings ({_settings(a)}; "
                                 f"{_settings(b)}): merge the stores of one suite's settings")
            row = _renumbered(row, ids)
            if (case, method) in rows:
                if _untimed(row) != _untimed(rows[case, method][0]):
                    raise InputError(f"{row.case_label} | {row.label} is in {rows[case, method][1]} and in {name} "
                                     f"with different rows (two runs of it): merge stores of disjoint pairs, such "
                                     f"as the shards of one suite (ocp bench --shard I/N)")
                continue
            rows[case, method] = row, name
            plan["results"].append((case, method, settings_key, ids.get(session, session),
                                    json.dumps(plain(to_dict(row)), allow_nan=False), started, finished))
    return plan


def _renumbered(row, ids):
    """`row` with the sessions it names (how it was timed) renumbered by `ids`."""
    others = tuple(ids.get(i, i) for i in row.timing.concurrent_sessions)
    if others == row.timing.concurrent_sessions:
        return row
    return dataclasses.replace(row, timing=dataclasses.replace(
        row.timing, concurrent_sessions=others, note=timing_note(row.timing.workers or 1, others)))


def _untimed(row):
    """A row's data without how it was timed (which a merge renumbers)."""
    return {k: v for k, v in to_dict(row).items() if k != "timing"}


def _agree(a, b):
    """Whether two References of one problem agree: both without an optimum, or the same structure
    and branch with T within the sum of their errors."""
    if a.T is None or b.T is None:
        return a.T is None and b.T is None
    return (a.arc_signs, a.branch) == (b.arc_signs, b.branch) and \
        abs(a.T - b.T) <= (a.T_error or 0.0) + (b.T_error or 0.0)


def _settings(key):
    """A settings key (`ocp.bench.suite.Suite.settings_key`) in words."""
    try:
        return ", ".join(f"{k} = {'none' if v is None else v}" for k, v in json.loads(key).items())
    except (TypeError, ValueError, AttributeError):
        return repr(key)[:60]


def flat(record, prefix=""):
    """A record as one level of columns: nested keys joined by '.', lists as JSON text."""
    out = {}
    for key, value in record.items():
        if isinstance(value, dict):
            out.update(flat(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = json.dumps(value) if isinstance(value, list) else value
    return out


def to_csv(rows, path):
    """Write Rows to a CSV file (whole, `ocp.core.files`), one line each, the union of their columns."""
    rows = [flat(to_dict(r)) for r in rows]
    columns = list(dict.fromkeys(k for row in rows for k in row))
    with replacing(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, columns)
        writer.writeheader()
        writer.writerows(rows)
    return path


def to_json(rows, path):
    """Write Rows to a JSON file (whole)."""
    text = json.dumps([to_dict(r) for r in rows], indent=1, allow_nan=False) + "\n"
    with replacing(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path
