"""The kinematic tree as SVG text: links as dots, joints as edges coloured by their space.

Drawn from the report's JSON document, so a saved report draws as a fresh one; a
mechanism's loops are drawn on it (`_loops`), each a dashed edge between the two links
its cut holds together. Two
layouts: left to right for a shallow tree, an outline (rows, indented where the tree
branches) for one that would be wider than `WIDEST` pixels. Either is linear in the
joints: each link is placed once, each edge drawn once, every name shortened to
`SHOWN_CHARS` characters where it is drawn, and no label lies where an edge passes.
"""

import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from html import escape
from typing import Any

from cspace._record import NamedTuple
from cspace._render._loops import Loop, across, beside, loops_of
from cspace._render.drawing import SPACES, name_key, shown, space_class, text

Group = list[Mapping[str, Any]]
"""The joints of one drawn edge: one joint, or an MJCF body's several (consecutive)."""

Edge = tuple[str | None, str, Group, bool]
"""An edge of the drawn tree: parent link (None above a root joint cspace added), child
link, its joints, and whether they are a run of fixed ones."""


@dataclass(frozen=True)
class Placed:
    """A link placed on the page: its name, depth (column) and row (may be fractional)."""

    link: str | None
    depth: int
    row: float


class Drawing(NamedTuple):
    """An SVG image and its size in pixels."""

    svg: str
    width: int
    height: int


_MOST_NAMES = 6
"""Most joint names in one edge's label: an MJCF body may hold thousands of joints."""


def tree_svg(
    document: Mapping[str, Any],
    *,
    collapse_fixed: bool,
    marked: set[str] | None = None,
    whole_joints: bool = True,
    whole_links: bool = True,
) -> Drawing:
    """The kinematic tree: links as dots, joints as edges coloured by their space.

    Laid out left to right (depth = column, each leaf a row, a parent in the middle of
    its children) when that is at most `WIDEST` pixels wide, else as an outline (each
    link a row, indented where the tree branches); names read horizontally either way.
    Linear in the joints whatever the document: each link is placed once (one reached
    again, which a checked report never has, keeps its first place), so no loop makes it
    run forever. Names are drawn shortened (`shown`) and keyed by `name_key`.

    Args:
        document: The report's JSON document.
        collapse_fixed: Draw a chain of fixed joints (each link with one child) as one
            grey edge saying how many.
        marked: Keys (`name_key`) of joints drawn as changed (a diff), and of loops
            (`_loops.changed_key`).
        whole_joints: An edge's tooltip holds its joints' whole names; else the shortened
            ones (the page, whose joint cards hold the whole names).
        whole_links: A link's tooltip holds its whole name; else the shortened one (the
            page: a link's whole name is in the JSON report and ``--format svg``).
    """
    groups: list[Group] = []
    children: dict[str | None, list[Group]] = {}
    is_child: set[str] = set()
    for joint in document["joints"]:
        parent, child = joint["parent_link"], joint["child_link"]
        last = groups[-1][0] if groups else None
        if last is not None and (last["parent_link"], last["child_link"]) == (parent, child):
            groups[-1].append(joint)  # several joints between two links: one edge
            continue
        groups.append([joint])
        children.setdefault(parent, []).append(groups[-1])
        is_child.add(child)
    roots: list[str | None] = [link for link in children if link not in is_child] or [None]
    seen: set[str | None] = set()
    merged: dict[str, str] = {}  # a link drawn as part of a run of fixed joints: its end

    def follow(group: Group) -> tuple[str, Group, bool]:
        """The link an edge ends at, its joints, and whether they are a run of fixed ones."""
        joint = group[0]
        link: str = joint["child_link"]
        if not (collapse_fixed and len(group) == 1 and joint["kind"] == "fixed"):
            return link, group, False
        chain, within = [joint], []
        while True:
            below = children.get(link, [])
            if len(below) != 1 or len(below[0]) != 1 or below[0][0]["kind"] != "fixed":
                break
            if below[0][0]["child_link"] in seen:
                break
            seen.add(link)  # drawn as part of the run, not as a dot
            within.append(link)
            chain.append(below[0][0])
            link = below[0][0]["child_link"]
        merged.update((inner, link) for inner in within)
        return link, chain, len(chain) > 1

    edges: list[Edge] = []
    places: dict[str | None, Placed] = {}  # left to right: depth a column, leaves rows
    listed: dict[str | None, Placed] = {}  # an outline: each link its own row, indented
    below: dict[str | None, list[str]] = {}
    next_row = 0.0
    for root in roots:
        if root in seen:
            continue
        seen.add(root)
        stack: list[tuple[str | None, int]] = [(root, 0)]
        order: list[tuple[str | None, int]] = []
        indent: dict[str | None, int] = {root: 0}  # the outline's: one more where it branches
        while stack:  # iterative: trees may be thousands of joints deep
            here, level = stack.pop()
            listed[here] = Placed(here, indent[here], float(len(listed)))
            order.append((here, level))
            kids: list[str] = []
            for group in children.get(here, []):
                if group[0]["child_link"] in seen:
                    continue  # reached twice: drawn once
                child, chain, run = follow(group)
                seen.add(child)
                edges.append((here, child, chain, run))
                kids.append(child)
            if kids:
                below[here] = kids
            indent.update((child, indent[here] + (len(kids) > 1)) for child in kids)
            stack.extend((child, level + 1) for child in reversed(kids))
        rows: dict[str | None, float] = {}
        for here, _ in order:  # leaves take rows in the order they are met
            if here not in below:
                rows[here] = next_row
                next_row += 1
        for here, level in reversed(order):  # children before parents
            placed = below.get(here)
            row = rows[here] if not placed else (places[placed[0]].row + places[placed[-1]].row) / 2
            places[here] = Placed(here, level, row)
    labels = [_label(chain, run) for _, _, chain, run in edges]
    column = max([_COLUMN, *(_CURVE + _text_width(label) + _GAP for label in labels)])
    depth = max((p.depth for p in places.values()), default=0)
    loops = loops_of(document, lambda link: _dot(merged.get(link, link), places), marked or set())
    marks = (marked or set(), whole_joints, whole_links)
    if _MARGIN * 2 + (depth + 1) * column <= WIDEST:
        return _draw_tree(places, edges, labels, column, loops, *marks)
    return _draw_outline(listed, edges, labels, loops, *marks)


def _dot(link: str, places: Mapping[str | None, Placed]) -> str | None:
    """The link itself when it is drawn as a dot, else None."""
    return link if link in places else None


_COLUMN, _ROW, _MARGIN = 190, 26, 16
_CURVE, _GAP = 80, 16
"""Left to right, an edge bends in its first `_CURVE` pixels and runs straight to its
child; its label sits over the straight part, `_GAP` pixels kept clear at the end."""

_INDENT, _LINE = 28, 24
"""The outline: pixels a level is indented, and a row's height."""

WIDEST = 1300
"""Widest tree drawn left to right (px): a page 1,400 pixels wide shows it whole. A
deeper tree (a humanoid, or a serial arm, whose depth is its joints) is drawn as an
outline instead, each link on its own row, indented by depth: its width grows with the
depth by `_INDENT` pixels, not by a column, and it reads top to bottom."""

_EM = 12.0
"""A label's font size (px)."""

_NARROW = frozenset("ijlI|.,:;' ")
_MIDDLE = frozenset("frt()[]-/\\")
_WIDE = frozenset("mwMW%@+=<>#&~^")


def _text_width(label: str) -> float:
    """An upper bound of a label's width in pixels, at 12 px in a sans-serif font.

    Each character's advance is bounded by its class, from DejaVu Sans (Debian's
    default; Arial and Helvetica are narrower): narrow ones 0.34 em, ``f r t``, round
    and square brackets, a hyphen and slashes 0.45 em, other lower-case letters, digits and
    ``_`` 0.64 em, capitals 0.80 em, ``m w M W`` and the wide signs (``% @ + = < > # & ~
    ^``) 1.0 em, anything beyond ASCII 1.5 em (CJK is 1 em, ``‰`` 1.34); and 5% more.
    ``tests/test_html.py`` measures every printable ASCII character against it.
    """
    ems = 0.0
    for ch in label:
        if ch in _NARROW:
            ems += 0.34
        elif ch in _MIDDLE:
            ems += 0.45
        elif not ch.isascii():
            ems += 1.5
        elif ch in _WIDE:
            ems += 1.0
        elif ch.isupper():
            ems += 0.80
        else:
            ems += 0.64
    return ems * _EM * 1.05


def _label(chain: Group, run: bool) -> str:
    """What an edge says: its joints' shortened names (six at most), or a run's count."""
    if run:
        return f"{len(chain)} fixed joints"
    names = " + ".join(shown(j["name"]) for j in chain[:_MOST_NAMES])
    more = len(chain) - _MOST_NAMES
    return names + (f" + {more:,} more" if more > 0 else "")


def _draw_tree(
    places: Mapping[str | None, Placed],
    edges: Sequence[Edge],
    labels: Sequence[str],
    column: float,
    loops: Sequence[Loop],
    marked: set[str],
    whole_joints: bool,
    whole_links: bool,
) -> Drawing:
    """Left to right: depth a column, each leaf a row, a parent amid its children.

    Each label lies over its edge's straight part, which the column is made wide enough
    for, so no label meets an edge.
    """
    depth = max((p.depth for p in places.values()), default=0)
    rows = max((p.row for p in places.values()), default=0.0) + 1
    width = int(_MARGIN * 2 + (depth + 1) * column)
    height = int(_MARGIN * 2 + rows * _ROW)

    def at(link: str | None) -> tuple[float, float]:
        p = places[link]
        return _MARGIN + 8 + p.depth * column, _MARGIN + p.row * _ROW + _ROW / 2

    drawn = []
    for (parent, child, chain, run), label in zip(edges, labels, strict=True):
        (x0, y0), (x1, y1) = at(parent), at(child)
        bend = x0 + _CURVE / 2
        path = (
            f"M{x0:.1f},{y0:.1f} C{bend:.1f},{y0:.1f} {bend:.1f},{y1:.1f} "
            f"{x0 + _CURVE:.1f},{y1:.1f} H{x1:.1f}"
        )
        drawn.append(
            _edge(chain, run, label, path, "", (x0 + _CURVE + 4, y1 - 5), marked, whole_joints)
        )
    closing, lowest = across(loops, at, _ROW, whole_joints)
    height = max(height, int(lowest + _MARGIN))
    return _svg([*drawn, *closing], places, at, width, height, whole_links)


def _draw_outline(
    listed: Mapping[str | None, Placed],
    edges: Sequence[Edge],
    labels: Sequence[str],
    loops: Sequence[Loop],
    marked: set[str],
    whole_joints: bool,
    whole_links: bool,
) -> Drawing:
    """An outline: each link on its own row (depth first), indented where the tree branches.

    A chain (a link with one child) goes straight down, its edges in their spaces'
    colours; a branch's edges run down its trunk (thin, grey) and across to each child
    (in the child's colour), one level in. Each label follows its link's dot. A trunk
    that passes a row belongs to a branching ancestor of that row's link, which is
    indented less, so no label meets an edge, however large the tree.
    """
    depth = max((p.depth for p in listed.values()), default=0)
    rows = len(listed)
    widest = max((_text_width(label) for label in labels), default=0.0)
    width = int(_MARGIN * 2 + 8 + depth * _INDENT + 12 + widest)
    height = int(_MARGIN * 2 + rows * _LINE)

    def at(link: str | None) -> tuple[float, float]:
        p = listed[link]
        return _MARGIN + 8 + p.depth * _INDENT, _MARGIN + p.row * _LINE + _LINE / 2

    drawn = []
    for (parent, child, chain, run), label in zip(edges, labels, strict=True):
        (x0, y0), (x1, y1) = at(parent), at(child)
        if x1 == x0:  # a chain: straight down
            path, trunk = f"M{x0:.1f},{y0:.1f} V{y1:.1f}", ""
        else:
            path = f"M{x0:.1f},{y1:.1f} H{x1:.1f}"
            trunk = (
                f'<path d="M{x0:.1f},{y0:.1f} V{y1:.1f}" class="trunk" stroke="#bbbbbb" '
                'stroke-width="1.5" fill="none"/>'
            )
        at_label = (x1 + 10, y1 + 4)
        drawn.append(_edge(chain, run, label, path, trunk, at_label, marked, whole_joints))
    right = width - _MARGIN
    closing, rightmost = beside(loops, at, right, whole_joints, _text_width)
    width = max(width, int(rightmost + _MARGIN))
    return _svg([*drawn, *closing], listed, at, width, height, whole_links)


def _edge(
    chain: Group,
    run: bool,
    label: str,
    path: str,
    trunk: str,
    where: tuple[float, float],
    marked: set[str],
    whole_joints: bool,
) -> str:
    """One edge: its title, its path in its space's colour, its label at ``where``."""
    head = chain[0]
    kind = "point" if run else space_class(head)
    tip = " + ".join(str(j["name"]) for j in chain) if whole_joints and not run else label
    keys = [name_key(j["name"]) for j in chain]
    dash = ' stroke-dasharray="4 3"' if kind in ("point", "mimic") else ""
    changed = " changed" if any(key in marked for key in keys) else ""
    return (
        f'<g class="edge{changed}" data-joint="{escape(keys[0])}" '
        f'data-joints="{escape(json.dumps(keys))}">'
        f"<title>{text(tip)}: {text(head['kind'])} ({text(head['manifold'])})</title>{trunk}"
        f'<path d="{path}" stroke="{SPACES[kind][0]}" stroke-width="4" fill="none"{dash}/>'
        f'<text x="{where[0]:.1f}" y="{where[1]:.1f}" class="joint-label">{text(label)}</text>'
        "</g>"
    )


def _svg(
    edges: Sequence[str],
    places: Mapping[str | None, Placed],
    at: Callable[[str | None], tuple[float, float]],
    width: int,
    height: int,
    whole_links: bool,
) -> Drawing:
    """The image: the edges, then a dot for each link (its name in the tooltip)."""
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" class="tree" width="{width}" '
        f'height="{height}" viewBox="0 0 {width} {height}" role="img" '
        'aria-label="kinematic tree">',
        *edges,
    ]
    for link in places:
        x, y = at(link)
        name = "(world)" if link is None else link
        parts.append(
            f'<g class="link" data-link="{escape(name_key(name))}"><circle cx="{x:.1f}" '
            f'cy="{y:.1f}" r="4"/><title>link {text(name if whole_links else shown(name))}'
            "</title></g>"
        )
    parts.append("</svg>")
    return Drawing("".join(parts), width, height)
