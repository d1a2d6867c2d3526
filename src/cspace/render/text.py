"""The human-readable text report.

Returns strings; printing is the caller's business. Colour (ANSI escapes) only when
the caller asks for it: the command-line tool asks when writing to a terminal and
``NO_COLOR`` is not set. What a file says (names, the path, messages) goes through
:func:`cspace.safetext.printable`, so that no escape sequence of its own reaches the
terminal.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from cspace.findings import Severity
from cspace.reports.report import JointReport, Report, index_range
from cspace.safetext import printable

if TYPE_CHECKING:  # diffs and summaries are imported by the commands that make them
    from cspace.reports.diff import Change, ReportDiff
    from cspace.reports.summary import SummaryRow

_STYLES = {"bold": "1", "dim": "2", "red": "31", "yellow": "33", "cyan": "36"}
_SEVERITY_STYLE = {Severity.ERROR: "red", Severity.WARNING: "yellow", Severity.INFO: "cyan"}


class _Painter:
    def __init__(self, color: bool) -> None:
        self.color = color

    def __call__(self, text: str, style: str) -> str:
        if not self.color:
            return text
        return f"\x1b[{_STYLES[style]}m{text}\x1b[0m"


def _number(x: float | None) -> str:
    if x is None or not math.isfinite(x):
        return str(x)
    return f"{x:.6g}"


def _limits(joint: JointReport) -> str:
    if joint.limits is None:
        return "-"
    pairs = [
        f"[{_number(lo)}, {_number(hi)}]"
        for lo, hi in zip(joint.limits.lower, joint.limits.upper, strict=True)
    ]
    return " ".join(pairs) + f" {joint.limits.unit}"


JOINT_COLUMNS = ("joint", "kind", "space", "limits", "q", "v")
"""The columns of the joint table, in the text and Markdown reports alike."""


def joint_rows(report: Report) -> list[list[str]]:
    """One row per joint under :data:`JOINT_COLUMNS`: limits in the joint's units."""
    return [
        [
            printable(j.name),
            j.kind.value,
            j.space.notation,
            _limits(j),
            index_range(j.q_index, j.nq),
            index_range(j.v_index, j.nv),
        ]
        for j in report.joints
    ]


def table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> list[str]:
    """Left-aligned columns separated by two spaces, header underlined."""
    widths = [
        max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(header)
    ]

    def line(cells: Sequence[str]) -> str:
        return "  ".join(c.ljust(w) for c, w in zip(cells, widths, strict=True)).rstrip()

    return [line(header), line(["-" * w for w in widths]), *(line(r) for r in rows)]


def render_text(report: Report, *, color: bool = False) -> str:
    """The text report: summary, joint table, diagnostics. Ends with a newline."""
    paint = _Painter(color)
    m = report.manifold
    root = f" (root joint: {report.root_joint})" if report.root_joint else ""
    out = [
        f"robot   {paint(printable(report.robot) or '(unnamed)', 'bold')}{root}",
        f"source  {printable(report.source.path)} ({report.source.format}, "
        f"sha256 {report.source.sha256[:12]})",
        "",
        f"  C = {paint(m.notation, 'bold')}",
        "",
        f"dimension          {report.dimension}",
        f"nq / nv            {report.nq} / {report.nv}",
        f"fundamental group  {m.fundamental_group}"
        + (" (simply connected)" if m.simply_connected else ""),
        "",
    ]
    out += table(JOINT_COLUMNS, joint_rows(report))
    out.append("")
    if report.diagnostics:
        out.append("diagnostics")
        for d in report.diagnostics:
            label = paint(f"{d.severity.value:<7}", _SEVERITY_STYLE[d.severity])
            out.append(f"  {label} {d.code}: {printable(d.message)}")
    else:
        out.append("diagnostics  none")
    return "\n".join(out) + "\n"


def render_diff_text(diff: ReportDiff) -> str:
    """The text of ``cspace diff``: one line per change. Ends with a newline."""
    from cspace.reports.diff import CHANGE_LABELS

    old_path, new_path = printable(diff.old_path), printable(diff.new_path)
    old_form, new_form = printable(diff.old_manifold), printable(diff.new_manifold)
    if diff.changed:
        headline = f"C-space changed: {old_form} -> {new_form}"
    else:
        headline = f"no C-space change: {new_form} (dimension {diff.new_dimension})"
    lines = [
        headline,
        f"  old {old_path}",
        f"  new {new_path}",
        f"  limits compared {diff.tolerance_text}",
    ]

    def rows(changes: Sequence[Change]) -> list[list[str]]:
        cells = ((CHANGE_LABELS[c.kind], c.joint or "-", c.before, c.after) for c in changes)
        return [[printable(text) for text in row] for row in cells]

    if diff.changes:
        lines += ["", *table(["change", "joint", "before", "after"], rows(diff.changes))]
    if diff.notes:
        lines += ["", "notes (how the two files store or name it; the C-space is the same):"]
        lines += table(["note", "joint", "old", "new"], rows(diff.notes))
    return "\n".join(lines) + "\n"


def render_summary_text(rows: Sequence[SummaryRow]) -> str:
    """The summary table, then the problems of files without a report. Ends with a newline."""
    from cspace.reports.summary import HEADER, totals

    out = table(HEADER, [[printable(c) for c in r.cells()] for r in rows])
    out += ["", totals(rows)]
    out += [f"  {printable(r.path)}: {printable(r.problem)}" for r in rows if r.problem is not None]
    return "\n".join(out) + "\n"
