"""The visual report: one self-contained HTML page, and the tree alone as SVG.

The page shows what the text report says as pictures: the normal form and each factor
in a line; the kinematic tree with every joint coloured by its space; a dial for every
revolute joint (the allowed arc, the zero mark, turns beyond one), a bar for every
prismatic joint, SO(3) as the ball it is; the coordinate layout of q (and MuJoCo's
qpos) joint by joint; findings beside their joints. Hovering a joint highlights it
everywhere. No network: styles, pictures and the small script are in the page, which
works from a ``file://`` URL and as a CI artifact. Jinja2 (imported only here) fills the
template with every value escaped; names from the file are made printable first.
"""

from __future__ import annotations

from collections.abc import Mapping
from importlib import resources
from typing import TYPE_CHECKING, Any

from cspace._version import __version__
from cspace.render.drawing import SPACES, picture, space_class, tree_svg
from cspace.safetext import printable

if TYPE_CHECKING:
    from cspace.reports.diff import Change, ReportDiff
    from cspace.reports.report import Report

_FACTORS = {
    "R": "R: an interval or a line, one per limited joint coordinate and translation",
    "T": "S^1: a circle, one per joint angle that turns without limits (T^n: n of them)",
    "RP3": "RP^3 = SO(3): every orientation of a ball joint or a floating base",
}


def render_html(report: Report) -> str:
    """The HTML page of a report (see the module docstring). Ends with a newline."""
    return render_html_document(report.to_dict())


def render_svg(report: Report) -> str:
    """The kinematic tree with each joint's space and a legend, as one SVG image."""
    document = report.to_dict()
    tree, width, height = tree_svg(document, collapse_fixed=True)
    used = sorted({space_class(j) for j in document["joints"]}, key=list(SPACES).index)
    title = _plain(f"{document['robot']}: C = {document['manifold']['notation']}")
    legend = [
        f'<g transform="translate(16,{52 + 18 * k})"><rect width="22" height="6" y="-6" '
        f'fill="{SPACES[name][0]}"/><text x="30" font-size="12">{_xml(SPACES[name][1])}</text></g>'
        for k, name in enumerate(used)
    ]
    top = 60 + 18 * len(used)
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{max(width, 420)}" '
        f'height="{height + top}" font-family="sans-serif">'
        f'<rect width="100%" height="100%" fill="#fff"/>'
        f'<text x="16" y="28" font-size="18" font-weight="600">{_xml(title)}</text>'
        + "".join(legend)
        + f'<g transform="translate(0,{top})">{tree}</g></svg>\n'
    )


def render_html_document(document: Mapping[str, Any]) -> str:
    """The HTML page of a report's JSON document (a saved report draws as a fresh one)."""
    page: str = _template("report.html").render(version=__version__, v=_view(document))
    return page


def render_diff_html(old: Mapping[str, Any], new: Mapping[str, Any], diff: ReportDiff) -> str:
    """Two reports' pages side by side, the changes listed above and marked on both.

    Args:
        old: The old side's JSON document (``Report.to_dict`` or a saved report).
        new: The new side's.
        diff: :func:`cspace.reports.diff.diff_reports` of the two.
    """
    changes = [_change(c) for c in diff.changes]
    marked = {c["joint"] for c in changes if c["joint"]}
    page: str = _template("diff.html").render(
        version=__version__,
        changed=diff.changed,
        changes=changes,
        notes=[_change(c) for c in diff.notes],
        marked=marked,
        old=_view(old, marked),
        new=_view(new, marked),
    )
    return page


def _change(change: Change) -> dict[str, Any]:
    return {
        "kind": change.kind,
        "joint": _plain(change.joint) if change.joint else None,
        "before": _plain(change.before),
        "after": _plain(change.after),
    }


def _template(name: str) -> Any:
    """A template of ``cspace/render/templates``, every value escaped (autoescape)."""
    import jinja2

    def load(template: str) -> str:
        return resources.files("cspace.render").joinpath(f"templates/{template}").read_text("utf-8")

    environment = jinja2.Environment(
        loader=jinja2.FunctionLoader(load), autoescape=True, keep_trailing_newline=True
    )
    return environment.get_template(name)


def _view(document: Mapping[str, Any], marked: set[str] | None = None) -> dict[str, Any]:
    manifold = document["manifold"]
    findings = [
        {
            "severity": d["severity"],
            "code": d["code"],
            "line": d.get("line"),
            "message": _plain(d["message"]),
            "joint": _plain(d["joint"]) if d.get("joint") else None,
        }
        for d in document["diagnostics"]
    ]
    by_joint: dict[str, list[dict[str, Any]]] = {}
    for f in findings:
        if f["joint"]:
            by_joint.setdefault(f["joint"], []).append(f)
    used = {space_class(j) for j in document["joints"]}
    return {
        "robot": _plain(document["robot"]) or "(unnamed)",
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
        "tree_collapsed": tree_svg(document, collapse_fixed=True, marked=marked).svg,
        "tree_full": tree_svg(document, collapse_fixed=False, marked=marked).svg,
        "joints": [_card(j, by_joint.get(_plain(j["name"]), [])) for j in document["joints"]],
        "strips": _strips(document),
        "findings": findings,
    }


def _card(joint: Mapping[str, Any], findings: list[dict[str, Any]]) -> dict[str, Any]:
    limits = joint.get("limits")
    shown = ""
    if limits:
        pairs = [
            f"[{_number(lo)}, {_number(hi)}]"
            for lo, hi in zip(limits["lower"], limits["upper"], strict=True)
        ]
        shown = " ".join(pairs) + f" {limits['unit']}"
    q = joint.get("q_index")
    qpos = joint.get("qposadr")
    return {
        "name": _plain(joint["name"]),
        "kind": joint["kind"],
        "manifold": joint["manifold"],
        "limits": shown,
        "colour": SPACES[space_class(joint)][0],
        "picture": picture(joint),
        "q": None if q is None else _range(q, joint["nq"]),
        "qpos": None if qpos is None else str(qpos),
        "findings": findings,
    }


def _strips(document: Mapping[str, Any]) -> list[tuple[str, list[dict[str, Any]]]]:
    """One strip of labelled slots per convention the report knows."""
    titles = {
        "canonical": "cspace's canonical coordinates",
        "pinocchio_q": "Pinocchio's q",
        "mujoco_qpos": "MuJoCo's qpos",
    }
    strips = []
    for key, title in titles.items():
        cells: list[tuple[int, dict[str, Any]]] = []
        for joint in document["joints"]:
            slot = joint.get("slots", {}).get(key)
            if not slot:
                continue
            for k, name in enumerate(slot["names"]):
                cells.append(
                    (
                        slot["index"] + k,
                        {
                            "index": slot["index"] + k,
                            "name": _plain(name),
                            "joint": _plain(joint["name"]),
                            "colour": SPACES[space_class(joint)][0],
                        },
                    )
                )
        if cells:
            strips.append((title, [cell for _, cell in sorted(cells, key=lambda c: c[0])]))
    return strips


def _range(first: int, count: int) -> str:
    return str(first) if count == 1 else f"{first}..{first + count - 1}"


def _number(x: float | None) -> str:
    return "None" if x is None else f"{x:.6g}"


def _plain(value: object) -> str:
    """Text from a file, made printable (control, C1, bidi characters escaped)."""
    return printable(str(value), limit=None)


def _xml(value: str) -> str:
    from html import escape

    return escape(value, quote=True)
