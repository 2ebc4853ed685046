"""Command line: ``robkin COMMAND ...``. A thin layer over the library.

Each command lives in ``robkin.commands.<name>`` and provides ``register(subparsers)`` (adds its
parser, with help text and examples) and ``run(args) -> int``. Command modules import heavy
dependencies inside ``run`` so that ``robkin --help`` and simple conversions start fast.

Exit status: 0 success; 2 bad input (one line on stderr naming the file, field or joint; nothing
written); 1 a bug (traceback).
"""

from __future__ import annotations

import argparse
import errno
import importlib
import os
import sys
import warnings
from typing import Sequence

#: command name -> module under robkin.commands; order is the order shown in --help
COMMANDS = ("convert", "fk", "ik", "check", "calibrate", "info", "lint", "collision", "workspace", "estimate", "plot",
            "gui", "demo")
#: options whose value may start with '-' (a negative number): '--q -1,2' is read as '--q=-1,2'
NUMBER_OPTIONS = ("--q", "--q0", "--pose", "--base", "--mask", "--view")


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line with exit status 2 (its default) to stderr."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The ``robkin`` parser; with ``command`` (one of COMMANDS) only that command's subparser.

    Building all the subparsers (~90 options) is a good part of a one-shot command's start-up, and a
    command line naming its command needs only that one; ``robkin --help``, a bad command name and
    ``robkin`` alone get them all.
    """
    from .version import __version__

    parser = _Parser(
        prog="robkin",
        description="Convert serial-robot kinematics between DH, modified DH, PoE, RPY-XYZ, GJD and URDF "
                    "exactly, and compute with them (FK, IK, Jacobians, structure estimation).",
        epilog="Run 'robkin COMMAND --help' for a command's options and examples. The examples name "
               "rrpr.yaml, scara.yaml and arbitrary_3r.yaml, bundled with robkin (robkin demo --help "
               "shows where), and ur5.urdf and panda.urdf, real robots from the example-robot-data package.",
    )
    parser.add_argument("--version", action="version", version=f"robkin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS if command is None else (command,):
        try:
            module = importlib.import_module(f"robkin.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"robkin.commands.{name}":
                continue  # command not built yet
            raise
        p = module.register(sub)
        # library messages name options as Python keywords (tip_link=); this command shows its flags
        flags = {a.dest: s for a in p._actions for s in a.option_strings if s.startswith("--")}
        p.set_defaults(_run=module.run, _flags=flags)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit status (testable without a subprocess)."""
    from .errors import InputError

    from .commands.support.common import number_option_fix

    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser(argv[0] if argv and argv[0] in COMMANDS else None)
    args = parser.parse_args(number_option_fix(argv, NUMBER_OPTIONS))
    if not getattr(args, "_run", None):
        parser.print_help(sys.stderr)
        return 2
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = _show_warning_one_line
        try:
            if getattr(args, "threads", None) is not None:  # --threads N (fk, ik): the batch kernels' bound
                return _run_with_threads(args)
            status = int(args._run(args) or 0)
            sys.stdout.flush()  # here, so that a full disk or closed pipe is reported like any error
            return status
        except InputError as exc:
            from .messages import render_options

            print(f"robkin: error: {render_options(str(exc), args._flags)}", file=sys.stderr)
            return 2
        except KeyboardInterrupt:
            print("robkin: interrupted", file=sys.stderr)
            return 130
        except BrokenPipeError:  # the reader went away (robkin ... | head): stop quietly
            _discard_stdout()
            return 0
        except OSError as exc:
            if exc.errno not in _OUTPUT_ERRNOS:
                raise
            print(f"robkin: error: cannot write to standard output ({exc.strerror})", file=sys.stderr)
            _discard_stdout()
            return 2


def _run_with_threads(args: argparse.Namespace) -> int:
    """Run a command with the batch kernels bound to --threads; the process default comes back after
    (``main`` is also called in-process, by tests and scripts)."""
    from .threads import get_threads, set_threads

    before = get_threads()
    set_threads(args.threads)
    try:
        status = int(args._run(args) or 0)
        sys.stdout.flush()
        return status
    finally:
        set_threads(before)


#: errno values of a write that failed for lack of room or a broken device (ENOSPC, EDQUOT, EFBIG, EIO)
_OUTPUT_ERRNOS = {getattr(errno, name) for name in ("ENOSPC", "EDQUOT", "EFBIG", "EIO") if hasattr(errno, name)}


def _discard_stdout() -> None:
    """Point standard output at the null device, so that the flush at exit cannot fail a second time."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)
    except (OSError, ValueError, AttributeError):  # stdout replaced by an object without a descriptor
        pass


def _show_warning_one_line(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings (e.g. an input projected onto a valid value) as one line on stderr, no source line."""
    print(f"robkin: warning: {message}", file=sys.stderr if file is None else file)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
