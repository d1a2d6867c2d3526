"""``cspace check --baseline FILE ROBOTS...``: each robot against its accepted report.

One line per robot (text) or a table (Markdown): ``same`` when its C-space is the
baseline's, ``changed`` with the diff's headline, ``new`` when the baseline has no
report of it; and a line for each baseline report whose file is gone. Exit 0 when all
are the same, 1 when any differs, 2 when a robot gives no report or the baseline cannot
be read.
"""

from __future__ import annotations

import argparse
import os

import cspace
from cspace._safetext import printable

from . import exit_codes, output
from .robots import expand_patterns, load_document, xacro_options


def check_baseline(args: argparse.Namespace) -> int:
    """Compare each robot named with the baseline's report of it."""
    from cspace._render.markdown import cell, code
    from cspace._reports.baseline import read_baseline
    from cspace._reports.diff import diff_reports
    from cspace._reports.savedreport import read_report_document

    try:
        xacro_options(args)
    except ValueError as exc:
        output.error(str(exc))
        return exit_codes.NO_REPORT
    baseline = read_baseline(args.baseline)
    worst = exit_codes.OK
    rows: list[tuple[str, str, str]] = []  # path, verdict, what
    names = expand_patterns(args.robot)
    for name in names:
        try:
            document = load_document(name, args)
        except cspace.CspaceError as exc:
            code_ = getattr(exc, "code", None)
            output.error(f"{exc} [{code_}]" if isinstance(code_, str) else str(exc))
            rows.append((name, "no report", str(exc)))
            worst = exit_codes.NO_REPORT
            continue
        path = str(document["source"]["path"])
        if path not in baseline:
            rows.append((path, "new", f"{document['manifold']['notation']}, not in the baseline"))
            worst = max(worst, exit_codes.FINDINGS)
            continue
        where, line = baseline[path]
        diff = diff_reports(read_report_document(where, line), document)
        if diff.changed:
            what = f"{diff.old_manifold} -> {diff.new_manifold}; {diff.what_differs}"
            rows.append((path, "changed", what))
            worst = max(worst, exit_codes.FINDINGS)
        elif diff.differs:
            rows.append((path, "differs", f"{diff.new_manifold}, but {diff.what_differs}"))
            worst = max(worst, exit_codes.FINDINGS)
        else:
            rows.append((path, "same", str(document["manifold"]["notation"])))
    checked = {row[0] for row in rows}
    for path in sorted(set(baseline) - checked):
        if not os.path.lexists(path):
            rows.append((path, "gone", "in the baseline, but the file is gone"))
            worst = max(worst, exit_codes.FINDINGS)
    if args.format == "markdown":
        lines = [
            "### cspace: against the baseline",
            "",
            "| robot | verdict | what |",
            "| --- | --- | --- |",
        ]
        lines += [f"| {code(p)} | {cell(v)} | {cell(w)} |" for p, v, w in rows]
        output.write("\n".join(lines))
    else:
        output.write(
            "\n".join(f"{printable(v)}: {printable(p)}: {printable(w)}" for p, v, w in rows)
        )
    return worst
