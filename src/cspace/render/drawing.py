"""Pictures of a configuration space, as SVG text: the tree, limit dials, bars, balls.

Everything here works from the report's JSON document (:meth:`Report.to_dict`), so a
saved report draws as well as a fresh one. Names from the file are made printable
(:func:`cspace.safetext.printable`) and XML-escaped before they reach the SVG. Angles
are in rad, drawn counter-clockwise from the right (the usual mathematical sense), with
y pointing down on the page.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from html import escape
from typing import Any, NamedTuple

from cspace.safetext import printable

SPACES = {
    "interval": ("#3b6fd4", "an interval of R: a joint with limits"),
    "line": ("#6b8fd8", "the line R: a translation without limits"),
    "circle": ("#2f9e5a", "the circle S^1: a joint that turns without limits"),
    "so3": ("#8e44ad", "SO(3) = RP^3: every orientation (a ball joint)"),
    "ball": ("#b07cc6", "a ball of rotations: a ball joint with a largest angle"),
    "se2": ("#16a0a0", "SE(2) = R^2 × S^1: a planar joint"),
    "se3": ("#e67e22", "SE(3) = R^3 × RP^3: a floating joint"),
    "mimic": ("#999999", "no coordinates: follows its leader (mimic)"),
    "point": ("#bbbbbb", "a point: a fixed joint"),
    "other": ("#6b8fd8", "a product of lines and intervals"),
}
"""Each class of joint space: its colour and a one-line explanation (legend)."""


def space_class(joint: Mapping[str, Any]) -> str:
    """The class of a joint's space, a key of :data:`SPACES`, from its JSON object."""
    kind, space = joint["kind"], joint["manifold"]
    if kind == "fixed" or space == "point":
        return "mimic" if joint.get("mimic") else "point"
    if kind == "floating":
        return "se3"
    if kind == "planar":
        return "se2"
    if kind == "spherical":
        return "so3" if space == "RP^3" else "ball"
    if space == "S^1":
        return "circle"
    if space == "R^1":
        return "interval" if joint.get("limits") else "line"
    return "other"


def text(value: object) -> str:
    """A name or message from a file, printable and XML-escaped."""
    return escape(printable(str(value), limit=None), quote=True)


Edge = tuple[str, str, list[Mapping[str, Any]], bool]
"""An edge of the drawn tree: parent link, child link, its joints, a run of fixed ones."""


@dataclass(frozen=True)
class Placed:
    """A link placed on the page: its name, depth (column) and row (may be fractional)."""

    link: str
    depth: int
    row: float


class Drawing(NamedTuple):
    """An SVG image and its size in pixels."""

    svg: str
    width: int
    height: int


def tree_svg(
    document: Mapping[str, Any], *, collapse_fixed: bool, marked: set[str] | None = None
) -> Drawing:
    """The kinematic tree: links as dots, joints as edges coloured by their space.

    Laid out left to right (depth = column, each leaf a row, a parent in the middle of
    its children), so that names read horizontally however many joints there are.
    ``collapse_fixed``: a chain of fixed joints (each link with one child) is drawn as
    one grey edge saying how many. ``marked``: joints drawn as changed (a diff).
    """
    joints = list(document["joints"])
    children: dict[str, list[Mapping[str, Any]]] = {}
    has_parent = set()
    for joint in joints:
        parent = joint["parent_link"] if joint["parent_link"] is not None else "(world)"
        siblings = children.setdefault(parent, [])
        if not any(j["child_link"] == joint["child_link"] for j in siblings[-2:]):
            siblings.append(joint)  # several joints between two links: one edge, the first
        has_parent.add(joint["child_link"])
    between: dict[tuple[str, str], list[Mapping[str, Any]]] = {}
    for joint in joints:
        parent = joint["parent_link"] if joint["parent_link"] is not None else "(world)"
        between.setdefault((parent, joint["child_link"]), []).append(joint)
    roots = [link for link in children if link not in has_parent] or ["(world)"]
    edges: list[Edge] = []
    places: dict[str, Placed] = {}
    next_row = [0.0]

    def follow(joint: Mapping[str, Any]) -> tuple[str, list[Mapping[str, Any]], bool]:
        """The link an edge ends at, its joints, and whether they are a run of fixed ones."""
        parent = joint["parent_link"] if joint["parent_link"] is not None else "(world)"
        link = joint["child_link"]
        group = between[(parent, link)]
        if not (collapse_fixed and len(group) == 1 and joint["kind"] == "fixed"):
            return link, group, False
        chain = [joint]
        while True:
            below = children.get(link, [])
            if len(below) != 1 or below[0]["kind"] != "fixed":
                break
            chain.append(below[0])
            link = below[0]["child_link"]
        return link, chain, len(chain) > 1

    below: dict[str, list[str]] = {}

    def place(link: str) -> None:
        stack = [(link, 0)]
        order: list[tuple[str, int]] = []
        while stack:  # iterative: trees may be thousands of joints deep
            here, level = stack.pop()
            order.append((here, level))
            for joint in children.get(here, []):
                child, chain, run = follow(joint)
                edges.append((here, child, chain, run))
                below.setdefault(here, []).append(child)
            stack.extend((child, level + 1) for child in reversed(below.get(here, [])))
        rows: dict[str, float] = {}
        for here, _ in order:  # leaves take rows in the order they are met
            if here not in below:
                rows[here] = next_row[0]
                next_row[0] += 1
        for here, level in reversed(order):  # children before parents
            kids = below.get(here)
            row = rows[here] if not kids else (places[kids[0]].row + places[kids[-1]].row) / 2
            places[here] = Placed(here, level, row)

    for root in roots:
        place(root)
    return _draw_tree(places, edges, marked or set())


_COLUMN, _ROW, _MARGIN = 190, 26, 16


def _draw_tree(places: Mapping[str, Placed], edges: Sequence[Edge], marked: set[str]) -> Drawing:
    depth = max((p.depth for p in places.values()), default=0)
    rows = max((p.row for p in places.values()), default=0.0) + 1
    width = _MARGIN * 2 + (depth + 1) * _COLUMN
    height = int(_MARGIN * 2 + rows * _ROW)

    def at(link: str) -> tuple[float, float]:
        p = places[link]
        return _MARGIN + 8 + p.depth * _COLUMN, _MARGIN + p.row * _ROW + _ROW / 2

    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" class="tree" width="{width}" '
        f'height="{height}" viewBox="0 0 {width} {height}" role="img" '
        'aria-label="kinematic tree">'
    ]
    for parent, child, chain, run in edges:
        (x0, y0), (x1, y1) = at(parent), at(child)
        head = chain[0]
        kind = "point" if run else space_class(head)
        colour = SPACES[kind][0]
        label = f"{len(chain)} fixed joints" if run else " + ".join(j["name"] for j in chain)
        names = escape(json.dumps([printable(str(j["name"]), limit=None) for j in chain]))
        dash = ' stroke-dasharray="4 3"' if kind in ("point", "mimic") else ""
        middle = (x0 + x1) / 2
        changed = (
            " changed"
            if any(printable(str(j["name"]), limit=None) in marked for j in chain)
            else ""
        )
        parts.append(
            f'<g class="edge{changed}" data-joint="{text(head["name"])}" data-joints="{names}">'
            f"<title>{text(label)}: {text(head['kind'])} ({text(head['manifold'])})</title>"
            f'<path d="M{x0:.1f},{y0:.1f} C{middle:.1f},{y0:.1f} {middle:.1f},{y1:.1f} '
            f'{x1:.1f},{y1:.1f}" stroke="{colour}" stroke-width="4" fill="none"{dash}/>'
            f'<text x="{x0 + 14:.1f}" y="{y1 - 5:.1f}" class="joint-label">{text(label)}</text>'
            "</g>"
        )
    for link in places:
        x, y = at(link)
        parts.append(
            f'<g class="link" data-link="{text(link)}"><circle cx="{x:.1f}" cy="{y:.1f}" '
            f'r="4"/><title>link {text(link)}</title></g>'
        )
    parts.append("</svg>")
    return Drawing("".join(parts), width, height)


def dial_svg(joint: Mapping[str, Any]) -> str:
    """A revolute joint as a dial: the allowed arc, the zero mark, turns beyond one."""
    kind = space_class(joint)
    colour = SPACES[kind][0]
    cx = cy = 40.0
    r = 28.0
    parts = [
        '<svg xmlns="http://www.w3.org/2000/svg" class="dial" width="80" height="80" '
        'viewBox="0 0 80 80">',
        f'<circle cx="{cx}" cy="{cy}" r="{r}" fill="none" stroke="#e3e3e3" stroke-width="7"/>',
    ]
    limits = joint.get("limits")
    if kind == "circle" or not limits:
        parts.append(
            f'<circle cx="{cx}" cy="{cy}" r="{r}" fill="none" stroke="{colour}" '
            'stroke-width="7"><title>the whole circle: θ and θ + 2π are one position</title>'
            "</circle>"
        )
    else:
        lower, upper = limits["lower"][0], limits["upper"][0]
        if lower is None or upper is None:
            return ""
        span = upper - lower
        turns = span / (2 * math.pi)
        if turns >= 1:
            parts.append(
                f'<circle cx="{cx}" cy="{cy}" r="{r}" fill="none" stroke="{colour}" '
                f'stroke-width="7"/><text x="{cx}" y="{cy + 4}" class="turns" '
                f'text-anchor="middle">{turns:.3g} turns</text>'
            )
        else:
            parts.append(_arc(cx, cy, r, lower, upper, colour))
    parts.append(  # the zero mark
        f'<line x1="{cx + r - 8}" y1="{cy}" x2="{cx + r + 8}" y2="{cy}" stroke="#222" '
        'stroke-width="2"><title>0 rad</title></line>'
    )
    parts.append("</svg>")
    return "".join(parts)


def _arc(cx: float, cy: float, r: float, start: float, end: float, colour: str) -> str:
    x0, y0 = cx + r * math.cos(start), cy - r * math.sin(start)
    x1, y1 = cx + r * math.cos(end), cy - r * math.sin(end)
    large = 1 if end - start > math.pi else 0
    return (
        f'<path d="M{x0:.2f},{y0:.2f} A{r},{r} 0 {large} 0 {x1:.2f},{y1:.2f}" fill="none" '
        f'stroke="{colour}" stroke-width="7" stroke-linecap="butt"/>'
    )


def bar_svg(joint: Mapping[str, Any]) -> str:
    """A prismatic joint's interval as a bar, with 0 marked when it is inside."""
    limits = joint.get("limits")
    colour = SPACES[space_class(joint)][0]
    if not limits or limits["lower"][0] is None or limits["upper"][0] is None:
        return (
            '<svg xmlns="http://www.w3.org/2000/svg" class="bar" width="140" height="24">'
            f'<line x1="4" y1="12" x2="136" y2="12" stroke="{colour}" stroke-width="6" '
            'stroke-dasharray="10 4"><title>the whole line</title></line></svg>'
        )
    lower, upper = limits["lower"][0], limits["upper"][0]
    span = (upper - lower) or 1.0
    zero = ""
    if lower <= 0 <= upper:
        x = 10 + 120 * (0 - lower) / span
        zero = f'<line x1="{x:.1f}" y1="3" x2="{x:.1f}" y2="21" stroke="#222" stroke-width="2"/>'
    return (
        '<svg xmlns="http://www.w3.org/2000/svg" class="bar" width="140" height="24">'
        f'<rect x="10" y="8" width="120" height="8" fill="{colour}"/>{zero}</svg>'
    )


def ball_svg(joint: Mapping[str, Any]) -> str:
    """SO(3) as what it is: the ball of rotation vectors of length at most π.

    Opposite points of its surface are one rotation (the dashed diameter); a limited
    ball joint shades the ball of rotations it may reach.
    """
    kind = space_class(joint)
    colour = SPACES[kind][0]
    inner = ""
    limits = joint.get("limits")
    if kind == "ball" and limits and limits["upper"] and limits["upper"][0] is not None:
        radius = 30 * min(1.0, limits["upper"][0] / math.pi)
        inner = f'<circle cx="40" cy="40" r="{radius:.1f}" fill="{colour}" fill-opacity="0.5"/>'
    return (
        '<svg xmlns="http://www.w3.org/2000/svg" class="ball" width="80" height="80" '
        'viewBox="0 0 80 80"><title>rotation vectors within π of 0; opposite points on the '
        "surface are one rotation</title>"
        f'<circle cx="40" cy="40" r="30" fill="none" stroke="{colour}" stroke-width="3"/>'
        f'{inner}<line x1="19" y1="19" x2="61" y2="61" stroke="{colour}" '
        'stroke-dasharray="3 3"/><circle cx="19" cy="19" r="3"/><circle cx="61" cy="61" '
        'r="3"/></svg>'
    )


def picture(joint: Mapping[str, Any]) -> str:
    """The picture of a joint's space: dial, bar, ball, or nothing for a point."""
    kind = space_class(joint)
    if joint["kind"] == "prismatic" or kind == "line":
        return bar_svg(joint)
    if kind in ("interval", "circle") and joint["kind"] in ("revolute", "continuous"):
        return dial_svg(joint)
    if kind in ("so3", "ball", "se3"):
        return ball_svg(joint)
    return ""
