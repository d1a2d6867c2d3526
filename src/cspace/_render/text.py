"""The human-readable text report.

Returns strings; printing is the caller's business. Colour (ANSI escapes) only when
the caller asks for it: the command-line tool asks when writing to a terminal and
``NO_COLOR`` is not set. What a file says (names, the path, messages) goes through
`printable`, so that no escape sequence of its own reaches the
terminal.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from cspace._findings import POSE_CODES, Diagnostic, Severity
from cspace._joint_kind import JointKind
from cspace._render._columns import location, table
from cspace._reports.report import JointReport, Report, index_range
from cspace._safetext import printable

if TYPE_CHECKING:  # diffs and summaries are imported by the commands that make them
    from cspace._render.formats import Options
    from cspace._reports.baseline import Row
    from cspace._reports.collisions import CollisionReport
    from cspace._reports.diff import Change, ReportDiff
    from cspace._reports.summary import SummaryRow

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


def _qpos_differs(report: Report) -> bool:
    """True for an MJCF report whose MuJoCo qpos is not Pinocchio's q (a mimic joint)."""
    return any(j.qposadr is not None and j.qposadr != j.q_index for j in report.joints)


def joint_columns(report: Report) -> tuple[str, ...]:
    """`JOINT_COLUMNS`, with ``qpos`` and ``ros2_control`` when a report needs them.

    ``qpos`` (MuJoCo's) when an MJCF file's qpos is not q; ``ros2_control`` when the URDF
    has ``<ros2_control>`` elements.
    """
    columns = (*JOINT_COLUMNS, "qpos") if _qpos_differs(report) else JOINT_COLUMNS
    if report.ros2_control:
        from cspace._render._ros2_control import COLUMN

        columns = (*columns, COLUMN)
    return columns


def joint_rows(report: Report, hide_fixed: bool = False) -> list[list[str]]:
    """One row per joint under `joint_columns`: limits in the joint's units."""
    qpos = _qpos_differs(report)
    control: dict[str, str] | None = None
    if report.ros2_control:
        from cspace._render._ros2_control import control_cells

        control = control_cells(report)
    return [
        [
            printable(j.name),
            j.kind.value,
            j.space.notation,
            _limits(j),
            index_range(j.q_index, j.nq),
            index_range(j.v_index, j.nv),
        ]
        + ([index_range(j.qposadr, j.nq if j.q_index is not None else 1)] if qpos else [])
        + ([control.get(j.name, "-")] if control is not None else [])
        for j in report.joints
        if not (hide_fixed and j.kind is JointKind.FIXED)
    ]


def _wrapped(head: str, text: str, width: int | None, indent: int) -> list[str]:
    """``head + text``, wrapped at word boundaries within ``width`` (None: one line)."""
    if width is None:
        return [head + text]
    import textwrap

    lines = textwrap.wrap(text, max(width - indent, 20), break_on_hyphens=False)
    return [head + lines[0], *(" " * indent + rest for rest in lines[1:])] if lines else [head]


GROUP_AT = 3
"""Findings of one code about this many joints or more are shown as one line."""


SAID_APART = 8
"""A joint's findings of one code, up to this many, are each shown (a joint_limits.yaml's
lower bound, upper bound and speed each say another thing); more are a flood (thousands
of actuators on one joint), folded into one line with the rest of their code."""


def grouped_findings(diagnostics: Sequence[Diagnostic]) -> list[tuple[Diagnostic, list[str]]]:
    """Each finding with the joints it stands for too: one line for a repeated finding.

    Findings of one severity and code about `GROUP_AT` joints or more become the
    first of them, with the other joints' names; the others stand as they are, and so
    does a joint's second finding of one code, up to `SAID_APART` of them (beyond, every
    one of that joint's is in the group). Order: each at its first finding's place. The
    JSON report keeps every finding.
    """
    per_joint = Counter((d.severity, d.code, d.joint) for d in diagnostics if d.joint is not None)
    alike: dict[tuple[Severity, str], list[Diagnostic]] = {}
    grouped: set[tuple[Severity, str, str]] = set()
    members: set[int] = set()  # the findings in a group, by index
    for index, d in enumerate(diagnostics):
        if d.joint is None or d.code in POSE_CODES:  # one per pose: each its own
            continue
        said = (d.severity, d.code, d.joint)
        if said not in grouped or per_joint[said] > SAID_APART:
            grouped.add(said)
            members.add(index)
            alike.setdefault((d.severity, d.code), []).append(d)
    out: list[tuple[Diagnostic, list[str]]] = []
    shown: set[tuple[Severity, str]] = set()
    for index, d in enumerate(diagnostics):
        key = (d.severity, d.code)
        group = alike.get(key, []) if index in members else []
        if len(group) < GROUP_AT:
            out.append((d, []))
        elif key not in shown:
            shown.add(key)
            out.append((d, [str(x.joint) for x in group[1:]]))
    return out


def also(others: Sequence[str], limit: int = 8) -> str:
    """`` (and 11 more joints like it: a, b, ...)``, or nothing.

    A joint named more than once (several findings about it) is named once, and the
    count is of findings: `` (and 4,999 more like it: j)``.
    """
    if not others:
        return ""
    distinct = list(dict.fromkeys(others))
    names = ", ".join(printable(n) for n in distinct[:limit])
    more = ", ..." if len(distinct) > limit else ""
    if len(distinct) < len(others):
        return f" (and {len(others):,} more like it: {names}{more})"
    return f" (and {len(others)} more joints like it: {names}{more})"


def _semantics_lines(report: Report) -> list[str]:
    """The SRDF read, the group reported, the poses stored: a line each, when present."""
    out = []
    if report.srdf is not None:
        groups = ", ".join(printable(g[0]) for g in report.srdf.groups) or "none"
        out.append(f"srdf    {printable(report.srdf.path)} (groups: {groups})")
    if report.group is not None:
        group = report.group
        out.append(
            f"group   {printable(group.name)}: {len(group.joints)} joints move, "
            f"{len(group.held)} held at {printable(group.held_at)}"
        )
    if report.ros2_control:
        from cspace._render._ros2_control import control_line

        out.append(control_line(report) or "")
    if report.poses:
        labels = ", ".join(printable(p.label) for p in report.poses[:8])
        more = f" and {len(report.poses) - 8:,} more" if len(report.poses) > 8 else ""
        out.append(f"poses   {labels}{more}")
    return out


def _mechanism(report: Report) -> list[str]:
    """The mechanism's lines under the C-space (none for a tree): `mechanism_lines`."""
    if report.closure is None:
        return []
    from cspace._render._mechanism import mechanism_lines

    head, *rest = mechanism_lines(report.closure, printable, lambda t: f"'{printable(t)}'")
    return [f"  {head}", *(f"    {line}" for line in rest)]


def _ambient(report: Report) -> str:
    """What the C-space line adds for a mechanism: the space is the tree's."""
    if report.closure is None:
        return ""
    from cspace._render._mechanism import AMBIENT

    return f"  ({AMBIENT})"


def render_text(
    report: Report, *, color: bool = False, hide_fixed: bool = False, width: int | None = None
) -> str:
    """The text report: summary, joint table, diagnostics. Ends with a newline.

    Args:
        report: The report.
        color: Colour the output with ANSI escapes.
        hide_fixed: Leave fixed joints out of the joint table (they are counted).
        width: Fit the joint table into this many columns (a terminal's width).
    """
    paint = _Painter(color)
    m = report.manifold
    root = f" (root joint: {report.root_joint})" if report.root_joint else ""
    out = [
        f"robot   {paint(printable(report.robot) or '(unnamed)', 'bold')}{root}",
        f"source  {printable(report.source.path)} ({report.source.format}, "
        f"sha256 {report.source.sha256[:12]})",
        *_semantics_lines(report),
        "",
        f"  C = {paint(m.notation, 'bold')}{_ambient(report)}",
        *_mechanism(report),
        "",
        f"dimension          {report.dimension}",
        f"nq / nv            {report.nq} / {report.nv}",
        f"fundamental group  {m.fundamental_group}"
        + (" (simply connected)" if m.simply_connected else ""),
        "",
    ]
    out += table(joint_columns(report), joint_rows(report, hide_fixed), width)
    fixed = sum(j.kind is JointKind.FIXED for j in report.joints)
    if hide_fixed and fixed:
        out.append(f"({fixed} fixed joints not shown)")
    out.append("")
    if report.limits_file is not None:
        from cspace._render._limits import COLUMNS, limits_head, limits_rows

        rows = [[printable(c) for c in row] for row in limits_rows(report.limits_file)]
        out += [limits_head(report.limits_file), *table(COLUMNS, rows, width), ""]
    if report.actuators:
        from cspace._render import _actuators as act

        rows = [[printable(c) for c in row] for row in act.actuator_rows(report.actuators)]
        out += [act.actuators_head(report.actuators), *table(act.COLUMNS, rows, width)]
        out += [*filter(None, [act.actuators_more(report.actuators)]), ""]
    if report.diagnostics:
        out.append("diagnostics")
        for d, others in grouped_findings(report.diagnostics):
            label = paint(f"{d.severity.value:<7}", _SEVERITY_STYLE[d.severity])
            where = location(d)
            at = "" if where is None else f" ({where})"
            line = f"{d.code}{at}: {printable(d.message)}{also(others)}"
            out += _wrapped(f"  {label} ", line, width, indent=len(f"  {d.severity.value:<7} "))
    else:
        out.append("diagnostics  none")
    return "\n".join(out) + "\n"


def render_diff_text(diff: ReportDiff, width: int | None = None) -> str:
    """The text of ``cspace diff``: one line per change. Ends with a newline.

    ``width``: fit the tables into this many columns (long cells end in ``…``).
    """
    from cspace._reports.diff import CHANGE_LABELS

    old_path, new_path = printable(diff.old_path), printable(diff.new_path)
    old_form, new_form = printable(diff.old_manifold), printable(diff.new_manifold)
    same_form = (diff.old_manifold, diff.old_dimension) == (diff.new_manifold, diff.new_dimension)
    dimension = f"(dimension {diff.new_dimension})"
    if diff.changed and same_form:  # the Markdown comment's words
        headline = (
            f"C-space changed: same normal form, {new_form} {dimension}, "
            "but not the same configurations"
        )
    elif diff.changed:
        headline = f"C-space changed: {old_form} -> {new_form}"
    elif diff.differs:
        headline = f"C-space the same: {new_form} {dimension}, but {diff.what_differs}"
    else:
        headline = f"no C-space change: {new_form} {dimension}"
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
        lines += ["", *table(["change", "joint", "before", "after"], rows(diff.changes), width)]
    if diff.notes:
        same = "" if diff.changed else "; the C-space is the same"
        lines += ["", f"notes (how the two files store or name it{same}):"]
        lines += table(["note", "joint", "old", "new"], rows(diff.notes), width)
    return "\n".join(lines) + "\n"


def render_summary_text(rows: Sequence[SummaryRow], width: int | None = None) -> str:
    """The summary table and its totals (why a file has no report goes to standard error).

    ``width``: fit the table into this many columns (file paths keep their ends).
    """
    from cspace._reports.summary import HEADER, totals

    out = table(HEADER, [[printable(c) for c in r.cells()] for r in rows], width, keep_end=(0,))
    out += ["", totals(rows)]  # why a file has no report is said once, on standard error
    return "\n".join(out) + "\n"


def inspect_one(report: Report, options: Options) -> str:
    """``inspect --format text`` of one robot: the text report (`render_text`)."""
    return render_text(
        report, color=options.color, hide_fixed=options.hide_fixed, width=options.width
    )


def inspect_end(rows: Sequence[SummaryRow], pieces: Sequence[str], options: Options) -> str:
    """``inspect --format text`` of several files: the summary table."""
    return render_summary_text(rows, options.width)


def diff(
    old: Mapping[str, Any], new: Mapping[str, Any], changes: ReportDiff, options: Options
) -> str:
    """``diff --format text``: the changes, a line each (`render_diff_text`)."""
    return render_diff_text(changes, options.width)


def check(rows: Sequence[Row], options: Options) -> str:
    """``check --baseline --format text``: ``VERDICT: PATH: WHAT``, a line per robot."""
    return "\n".join(
        f"{printable(r.verdict)}: {printable(r.path)}: {printable(r.what)}" for r in rows
    )


def collisions(report: CollisionReport, options: Options) -> str:
    """The self-collision report for people (`cspace._render._collisions_text`)."""
    from cspace._render._collisions_text import render

    return render(report, options)
