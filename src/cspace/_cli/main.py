"""Entry point: parses the command line and dispatches to a command module.

Each module in ``commands`` has ``register(subparsers)``, which adds its parser and sets
``run`` (a function of the parsed arguments that returns an exit code); only the module
of the command run is imported, the others listed from `commands.COMMANDS`. Library
errors become one line on standard error and exit code 2; ``--debug`` shows the
traceback instead.

Each name after the first ``--`` is marked a `FileName` before parsing (a file's path,
never a pattern, ``-`` or ``erd:NAME``), and an argument before ``--`` spelt as an
option that names an existing file or folder is refused: a list of file names handed
over without ``--`` (``--arg=x:=1.urdf``, ``--allow-dir=y.urdf``) fails
loudly rather than being read as options and leaving those files unread.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import os
import sys
from collections.abc import Sequence
from typing import Any

# Before NumPy is imported: no OpenBLAS threads (cspace multiplies no large matrices), so
# that `inspect --jobs` can fork its workers from this one-thread process.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from cspace import CspaceError, __version__
from cspace._safetext import MAX_PROBLEM_CHARS, printable

from . import exit_codes, output
from .commands import COMMANDS
from .patterns import FileName


class _Formatter(argparse.HelpFormatter):
    """argparse's help, as wide as shutil would make it, without importing shutil.

    argparse makes a formatter for every argument it adds, and each imports shutil
    (6 ms of every start-up, with the compression modules it imports) for the width.
    """

    def __init__(self, prog: str, *args: int | None, **kwargs: int | None) -> None:
        if not args and kwargs.get("width") is None:  # shutil.get_terminal_size's columns
            kwargs["width"] = output.terminal_columns() - 2
        super().__init__(prog, *args, **kwargs)  # type: ignore[arg-type]


class _Parser(argparse.ArgumentParser):
    """argparse, with usage errors as one line and exit code 2."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", _Formatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> None:  # type: ignore[override]
        output.error(f"{message} (see '{self.prog} --help')")
        sys.exit(exit_codes.NO_REPORT)


def build_parser(only: str | None = None, listed: bool = True) -> argparse.ArgumentParser:
    """The parser of every command, or of command ``only`` with the others listed.

    Args:
        only: The command to be run: the others are named with their help line, their
            modules not imported. None: every command's whole parser.
        listed: Whether the other commands are listed, for ``cspace --help``; without
            them, a run of command ``only`` makes one parser less per command.
    """
    parser = _Parser(
        prog="cspace",
        description="The true shape of a robot's configuration space.",
    )
    parser.add_argument("--version", action="version", version=f"cspace {__version__}")
    parser.add_argument(
        "--debug", action="store_true", help="show a Python traceback when something fails"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name, summary in COMMANDS.items():
        if only is None or name == only:
            importlib.import_module(f"{__package__}.commands.{name}").register(sub)
        elif listed:
            sub.add_parser(name, help=summary)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the tool; return its exit code."""
    if argv is None:  # run as the program (the script, python -m cspace)
        # What is imported by now lives until the process ends: the cyclic collector need
        # not walk it again at each collection while the command imports the rest
        # (Pinocchio, NumPy): 2.5 % of what a URDF's inspect executes. Not when called
        # with arguments, from another program whose objects are not ours to freeze.
        gc.freeze()
    given = list(sys.argv[1:] if argv is None else argv)
    if "_ARGCOMPLETE" in os.environ:  # a shell asking for completions (cspace completion)
        import argcomplete

        argcomplete.autocomplete(build_parser())  # answers and exits
    named = next((a for a in given if not a.startswith("-")), None)  # --debug takes none
    before = given[: given.index(named)] if named is not None else given
    # only `cspace [--debug] COMMAND ...` can go without the other commands' help lines
    parser = build_parser(
        named if named in COMMANDS else None, listed=any(a != "--debug" for a in before)
    )
    cut = given.index("--") if "--" in given else len(given)
    for option in given[:cut]:
        if option.startswith("-") and option != "-" and os.path.lexists(option):
            output.error(
                f"'{option}' is an option, and a file here: put -- before file names "
                "(cspace COMMAND [OPTIONS] -- FILE...)"
            )
            return exit_codes.NO_REPORT
    args = parser.parse_args([*given[: cut + 1], *map(FileName, given[cut + 1 :])])
    try:
        code: int = args.run(args)
    except CspaceError as exc:
        if args.debug:
            _print_traceback()  # the traceback, and the exit code all the same
        for one in getattr(exc, "errors", None) or (exc,):  # every problem, a line each
            kind = getattr(one, "code", None)  # every error carries a stable code
            limit = getattr(one, "message_chars", MAX_PROBLEM_CHARS)
            output.error(f"{one} [{kind}]" if isinstance(kind, str) else str(one), limit)
        return exit_codes.NO_REPORT
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        return exit_codes.OK
    except Exception as exc:  # a bug of ours: still one line, unless debugging
        if args.debug:
            _print_traceback()
        output.error(f"internal error: {type(exc).__name__}: {exc} (run with --debug for details)")
        return exit_codes.NO_REPORT
    return code


def _print_traceback() -> None:
    """The current exception's traceback, on standard error, each line escaped.

    Its messages may quote a file (a name, a path): as every output, no line of it is a
    workflow command or holds a control character. ``traceback`` is imported only here:
    it costs 3 ms of every start-up otherwise.
    """
    import traceback

    for line in traceback.format_exc().splitlines():
        sys.stderr.write(printable(line, limit=None) + "\n")
