"""The kinematic tree as SVG text: links as dots, joints as edges coloured by their space.

Drawn from the report's JSON document, so a saved report draws as a fresh one. The
layout is linear in the joints: each link is placed once, each edge drawn once, every
name shortened to `SHOWN_CHARS` characters where it is drawn.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from html import escape
from typing import Any, NamedTuple

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
    its children), so that names read horizontally however many joints there are.
    Linear in the joints whatever the document: each link is placed once (one reached
    again, which a checked report never has, keeps its first place), so no loop makes it
    run forever. Names are drawn shortened (`shown`) and keyed by `name_key`.

    Args:
        document: The report's JSON document.
        collapse_fixed: Draw a chain of fixed joints (each link with one child) as one
            grey edge saying how many.
        marked: Keys (`name_key`) of joints drawn as changed (a diff).
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

    def follow(group: Group) -> tuple[str, Group, bool]:
        """The link an edge ends at, its joints, and whether they are a run of fixed ones."""
        joint = group[0]
        link: str = joint["child_link"]
        if not (collapse_fixed and len(group) == 1 and joint["kind"] == "fixed"):
            return link, group, False
        chain = [joint]
        while True:
            below = children.get(link, [])
            if len(below) != 1 or len(below[0]) != 1 or below[0][0]["kind"] != "fixed":
                break
            if below[0][0]["child_link"] in seen:
                break
            seen.add(link)  # drawn as part of the run, not as a dot
            chain.append(below[0][0])
            link = below[0][0]["child_link"]
        return link, chain, len(chain) > 1

    edges: list[Edge] = []
    places: dict[str | None, Placed] = {}
    below: dict[str | None, list[str]] = {}
    next_row = 0.0
    for root in roots:
        if root in seen:
            continue
        seen.add(root)
        stack: list[tuple[str | None, int]] = [(root, 0)]
        order: list[tuple[str | None, int]] = []
        while stack:  # iterative: trees may be thousands of joints deep
            here, level = stack.pop()
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
    return _draw_tree(places, edges, marked or set(), whole_joints, whole_links)


_COLUMN, _ROW, _MARGIN = 190, 26, 16


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
    marked: set[str],
    whole_joints: bool,
    whole_links: bool,
) -> Drawing:
    depth = max((p.depth for p in places.values()), default=0)
    rows = max((p.row for p in places.values()), default=0.0) + 1
    width = _MARGIN * 2 + (depth + 1) * _COLUMN
    height = int(_MARGIN * 2 + rows * _ROW)

    def at(link: str | None) -> tuple[float, float]:
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
        label = _label(chain, run)
        tip = " + ".join(str(j["name"]) for j in chain) if whole_joints and not run else label
        keys = [name_key(j["name"]) for j in chain]
        dash = ' stroke-dasharray="4 3"' if kind in ("point", "mimic") else ""
        middle = (x0 + x1) / 2
        changed = " changed" if any(key in marked for key in keys) else ""
        parts.append(
            f'<g class="edge{changed}" data-joint="{escape(keys[0])}" '
            f'data-joints="{escape(json.dumps(keys))}">'
            f"<title>{text(tip)}: {text(head['kind'])} ({text(head['manifold'])})</title>"
            f'<path d="M{x0:.1f},{y0:.1f} C{middle:.1f},{y0:.1f} {middle:.1f},{y1:.1f} '
            f'{x1:.1f},{y1:.1f}" stroke="{colour}" stroke-width="4" fill="none"{dash}/>'
            f'<text x="{x0 + 14:.1f}" y="{y1 - 5:.1f}" class="joint-label">{text(label)}</text>'
            "</g>"
        )
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
