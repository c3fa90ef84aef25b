"""What the suite writes to the terminal.

Compiled solvers print: CasADi's plugins (IPOPT, qpOASES, SUNDIALS...) write to the C file
descriptors 1 and 2, and CasADi's own messages go through Python's sys.stdout. `solver_output(to)`
points both elsewhere meanwhile, so that stdout holds only the answer (one JSON object with
--json, written by `print_json`)."""

import contextlib
import ctypes
import json
import math
import os
import sys

#: seconds a long stage (a direct solve, a search) runs before it reports its progress
QUIET_S = 2.0


def printable(text, lines=False):
    """`text` safe for a terminal: every character that is not printable (escape sequences and
    other control characters, line breaks unless `lines`, bidirectional overrides) written as its
    Python escape (ESC as \\x1b), the rest unchanged."""
    return "".join(c if c.isprintable() or (lines and c == "\n") else repr(c)[1:-1] for c in str(text))


def plain(obj):
    """JSON-ready data: numpy values as lists and floats, non-finite numbers as null."""
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if hasattr(obj, "tolist"):
        return plain(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def print_json(obj):
    """One JSON document on stdout."""
    print(json.dumps(plain(obj), indent=2, allow_nan=False))


@contextlib.contextmanager
def solver_output(to):
    """Descriptors 1 and 2, and Python's sys.stdout (and with "devnull" sys.stderr, where CasADi's
    warnings go), to `to` ("stderr": to stderr; "devnull": discarded) meanwhile. The C library's buffers are flushed before the descriptors return, or a
    solver's buffered output (e.g. feasiblesqpmethod's banner) would surface later on the real stdout."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    sink = os.open(os.devnull, os.O_WRONLY) if to == "devnull" else os.dup(2)
    os.dup2(sink, 1)
    os.dup2(sink, 2)
    try:
        with open(os.devnull, "w") if to == "devnull" else contextlib.nullcontext(sys.stderr) as python_sink, \
                contextlib.redirect_stdout(python_sink), contextlib.redirect_stderr(python_sink):
            yield
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        ctypes.CDLL(None).fflush(None)
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in saved + [sink]:
            os.close(fd)
