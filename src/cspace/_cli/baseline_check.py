"""``cspace check --baseline FILE ROBOTS...``: each robot against its accepted report.

One line per robot (text), a table (Markdown) or workflow commands (``github``):
``same`` when its C-space is the baseline's, ``changed`` when the C-space changed,
``differs`` when only its limits or q/v layout differ, ``new`` when the baseline has no
report of it, ``moved`` when a file renamed has the report of one the baseline holds
and that is gone (this passes); and a line for each other baseline report whose file is
gone. In the ``github`` format each difference is an ``error`` annotation at the
joint's line in the new file (at the file for what belongs to the whole robot), so a
reviewer sees it where the pull request changed it. Exit 0 when all are the same or
moved, 1 when any differs, 2 when a robot gives no report or the baseline cannot be
read.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, NamedTuple

import cspace
from cspace._safetext import printable

from . import exit_codes, output
from .robots import expand_patterns, load_document, xacro_options

if TYPE_CHECKING:
    from cspace._reports.diff import ReportDiff


class _Spot(NamedTuple):
    """One annotation: a line of the robot file (None: the whole file), a title, a message."""

    line: int | None
    title: str
    message: str


class _Row(NamedTuple):
    """One robot's verdict against the baseline."""

    path: str
    verdict: str
    what: str
    spots: tuple[_Spot, ...] = ()


def check_baseline(args: argparse.Namespace) -> int:
    """Compare each robot named with the baseline's report of it."""
    from cspace._reports.baseline import read_baseline
    from cspace._reports.diff import diff_reports
    from cspace._reports.savedreport import read_report_document
    from cspace._reports.summary import FRAGMENT_CODE

    try:
        xacro_options(args)
    except ValueError as exc:
        output.error(str(exc))
        return exit_codes.NO_REPORT
    baseline = read_baseline(args.baseline)
    worst = exit_codes.OK
    rows: list[_Row] = []
    unknown: dict[int, tuple[Any, ...]] = {}  # new robots' rows: their reports' fingerprints
    for name in expand_patterns(args.robot):
        try:
            document = load_document(name, args)
        except cspace.CspaceError as exc:
            code = getattr(exc, "code", None)
            if code == FRAGMENT_CODE and name in baseline:  # a robot no more: said, failed
                what = "in the baseline, but now a fragment that other files include"
                rows.append(_Row(name, "gone", what, (_Spot(None, "gone", what),)))
                continue
            if code == FRAGMENT_CODE:  # no robot of its own: its model is checked
                output.note(f"{exc} [{code}]")
                continue
            output.error(f"{exc} [{code}]" if isinstance(code, str) else str(exc))
            rows.append(_Row(name, "no report", str(exc), (_Spot(None, "no report", str(exc)),)))
            worst = exit_codes.NO_REPORT
            continue
        path = str(document["source"]["path"])
        notation = str(document["manifold"]["notation"])
        if path not in baseline:
            unknown[len(rows)] = _fingerprint(document)
            what = f"{notation}, not in the baseline"
            rows.append(_Row(path, "new", what, (_Spot(None, "new", what),)))
            continue
        where, line = baseline[path]
        diff = diff_reports(read_report_document(where, line), document)
        if diff.verdict == "same":
            rows.append(_Row(path, "same", notation))
            continue
        what = (
            f"{diff.old_manifold} -> {diff.new_manifold}: {diff.kinds_text}"
            if diff.changed
            else f"{notation}, but {diff.what_differs}"
        )
        rows.append(_Row(path, diff.verdict, what, _spots(diff, document)))
        worst = max(worst, exit_codes.FINDINGS)
    checked = {row.path for row in rows}
    gone = [p for p in sorted(set(baseline) - checked) if not os.path.lexists(p)]
    moved = _moves(baseline, gone, unknown, rows)
    for index, old in moved:
        notation = unknown[index][1]  # the fingerprint's second part
        rows[index] = _Row(rows[index].path, "moved", f"from {old}, the same {notation}")
    moved_from = {old for _, old in moved}
    for path in (p for p in gone if p not in moved_from):
        what = "in the baseline, but the file is gone"
        rows.append(_Row(path, "gone", what, (_Spot(None, "gone", what),)))
    if any(row.verdict in ("new", "gone") for row in rows):
        worst = max(worst, exit_codes.FINDINGS)
    output.write(_RENDER[args.format](rows))
    return worst


def _fingerprint(document: Mapping[str, Any]) -> tuple[Any, ...]:
    """All that `diff_reports` compares of a report: equal ones diff as the same."""
    return (
        document["source"]["format"],
        document["manifold"]["notation"],
        document["dimension"],
        document["nq"],
        document["nv"],
        document.get("root_joint"),
        *(
            (
                j["name"],
                j["kind"],
                j["manifold"],
                repr(j.get("limits")),
                j.get("q_index"),
                j["nq"],
                j.get("v_index"),
                j["nv"],
                j.get("qposadr"),
            )
            for j in document["joints"]
        ),
    )


def _moves(
    baseline: Mapping[str, tuple[str, bytes]],
    gone: list[str],
    unknown: Mapping[int, tuple[Any, ...]],
    rows: list[_Row],
) -> list[tuple[int, str]]:
    """Files renamed: each new file (by its row) paired with a gone one of the same report.

    Reports are matched by fingerprint, one gone report read at a time, in time linear in
    the files. Among gone files of one report, a new file takes one of its own name (a
    folder renamed), else the first left, new and gone files taken in the order of
    their paths.
    """
    from collections import deque

    from cspace._reports.savedreport import read_report_document

    if not unknown or not gone:
        return []
    named: dict[tuple[Any, ...], dict[str, deque[str]]] = {}  # report -> name -> gone paths
    left: dict[tuple[Any, ...], deque[str]] = {}  # report -> gone paths, in order
    for path in gone:  # sorted
        found = _fingerprint(read_report_document(*baseline[path]))
        named.setdefault(found, {}).setdefault(os.path.basename(path), deque()).append(path)
        left.setdefault(found, deque()).append(path)
    taken: set[str] = set()
    pairs: dict[int, str] = {}
    order = sorted(unknown, key=lambda index: rows[index].path)
    for index in order:  # a file of the same name first
        same = named.get(unknown[index], {}).get(os.path.basename(rows[index].path))
        if same:
            pairs[index] = same.popleft()
            taken.add(pairs[index])
    for index in order:
        queue = left.get(unknown[index], deque())
        while index not in pairs and queue:
            old = queue.popleft()
            if old not in taken:
                pairs[index] = old
                taken.add(old)
    return sorted(pairs.items())


def _spots(diff: ReportDiff, document: Mapping[str, Any]) -> tuple[_Spot, ...]:
    """Each change of a diff at the line of its joint in the new file (or at the file)."""
    from cspace._reports.diff import CHANGE_LABELS

    lines = {j["name"]: j.get("line") for j in document["joints"]}
    spots = []
    for c in diff.changes:
        if c.before == "-":
            said = f"{c.after}, not in the baseline"
        elif c.after == "-":
            said = f"{c.before} in the baseline, none now"
        else:
            said = f"{c.before} in the baseline, {c.after} now"
        line = lines.get(c.joint) if c.joint is not None else None
        message = (
            f"{c.joint + ': ' if c.joint else ''}{said} (write the baseline again to accept it)"
        )
        spots.append(_Spot(line, CHANGE_LABELS[c.kind], message))
    return tuple(spots)


def _text(rows: list[_Row]) -> str:
    return "\n".join(
        f"{printable(r.verdict)}: {printable(r.path)}: {printable(r.what)}" for r in rows
    )


def _markdown(rows: list[_Row]) -> str:
    from cspace._render.markdown import cell, code

    lines = [
        "### cspace: against the baseline",
        "",
        "| robot | verdict | what |",
        "| --- | --- | --- |",
    ]
    lines += [f"| {code(r.path)} | {cell(r.verdict)} | {cell(r.what)} |" for r in rows]
    return "\n".join(lines)


def _github(rows: list[_Row]) -> str:
    from cspace._render.annotations import command

    return "\n".join(
        command("error", r.path, s.line, f"cspace baseline: {s.title}", s.message)
        for r in rows
        for s in r.spots
    )


_RENDER = {"text": _text, "markdown": _markdown, "github": _github}
"""The formats of ``check --baseline``, by ``--format`` name."""
