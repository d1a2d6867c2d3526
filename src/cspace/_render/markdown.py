"""Markdown (GitHub-flavoured) for pull-request comments: reports, a diff, a baseline check.

Returns strings; posting them is the caller's business. What a file says (names, paths,
messages) is first made printable (`printable`: no line break, no
control or bidi character), then set in a code span, where Markdown reads nothing: no
HTML, no link or autolink, no @mention, no emphasis. Text made only of the characters
of cspace's own values (``R^2 × S^1``, ``[-2, 2] rad``, ``q 1..2, v 1``) stays plain.
In a table every pipe is escaped, the one character a code span does not protect there.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from cspace._render._columns import location
from cspace._render._markdown_escape import cell, code, md_table
from cspace._render._mechanism import AMBIENT, mechanism_lines
from cspace._render.text import also, grouped_findings, joint_columns, joint_rows
from cspace._reports.report import Report

if TYPE_CHECKING:  # diffs and summaries are imported by the commands that make them
    from cspace._render.formats import Options
    from cspace._reports.baseline import Row
    from cspace._reports.collisions import CollisionReport
    from cspace._reports.diff import ReportDiff
    from cspace._reports.summary import SummaryRow


def render_markdown(report: Report) -> str:
    """The report as Markdown: headline, joint table, findings. Ends with a newline."""
    m = report.manifold
    root = f", root joint {report.root_joint}" if report.root_joint else ""
    out = [
        f"### cspace: {code(report.source.path)}",
        "",
        f"**C = {code(m.notation)}**, dimension {report.dimension}, nq / nv "
        f"{report.nq} / {report.nv}, fundamental group {cell(m.fundamental_group)}",
        "",
        f"Robot {code(report.robot or '(unnamed)')} ({cell(report.source.format)}{root}).",
        "",
        *_mechanism_markdown(report),
    ]
    out += md_table(joint_columns(report), joint_rows(report), code_columns=(0,))
    out.append("")
    if report.limits_file is not None:
        from cspace._render._limits import COLUMNS, limits_head, limits_rows

        out += [f"**{cell(limits_head(report.limits_file))}**", ""]
        out += [*md_table(COLUMNS, limits_rows(report.limits_file), code_columns=(0,)), ""]
    if report.actuators:
        from cspace._render import _actuators as act

        out += [f"**{cell(act.actuators_head(report.actuators))}**", ""]
        rows = act.actuator_rows(report.actuators)
        out += [*md_table(act.COLUMNS, rows, code_columns=(1, 3)), ""]
        more = act.actuators_more(report.actuators)
        out += [cell(more), ""] if more else []
    if report.diagnostics:
        out.append("**Findings**")
        out.append("")
        out += [
            f"- **{d.severity.value}** {code(d.code)}"
            + ("" if location(d) is None else f" ({cell(str(location(d)))})")
            + f": {cell(d.message + also(others))}"
            for d, others in grouped_findings(report.diagnostics)
        ]
    else:
        out.append("No findings.")
    return "\n".join(out) + "\n"


def _mechanism_markdown(report: Report) -> list[str]:
    """The mechanism under the C-space (none for a tree): `mechanism_lines` as a list."""
    if report.closure is None:
        return []
    head, *rest = mechanism_lines(report.closure, code, code)
    return [
        f"**{head[:1].upper() + head[1:]}**; the C-space above is {AMBIENT}.",  # cspace's words
        "",
        *(f"- {line}" for line in rest),
        *([""] if rest else []),
    ]


def render_diff_markdown(diff: ReportDiff) -> str:
    """The diff as Markdown for a pull-request comment. Ends with a newline."""
    from cspace._reports.diff import CHANGE_LABELS

    name = code(diff.new_path)
    old, new = code(diff.old_manifold), code(diff.new_manifold)
    limits = f"Limits compared {diff.tolerance_text}."
    notes = _notes_markdown(diff)
    dimension = f"(dimension {diff.new_dimension})"
    if not diff.differs:
        return (
            f"### cspace: no C-space change in {name}\n\n{new}, dimension "
            f"{diff.new_dimension}. {limits}\n" + notes
        )
    if not diff.changed:
        title = f"### cspace: {diff.what_differs} in {name}"
        headline = f"The same C-space, {new} {dimension}, but {diff.what_differs}:"
    elif (diff.old_manifold, diff.old_dimension) == (diff.new_manifold, diff.new_dimension):
        title = f"### cspace: C-space changed in {name}"
        headline = f"Same normal form, {new} {dimension}, but not the same configurations:"
    else:
        title = f"### cspace: C-space changed in {name}"
        headline = f"{old} (dimension {diff.old_dimension}) → {new} {dimension}"
    out = [title, "", headline, ""]
    rows = [[CHANGE_LABELS[c.kind], c.joint or "-", c.before, c.after] for c in diff.changes]
    out += md_table(["change", "joint", "before", "after"], rows, code_columns=(1,))
    return "\n".join([*out, "", limits]) + "\n" + notes


def _notes_markdown(diff: ReportDiff) -> str:
    """The notes of a diff as a Markdown section (empty without notes)."""
    from cspace._reports.diff import CHANGE_LABELS

    if not diff.notes:
        return ""
    rows = [[CHANGE_LABELS[c.kind], c.joint or "-", c.before, c.after] for c in diff.notes]
    same = "" if diff.changed else "; the C-space is the same"
    out = ["", f"Notes (how the two files store or name it{same}):", ""]
    out += md_table(["note", "joint", "old", "new"], rows, code_columns=(1,))
    return "\n".join(out) + "\n"


def render_summary_markdown(rows: Sequence[SummaryRow]) -> str:
    """The summary as a Markdown table (for a pull-request comment). Ends with a newline."""
    from cspace._reports.summary import HEADER, totals

    out = ["### cspace: robot files", ""]
    out += md_table(HEADER, [r.cells() for r in rows], code_columns=(0, 2))
    out += ["", totals(rows) + "."]
    out += [""] if any(r.problem is not None for r in rows) else []
    out += [
        f"- {cell(r.problem)}"
        if r.problem.startswith(r.path)
        else f"- {code(r.path)}: {cell(r.problem)}"
        for r in rows
        if r.problem is not None
    ]
    return "\n".join(out) + "\n"


def inspect_one(report: Report, options: Options) -> str:
    """``inspect --format markdown`` of one robot (`render_markdown`)."""
    return render_markdown(report)


def inspect_end(rows: Sequence[SummaryRow], pieces: Sequence[str], options: Options) -> str:
    """``inspect --format markdown`` of several files: the summary table."""
    return render_summary_markdown(rows)


def diff(
    old: Mapping[str, Any], new: Mapping[str, Any], changes: ReportDiff, options: Options
) -> str:
    """``diff --format markdown`` (`render_diff_markdown`)."""
    return render_diff_markdown(changes)


def check(rows: Sequence[Row], options: Options) -> str:
    """``check --baseline --format markdown``: a table of each robot's verdict."""
    table = md_table(
        ["robot", "verdict", "what"], [(r.path, r.verdict, r.what) for r in rows], code_columns=(0,)
    )
    return "\n".join(["### cspace: against the baseline", "", *table])


def collisions(report: CollisionReport, options: Options) -> str:
    """``cspace collisions --format markdown`` (`cspace._render._collisions_markdown`)."""
    from cspace._render._collisions_markdown import render

    return render(report)
