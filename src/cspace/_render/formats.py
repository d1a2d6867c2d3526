"""The output formats of ``inspect``, ``diff`` and ``check``: one table, `FORMATS`.

A row is one format: the module that renders it, what it is for in each command it
serves (its line of that command's ``--format`` help; a command it does not serve has
none), and how its output is written. The module has the functions of those commands,
under the fixed names of `Renderer`, and is imported only when its format is used (as
pip's commands are): a URDF's ``inspect`` imports the text renderer and no other.

``inspect`` of one robot: ``inspect_one(report, options)`` is the whole output. Of
several: each report (in the worker that inspected it) becomes an ``inspect_piece``,
written at once when the format streams (JSON Lines, annotations) or kept, and
``inspect_end`` writes what follows them all from the pieces and the summary rows (a
table, a SARIF log). A file without a report becomes a piece too (``inspect_failed``),
for the formats that show failures where a reviewer looks. ``diff(old, new, changes,
options)`` is the output of ``cspace diff``; ``check(rows, options)`` that of ``cspace
check --baseline``.

Adding a format is one module and one row; each command's choices and help come from
this table (`choices`, `help_text`), and the CLI calls the renderers through the
functions below, never a renderer of its own.
"""

import importlib
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, Literal, Protocol, cast

from cspace._record import NamedTuple

if TYPE_CHECKING:
    from cspace._reports.baseline import Row
    from cspace._reports.collisions import CollisionReport
    from cspace._reports.diff import ReportDiff
    from cspace._reports.report import Report
    from cspace._reports.summary import SummaryRow

Command = Literal["inspect", "diff", "check", "collisions"]
"""A command that writes its output in a format of `FORMATS`."""

FUNCTIONS: dict[Command, tuple[str, ...]] = {
    "inspect": ("inspect_one", "inspect_piece", "inspect_failed", "inspect_end"),
    "diff": ("diff",),
    "check": ("check",),
    "collisions": ("collisions",),
}
"""The functions of `Renderer` each command calls; a module serving the command has the
first, and may have the others."""


class Options(NamedTuple):
    """How a person asked for the output.

    Attributes:
        color: ANSI colour (text).
        width: Columns to fit tables into, or None.
        hide_fixed: Leave fixed joints out of the joint table (text).
    """

    color: bool = False
    width: int | None = None
    hide_fixed: bool = False


class Renderer(Protocol):
    """A renderer module: the functions of the commands its format serves (`FUNCTIONS`)."""

    def inspect_one(self, report: "Report", options: Options) -> str:
        """One robot's whole output."""

    def inspect_piece(self, report: "Report") -> str:
        """One robot's part of a run of several, made in the worker that inspected it."""

    def inspect_failed(self, path: str, message: str, code: str | None, line: int | None) -> str:
        """The part of a file that gave no report (at its line, when known)."""

    def inspect_end(
        self, rows: "Sequence[SummaryRow]", pieces: Sequence[str], options: Options
    ) -> str:
        """What follows every file of a run of several ("" for nothing)."""

    def diff(
        self,
        old: Mapping[str, Any],
        new: Mapping[str, Any],
        changes: "ReportDiff",
        options: Options,
    ) -> str:
        """The changes between two reports (their JSON documents and their diff)."""

    def check(self, rows: "Sequence[Row]", options: Options) -> str:
        """Each robot's verdict against a baseline."""

    def collisions(self, report: "CollisionReport", options: Options) -> str:
        """A robot's self-collision report (``cspace collisions``)."""


class Format(NamedTuple):
    """One output format.

    Attributes:
        module: The module with its functions (`Renderer`), imported on use.
        inspect: Its line of ``inspect --format``'s help, or "": it does not serve
            ``inspect``.
        diff: Its line of ``diff --format``'s help, or "".
        check: Its line of ``check --format``'s help, or "".
        collisions: Its line of ``collisions --format``'s help, or "".
        streams: ``inspect``: each piece is written when it is made (else kept for
            ``inspect_end``).
        several: ``inspect``: the format can hold several robots in one output (``html``
            and ``svg`` draw one: several go to a folder, a file each, with
            ``--output-dir``).
        commands: Its lines are GitHub workflow commands that cspace means (each
            escaped where it is made); every other format's output is kept free of them.
    """

    module: str
    inspect: str = ""
    diff: str = ""
    check: str = ""
    collisions: str = ""
    streams: bool = True
    several: bool = True
    commands: bool = False

    def help_for(self, command: Command) -> str:
        """Its line of ``command``'s ``--format`` help ("" when it does not serve it)."""
        return {
            "inspect": self.inspect,
            "diff": self.diff,
            "check": self.check,
            "collisions": self.collisions,
        }[command]

    def renderer(self) -> Renderer:
        """Its module, imported now (it has the functions of the commands it serves)."""
        return cast("Renderer", importlib.import_module(self.module))


FORMATS: dict[str, Format] = {
    "text": Format(
        "cspace._render.text",
        inspect="text for people (default); several files: a summary table",
        diff="text for people (default)",
        check="text (default)",
        collisions="text for people (default)",
    ),
    "json": Format(
        "cspace._render.json_report",
        inspect="json for CI and tools (JSON Lines for several files)",
        diff="json for tools",
        collisions="json for CI and tools (cspace schema --collisions)",
    ),
    "jsonl": Format(
        "cspace._render.json_lines",
        inspect="jsonl for JSON Lines however many files",
        collisions="jsonl for one line (a line of a baseline: cspace check --baseline)",
    ),
    "markdown": Format(
        "cspace._render.markdown",
        inspect="markdown for a pull-request comment or $GITHUB_STEP_SUMMARY",
        diff="markdown for a pull-request comment",
        check="markdown for a pull-request comment",
        collisions="markdown for a pull-request comment",
    ),
    "sarif": Format(
        "cspace._render.sarif",
        inspect="sarif for code scanning (SARIF 2.1.0: each finding on its file and line)",
        collisions="sarif for code scanning (each finding on the SRDF's or the robot's line)",
        streams=False,
    ),
    "github": Format(
        "cspace._render.annotations",
        inspect="github for annotations on a pull request's lines (GitHub workflow commands)",
        check="github for annotations at the lines that differ (GitHub workflow commands)",
        collisions="github for annotations on the SRDF's or the robot's lines",
        commands=True,
    ),
    "html": Format(
        "cspace._render.html",
        inspect="html for a self-contained visual report (one robot; several with --output-dir)",
        diff="html for both sides' pictures side by side with the changes marked",
        collisions="html for a self-contained page with the matrix of link pairs",
        several=False,
    ),
    "svg": Format(
        "cspace._render.svg",
        inspect="svg for the tree alone (one robot; several with --output-dir)",
        several=False,
    ),
}
"""Every output format, by the name ``--format`` takes, in the order help lists them."""


def choices(command: Command) -> tuple[str, ...]:
    """The formats ``command`` offers, in the table's order."""
    return tuple(name for name, f in FORMATS.items() if f.help_for(command))


def help_text(command: Command, last: str = "") -> str:
    """The help of ``command``'s ``--format``: each format's line, ``last`` before the last."""
    lines = [f.help_for(command) for f in FORMATS.values() if f.help_for(command)]
    return ", ".join([*lines[:-1], last + lines[-1]])


def one(fmt: str, report: "Report", options: Options) -> str:
    """One robot's whole output in format ``fmt``."""
    return FORMATS[fmt].renderer().inspect_one(report, options)


def piece(fmt: str, report: "Report") -> str | None:
    """One robot's part of a run of several in format ``fmt`` (None: the format has none)."""
    renderer = FORMATS[fmt].renderer()
    return renderer.inspect_piece(report) if hasattr(renderer, "inspect_piece") else None


def shows_failures(fmt: str) -> bool:
    """Whether format ``fmt`` shows a file without a report in its output (`failed`)."""
    return hasattr(FORMATS[fmt].renderer(), "inspect_failed")


def failed(fmt: str, path: str, message: str, code: str | None, line: int | None) -> str:
    """The part of a file without a report, in a format that `shows_failures`."""
    return FORMATS[fmt].renderer().inspect_failed(path, message, code, line)


def end_of(fmt: str, rows: "Sequence[SummaryRow]", pieces: Sequence[str], options: Options) -> str:
    """What a run of several files ends with in format ``fmt`` ("" for nothing)."""
    renderer = FORMATS[fmt].renderer()
    return renderer.inspect_end(rows, pieces, options) if hasattr(renderer, "inspect_end") else ""


def diff(
    fmt: str,
    old: Mapping[str, Any],
    new: Mapping[str, Any],
    changes: "ReportDiff",
    options: Options,
) -> str:
    """``cspace diff``'s output in format ``fmt``."""
    return FORMATS[fmt].renderer().diff(old, new, changes, options)


def check(fmt: str, rows: "Sequence[Row]", options: Options) -> str:
    """``cspace check --baseline``'s output in format ``fmt``."""
    return FORMATS[fmt].renderer().check(rows, options)


def collisions(fmt: str, report: "CollisionReport", options: Options) -> str:
    """``cspace collisions``' output in format ``fmt``."""
    return FORMATS[fmt].renderer().collisions(report, options)
