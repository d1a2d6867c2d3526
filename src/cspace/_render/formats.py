"""The output formats of ``cspace inspect``: one table, format name -> renderer.

Every format takes the same input, reports, and is used the same way: for one
robot, ``one(report, options)`` is the whole output; for several, each report (in the
worker that inspected it) becomes a ``piece``, written at once when the format streams
(JSON Lines, annotations) or kept, and ``end`` writes what follows them all from the
pieces and the summary rows (a table, a SARIF log). A file without a report becomes a
piece too (``failed``), for the formats that show failures where a reviewer looks.

A renderer's module is imported only when its format is used (as pip's commands are).
Adding a format is one module and one row of `FORMATS`; the command line's choices and
help come from this table.
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

if TYPE_CHECKING:
    from cspace._reports.report import Report
    from cspace._reports.summary import SummaryRow


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


class Format(NamedTuple):
    """One output format.

    Attributes:
        help: What it is for, for ``--help``.
        module: The module under ``cspace._render`` with its functions (imported on use).
        one: Its function ``(report, options) -> str``: one robot's output.
        piece: Its function ``(report) -> str``, or "": one robot's part of a run of
            several, made in the worker.
        failed: Its function ``(path, problem, code, line) -> str``, or "": the part of
            a file that gave no report.
        end: Its function ``(rows, pieces, options) -> str``, or "": what follows all files.
        streams: Each piece is written when it is made (else kept for ``end``).
        several: The format can hold several robots in one output (``html`` and ``svg``
            draw one: several go to a folder, a file each, with ``--output-dir``).
        commands: Its lines are GitHub workflow commands that cspace means (each
            escaped where it is made); every other format's output is kept free of them.
    """

    help: str
    module: str
    one: str
    piece: str = ""
    failed: str = ""
    end: str = ""
    streams: bool = True
    several: bool = True
    commands: bool = False

    def call(self, function: str, *args: Any) -> Any:
        """Call one of the format's functions (its module imported now)."""
        module = importlib.import_module(f"cspace._render.{self.module}")
        return getattr(module, function)(*args)


FORMATS: dict[str, Format] = {
    "text": Format(
        "text for people (default); several files: a summary table",
        "_plain",
        "one_text",
        end="end_text",
    ),
    "json": Format(
        "json for CI and tools (JSON Lines for several files)",
        "_plain",
        "one_json",
        piece="piece_json",
    ),
    "jsonl": Format(
        "jsonl for JSON Lines however many files",
        "_plain",
        "one_jsonl",
        piece="piece_json",
    ),
    "markdown": Format(
        "markdown for a pull-request comment or $GITHUB_STEP_SUMMARY",
        "_plain",
        "one_markdown",
        end="end_markdown",
    ),
    "sarif": Format(
        "sarif for code scanning (SARIF 2.1.0: each finding on its file and line)",
        "sarif",
        "one_sarif",
        piece="piece_sarif",
        failed="failed_sarif",
        end="end_sarif",
        streams=False,
    ),
    "github": Format(
        "github for annotations on a pull request's lines (GitHub workflow commands)",
        "annotations",
        "one_github",
        piece="piece_github",
        failed="failed_github",
        commands=True,
    ),
    "html": Format(
        "html for a self-contained visual report (one robot; several with --output-dir)",
        "_plain",
        "one_html",
        piece="piece_html",
        several=False,
    ),
    "svg": Format(
        "svg for the tree alone (one robot; several with --output-dir)",
        "_plain",
        "one_svg",
        piece="piece_svg",
        several=False,
    ),
}
"""Every output format of ``cspace inspect``, by the name ``--format`` takes."""


def help_text() -> str:
    """The help of ``--format``: each format's line, in the table's order."""
    return ", ".join(f.help for f in FORMATS.values())


def end_of(fmt: str, rows: Sequence[SummaryRow], pieces: Sequence[str], options: Options) -> str:
    """What a run of several files ends with in format ``fmt`` ("" for nothing)."""
    chosen = FORMATS[fmt]
    return str(chosen.call(chosen.end, rows, pieces, options)) if chosen.end else ""


def one(fmt: str, report: Report, options: Options) -> str:
    """One robot's whole output in format ``fmt``."""
    chosen = FORMATS[fmt]
    return str(chosen.call(chosen.one, report, options))
