"""Markdown (GitHub-flavoured) for pull-request comments: a report and a diff.

Returns strings; posting them is the caller's business. Every value that comes from a
file (names, messages) is escaped so that it cannot break the table it sits in.
"""

from __future__ import annotations

from collections.abc import Sequence

from .diff import CHANGE_LABELS, ReportDiff
from .render import JOINT_COLUMNS, joint_rows
from .report import Report


def cell(text: str) -> str:
    """Text made safe for a table cell: pipes escaped, line breaks and backticks removed."""
    return " ".join(text.replace("|", "\\|").replace("`", "'").split())


def md_table(
    header: Sequence[str], rows: Sequence[Sequence[str]], code_columns: Sequence[int] = ()
) -> list[str]:
    """A Markdown table; cells of ``code_columns`` are set in code (unless ``-``)."""

    def line(cells: Sequence[str]) -> str:
        return "| " + " | ".join(cells) + " |"

    body = [
        [f"`{c}`" if i in code_columns and c != "-" else c for i, c in enumerate(row)]
        for row in rows
    ]
    return [line(header), line(["---"] * len(header)), *(line(r) for r in body)]


def render_markdown(report: Report) -> str:
    """The report as Markdown: headline, joint table, findings. Ends with a newline."""
    m = report.manifold
    root = f", root joint {report.root_joint}" if report.root_joint else ""
    out = [
        f"### cspace: `{cell(report.source.path)}`",
        "",
        f"**C = `{m.notation}`**, dimension {report.dimension}, nq / nv "
        f"{report.nq} / {report.nv}, fundamental group {m.fundamental_group}",
        "",
        f"Robot `{cell(report.robot or '(unnamed)')}` ({report.source.format}{root}).",
        "",
    ]
    rows = [[cell(name), *rest] for name, *rest in joint_rows(report)]
    out += md_table(JOINT_COLUMNS, rows, code_columns=(0,))
    out.append("")
    if report.diagnostics:
        out.append("**Findings**")
        out.append("")
        out += [
            f"- **{d.severity.value}** `{d.code}`: {cell(d.message)}" for d in report.diagnostics
        ]
    else:
        out.append("No findings.")
    return "\n".join(out) + "\n"


def render_diff_markdown(diff: ReportDiff) -> str:
    """The diff as Markdown for a pull-request comment. Ends with a newline."""
    name = cell(diff.new_path)
    if not diff.changed:
        return (
            f"### cspace: no C-space change in `{name}`\n\n"
            f"`{diff.new_manifold}`, dimension {diff.new_dimension}.\n"
        )
    if (diff.old_manifold, diff.old_dimension) == (diff.new_manifold, diff.new_dimension):
        headline = (
            f"Same normal form, `{diff.new_manifold}` (dimension {diff.new_dimension}), "
            "but not the same configurations:"
        )
    else:
        headline = (
            f"`{diff.old_manifold}` (dimension {diff.old_dimension}) → "
            f"`{diff.new_manifold}` (dimension {diff.new_dimension})"
        )
    out = [f"### cspace: C-space changed in `{name}`", "", headline, ""]
    rows = [
        [CHANGE_LABELS[c.kind], cell(c.joint) if c.joint else "-", cell(c.before), cell(c.after)]
        for c in diff.changes
    ]
    out += md_table(["change", "joint", "before", "after"], rows, code_columns=(1,))
    return "\n".join(out) + "\n"
