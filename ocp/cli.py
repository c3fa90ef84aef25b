"""The `ocp` command line: one line per common job, `--json` for scripts.

Exit status: 0 done; 1 a solve that failed (with --json, still one object, "success": false) or a
fault of the environment (a folder not writable, a full disk, a corrupted store, standard output
closed or full); 2 bad input (one line says what was wrong and what is accepted); 130 interrupted.
No traceback reaches the user.

This module only dispatches: each command is a module of `ocp/commands/` (`ocp bench` and `ocp
report`: `ocp/bench/command.py`), listed in `COMMANDS`, with `add_commands(sub)` registering its
parser and a `run(args)` returning the exit status; the pieces they share (the strict parser, flags
made from registries, paths checked before any work) are `ocp.core.arguments`.
"""

import _thread
import argparse
import contextlib
import errno
import os
import signal
import sys
import threading
import time

from .bench import command as bench
from .commands import failure_map, figures, reference, solve, synthesis, verify
from .core.arguments import Parser
from .core.errors import Fault, InputError
from .core.output import printable

#: the command modules, in the order of `ocp --help`
COMMANDS = (solve, verify, figures, synthesis, failure_map, bench, reference)


class _Version(argparse.Action):
    """--version: the installed package's version (read only when asked)."""

    def __init__(self, option_strings, dest, **kwargs):
        super().__init__(option_strings, dest, nargs=0, help="print the version of ocp and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        from importlib.metadata import version

        print(f"ocp {version('ocp')}")
        parser.exit()


def parser():
    """The whole command line: the top parser and a subparser per command."""
    top = Parser(prog="ocp", description=__doc__.splitlines()[0])
    top.add_argument("--version", action=_Version)
    sub = top.add_subparsers(dest="command", required=True, parser_class=Parser)
    for module in COMMANDS:
        module.add_commands(sub)
    return top


def _output_broken():
    """Whether standard output cannot be written (closed, a full device, an I/O error)."""
    try:
        sys.stdout.flush()
        os.fstat(1)
    except (OSError, ValueError, AttributeError):
        return True
    return False


def _quiet_stdout():
    """Standard output to /dev/null, so that the interpreter's last flush finds nothing to fail on."""
    os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


#: seconds from SIGINT to the end of the process at the latest
INTERRUPT_GRACE = 2.0


@contextlib.contextmanager
def _interruptible(hard):
    """SIGINT honoured within INTERRUPT_GRACE seconds. Python raises KeyboardInterrupt only when the
    main thread next runs Python code, and a library may catch it (CasADi ends the running NLP solve
    with it and returns; a weakref callback ignores it). So a thread woken by the signal itself
    (`signal.set_wakeup_fd`) raises it once more after INTERRUPT_GRACE / 2 seconds (once: a second
    could cut a command's own cleanup, such as bench's line on the rows kept), and, with `hard`
    (the process is ocp's own), ends a command still running after INTERRUPT_GRACE seconds (inside
    compiled code that never looks at signals, such as CasADi building a large NLP): what is stored
    is stored row by row or written whole (`ocp.core.files`), so nothing finished is lost. In the
    main thread only."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    woken, wake = os.pipe()
    os.set_blocking(wake, False)
    stderr, stopped = os.dup(2), threading.Event()        # stderr: fd 2 may point to /dev/null meanwhile

    def watch():
        try:
            while os.read(woken, 1) != bytes([signal.SIGINT]):
                pass
            if not stopped.wait(INTERRUPT_GRACE / 2):
                _thread.interrupt_main()                # once: a second one could cut a command's own cleanup
                if not stopped.wait(INTERRUPT_GRACE / 2):
                    os.write(stderr, b"interrupted\n")   # still inside compiled code: ended here
                    os._exit(130)
            if hard:                                    # the command ended; should the interpreter's own exit
                time.sleep(INTERRUPT_GRACE)             # hang (a pool joining a stuck worker), it is ended
                os._exit(130)
        finally:
            os.close(woken)
            os.close(stderr)

    previous = signal.set_wakeup_fd(wake, warn_on_full_buffer=False)
    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    try:
        yield
    finally:
        stopped.set()
        signal.set_wakeup_fd(previous)
        if not hard:                                    # called in a process that goes on: end the thread
            os.write(wake, bytes([signal.SIGINT]))
            watcher.join()
            os.close(wake)


def _interrupted(err):
    """Whether a KeyboardInterrupt is among the causes of `err`."""
    seen = set()
    while err is not None and id(err) not in seen:
        if isinstance(err, KeyboardInterrupt):
            return True
        seen.add(id(err))
        err = err.__cause__ or err.__context__
    return False


def main(argv=None):
    if sys.stdout is None or _output_broken():        # closed: its descriptor would be reused by the next file
        print("failed: standard output is closed", file=sys.stderr)
        return 1
    with _interruptible(hard=argv is None):
        return _main(argv)


def _main(argv):
    try:
        try:
            args = parser().parse_args(argv)
            code = args.run(args)
        except SystemExit as exit_:                    # --help, --version
            code = exit_.code
        sys.stdout.flush()
        return code
    except InputError as err:
        print(f"error: {printable(err)}", file=sys.stderr)
        return 2
    except Fault as err:
        print(f"failed: {printable(err)}", file=sys.stderr)
        return 1
    except BrokenPipeError:          # the reader (e.g. `| head`) stopped reading: not an error of ours
        _quiet_stdout()
        return 0
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except OSError as err:           # a full disk or device, an I/O error, standard output closed meanwhile
        if err.errno not in (errno.ENOSPC, errno.EIO, errno.EBADF, errno.EDQUOT, errno.EFBIG):
            raise
        print(f"failed: cannot write {printable(err.filename) if err.filename else 'to standard output'}: "
              f"{printable(err.strerror)}", file=sys.stderr)
        _quiet_stdout()
        return 1
    except Exception as err:         # an interrupt that a library turned into its own error (e.g. SystemError)
        if not _interrupted(err):
            raise
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
