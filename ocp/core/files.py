"""Files written whole: every output goes to a temporary name beside its target and is renamed
over it only when complete, so that a full disk or an error midway leaves no half-written file
(the previous file, if any, stays). A failure of the file system is a `Fault`."""

import contextlib
import json
import os
import tempfile
from pathlib import Path

from .errors import Fault


def folder(path):
    """The folder `path`, created with its parents if absent (Fault if it cannot be)."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise Fault(f"cannot create the folder {path}: {err.strerror or err}") from None
    return path


@contextlib.contextmanager
def replacing(path, mode="w", **open_args):
    """A file open for writing (`mode` "w" or "wb") whose contents become `path` when the block
    ends without error; otherwise `path` is untouched and the temporary file removed."""
    path = Path(path)
    folder(path.parent)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    except OSError as err:
        raise Fault(f"cannot write {path}: {err.strerror or err}") from None
    try:
        with os.fdopen(fd, mode, **open_args) as f:
            yield f
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as err:
        raise Fault(f"cannot write {path}: {err.strerror or err}") from None
    finally:
        with contextlib.suppress(OSError):
            os.unlink(tmp)


def write_text(path, text):
    """`text` written whole to `path` (UTF-8); returns path."""
    with replacing(path, "w", encoding="utf-8", newline="") as f:
        f.write(text)
    return Path(path)


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def read_rows(path, key, what):
    """{row[key]: row} of the JSON lines at `path` (empty if absent); a line that is not a JSON object
    with `key` is a Fault naming the line and `what` the file holds."""
    rows = {}
    try:
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                if line.strip():
                    try:
                        row = json.loads(line)
                        rows[row[key]] = row
                    except (json.JSONDecodeError, KeyError, TypeError):
                        raise Fault(f"{path}, line {number}: not {what}") from None
    except FileNotFoundError:
        pass
    except (OSError, UnicodeDecodeError) as err:
        raise Fault(f"cannot read {path}: {err}") from None
    return rows
