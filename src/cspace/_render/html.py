"""The visual report: one self-contained HTML page (the tree alone as SVG: `svg`).

The page shows what the text report says as pictures: the normal form and each factor
in a line; the kinematic tree with every joint coloured by its space; a dial for every
revolute joint (the allowed arc, the zero mark, turns beyond one), a bar for every
prismatic joint, SO(3) as the ball it is; the coordinate layout of q (and MuJoCo's
qpos) joint by joint; findings beside their joints; a mechanism's loops, each a dashed
edge on the tree between the two links its cut holds, and its mobility under the
C-space. Hovering a joint highlights it everywhere. No network: styles, pictures and the
small script are in the page, which works from a ``file://`` URL and as a CI artifact.
Jinja2 (imported only here) fills the template with every value escaped; names from the
file are made printable first.

The page stays within a small multiple of its report's size (a saved report is untrusted):
each name is drawn shortened (`shown`), keyed in
``data-joint`` by `name_key`, and whole only once, in its
joint card's tooltip (a link's whole name is in the JSON report and ``--format svg``).

``cspace collisions --format html`` is a page of its own (`collisions`): the matrix of
link pairs coloured by their share of samples in collision, made by
`cspace._render._collisions_html` and the template ``collisions.html``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from importlib import resources
from typing import TYPE_CHECKING, Any

from cspace._render._html_parts import Pieces, cards_html, strips_html
from cspace._render._loops import changed_key
from cspace._render._mechanism import AMBIENT, mechanism_lines
from cspace._render.drawing import SPACES, name_key, shown, space_class, whole_if_shortened
from cspace._render.tree import tree_svg
from cspace._safetext import printable
from cspace._version import __version__

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.collisions import CollisionReport
    from cspace._reports.diff import Change, ReportDiff
    from cspace._reports.report import Report
    from cspace._reports.summary import SummaryRow

_FACTORS = {
    "R": "R: an interval or a line, one per limited joint coordinate and translation",
    "T": "S^1: a circle, one per joint angle that turns without limits (T^n: n of them)",
    "RP3": "RP^3 = SO(3): every orientation of a ball joint or a floating base",
}


def render_html(report: Report) -> str:
    """The HTML page of a report (see the module docstring). Ends with a newline."""
    return render_html_document(report.to_dict())


def render_html_document(document: Mapping[str, Any]) -> str:
    """The HTML page of a report's JSON document (a saved report draws as a fresh one)."""
    pieces = Pieces()
    view = _view(document, pieces, listed=True)
    return pieces.join(_template("report.html").render(version=__version__, v=view))


def render_index_html(rows: Sequence[SummaryRow], pages: Sequence[str | None]) -> str:
    """The index of a folder of pages: the summary table, each robot linked to its page.

    Args:
        rows: The summary rows of the files, in order.
        pages: Each row's page (a file name in the same folder), or None for none.
    """
    from cspace._reports.summary import HEADER, totals

    views = [
        {
            "cells": [_plain(c) for c in row.cells()],
            "page": page,
            "problem": _plain(row.problem) if row.problem is not None else None,
        }
        for row, page in zip(rows, pages, strict=True)
    ]
    page = _template("index.html").render(
        version=__version__, rows=views, header=HEADER, totals=totals(rows)
    )
    return str(page)


def render_diff_html(old: Mapping[str, Any], new: Mapping[str, Any], diff: ReportDiff) -> str:
    """Two reports' pages side by side, the changes listed above and marked on both.

    Args:
        old: The old side's JSON document (``Report.to_dict`` or a saved report).
        new: The new side's.
        diff: `diff_reports` of the two.
    """
    changes = [_change(c) for c in diff.changes]
    marked = {c["key"] for c in changes if c["key"]} | _loops_changed(old, new, diff)
    pieces = Pieces()
    page = _template("diff.html").render(
        version=__version__,
        changed=diff.changed,
        differs=diff.what_differs,
        changes=changes,
        notes=[_change(c) for c in diff.notes],
        marked=marked,
        old=_view(old, pieces, marked, listed=False),
        new=_view(new, pieces, marked, listed=False),
    )
    return pieces.join(page)


def _loops_changed(old: Mapping[str, Any], new: Mapping[str, Any], diff: ReportDiff) -> set[str]:
    """The keys (`changed_key`) of the cuts a diff adds, removes or changes, on each side."""
    from cspace._reports._closure_diff import cut_text
    from cspace._reports.closure import Cut

    said = {text for c in diff.changes if c.kind.startswith("cut-") for text in (c.before, c.after)}
    cuts = [cut for doc in (old, new) for cut in (doc.get("closure") or {}).get("cuts", ())]
    return {changed_key(str(cut["name"])) for cut in cuts if cut_text(Cut.from_dict(cut)) in said}


def _change(change: Change) -> dict[str, Any]:
    """A change or note as the diff page shows it, named in the text diff's words."""
    from cspace._reports.diff import CHANGE_LABELS

    joint = change.joint
    return {
        "kind": CHANGE_LABELS[change.kind],  # "C-space", "q/v size", as cspace diff says
        "key": name_key(joint) if joint else None,
        "joint": shown(joint) if joint else None,  # whole in its card's tooltip
        "before": printable(change.before),  # at most 600 characters, as in the text
        "after": printable(change.after),
    }


def _template(name: str) -> Any:
    """A template of ``cspace/_render/templates``, every value escaped (autoescape)."""
    import jinja2

    def load(template: str) -> str:
        return (
            resources.files("cspace._render").joinpath(f"templates/{template}").read_text("utf-8")
        )

    environment = jinja2.Environment(
        loader=jinja2.FunctionLoader(load), autoescape=True, keep_trailing_newline=True
    )
    return environment.get_template(name)


def _view(
    document: Mapping[str, Any], pieces: Pieces, marked: set[str] | None = None, *, listed: bool
) -> dict[str, Any]:
    """What the templates show of one report; ``listed``: its findings listed too."""
    manifold = document["manifold"]
    joints = document["joints"]
    by_joint: dict[str, list[Mapping[str, Any]]] = {}  # by the joint's whole name
    for d in document["diagnostics"]:
        if d.get("joint"):
            by_joint.setdefault(str(d["joint"]), []).append(d)
    findings = [
        {
            "severity": d["severity"],
            "code": d["code"],
            "line": d.get("line"),
            "file": _plain(str(d["file"]).replace("\\", "/").rsplit("/", 1)[-1])
            if d.get("file")
            else None,
            "message": _plain(d["message"]),
            "joint": name_key(d["joint"]) if d.get("joint") else None,
        }
        for d in (document["diagnostics"] if listed else ())
    ]
    used = {space_class(j) for j in joints}
    return {
        "robot": shown(document["robot"]) or "(unnamed)",
        "robot_title": whole_if_shortened(document["robot"]),
        "root_joint": document.get("root_joint"),
        "notation": manifold["notation"],
        "dimension": document["dimension"],
        "nq": document["nq"],
        "nv": document["nv"],
        "fundamental_group": manifold["fundamental_group"],
        "simply_connected": manifold["simply_connected"],
        "factor_lines": [
            f"{count} × {_FACTORS[key]}" for key, count in manifold["factors"].items() if count
        ]
        or ["a point: the robot cannot move"],
        "source": _plain(
            f"{document['source']['path']} ({document['source']['format']}, sha256 "
            f"{document['source']['sha256'][:12]})"
        ),
        "legend": [(name, *SPACES[name]) for name in SPACES if name in used],
        "tree_collapsed": pieces.put(
            tree_svg(
                document, collapse_fixed=True, marked=marked, whole_joints=False, whole_links=False
            ).svg
        ),
        "tree_full": pieces.put(
            tree_svg(
                document, collapse_fixed=False, marked=marked, whole_joints=False, whole_links=False
            ).svg
        ),
        "cards": pieces.put(cards_html(joints, by_joint, marked or set())),
        "strips": [(title, pieces.put(cells)) for title, cells in strips_html(joints)],
        "findings": findings,
        "mechanism": _mechanism(document),
        "ambient": AMBIENT,
        "limits": _limits(document),
        "control": _control(document),
    }


def _limits(document: Mapping[str, Any]) -> dict[str, Any] | None:
    """The limits MoveIt plans with (the report's ``limits_file``): a title and a table."""
    if not document.get("limits_file"):
        return None
    from cspace._render._limits import COLUMNS, limits_head, limits_rows
    from cspace._reports.limits import LimitsSummary

    summary = LimitsSummary.from_dict(document["limits_file"])
    rows = [[_plain(cell) for cell in row] for row in limits_rows(summary)]
    return {"head": limits_head(summary), "columns": COLUMNS, "rows": rows}


def _control(document: Mapping[str, Any]) -> dict[str, Any] | None:
    """The URDF's ``<ros2_control>`` components (the report's ``ros2_control``): a table."""
    if not document.get("ros2_control"):
        return None
    from cspace._render._ros2_control import ROW_COLUMNS, control_rows
    from cspace._ros2_control import ControlHardware

    hardware = [ControlHardware.from_dict(h) for h in document["ros2_control"]]
    rows = [[_plain(cell) for cell in row] for row in control_rows(hardware)]
    return {"columns": ROW_COLUMNS, "rows": rows}


def _mechanism(document: Mapping[str, Any]) -> list[str]:
    """The mechanism's lines (`mechanism_lines`), names drawn shortened; none for a tree."""
    if not document.get("closure"):
        return []
    from cspace._reports.closure import Closure

    closure = Closure.from_dict(document["closure"])
    return mechanism_lines(closure, shown, lambda name: f"'{shown(name)}'")


def _plain(value: object) -> str:
    """Text from a file, made printable (control, C1, bidi characters escaped)."""
    return printable(str(value), limit=None)


def inspect_one(report: Report, options: Options) -> str:
    """``inspect --format html`` of one robot: its page (`render_html`)."""
    return render_html(report)


def inspect_piece(report: Report) -> str:
    """One robot's page, for a folder of pages (``--output-dir``)."""
    return render_html(report)


def diff(
    old: Mapping[str, Any], new: Mapping[str, Any], changes: ReportDiff, options: Options
) -> str:
    """``diff --format html``: both sides' pages, the changes marked (`render_diff_html`)."""
    return render_diff_html(old, new, changes)


def collisions(report: CollisionReport, options: Options) -> str:
    """``cspace collisions --format html``: the page with the matrix of link pairs.

    What it shows is `cspace._render._collisions_html.view`; the template
    ``collisions.html`` escapes every value.
    """
    from cspace._render._collisions_html import view

    return str(_template("collisions.html").render(version=__version__, v=view(report)))
