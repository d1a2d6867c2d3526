"""A mechanism's loops drawn on its tree: a dashed edge between each cut's two links.

The tree (`tree`) is the mechanism with its loops cut open; each cut (the report's
``closure.cuts``) closes one, between two links of the tree. It is drawn as a dashed
orange edge between their dots, labelled with the cut's name (shortened as every name
drawn, `shown`; whole, made printable, in its tooltip when the caller draws whole
names). Left to right, it bows below the links' rows; in an outline, it runs under the
labels to a lane of its own right of them, its label beyond the lanes. At most
`MOST_DRAWN` are drawn (the text and JSON reports list them all), so the picture stays
linear in the report.
"""

from collections.abc import Callable, Mapping, Sequence
from typing import Any

from cspace._record import NamedTuple
from cspace._render.drawing import shown, text

MOST_DRAWN = 32
"""Most cuts drawn on one tree."""

COLOUR = "#e07b00"
"""A loop's edge: no space's colour (`drawing.SPACES`)."""

LANE = 12
"""Pixels between two loops' lanes in an outline, and the lane's distance from the text."""

At = Callable[[str | None], tuple[float, float]]
"""Where a placed link's dot is."""


class Loop(NamedTuple):
    """A cut to draw: its kind and name, and the links whose dots it joins."""

    kind: str
    name: str
    first: str
    second: str
    changed: bool = False


def changed_key(name: str) -> str:
    """The key of a cut drawn as changed (a diff): never a joint's, which is printable."""
    return f"\x00loop {name}"


def loops_of(
    document: Mapping[str, Any], placed: Callable[[str], str | None], marked: set[str]
) -> list[Loop]:
    """The report's cuts whose two links are drawn (`MOST_DRAWN` at most).

    ``placed`` maps a link to the placed link whose dot stands for it (a link inside a
    collapsed run of fixed joints is drawn as the run's end), or None when it has none;
    a cut whose `changed_key` is ``marked`` is drawn as changed.
    """
    closure = document.get("closure")
    if not closure:
        return []
    out = []
    for cut in closure["cuts"][:MOST_DRAWN]:
        first, second = (placed(str(link)) for link in cut["links"])
        if first is not None and second is not None and first != second:
            name = str(cut["name"])
            changed = changed_key(name) in marked
            out.append(Loop(str(cut["kind"]), name, first, second, changed))
    return out


def _edge(loop: Loop, path: str, where: tuple[float, float], whole: bool) -> str:
    """One loop: its tooltip, its dashed path, its label at ``where``."""
    names = [loop.name, loop.first, loop.second]
    name, first, second = (text(n if whole else shown(n)) for n in names)
    tip = f"loop closed by {text(shown(loop.kind))} '{name}': {first} to {second}"
    return (
        f'<g class="loop{" changed" if loop.changed else ""}"><title>{tip}</title>'
        f'<path d="{path}" stroke="{COLOUR}" stroke-width="2.5" stroke-dasharray="7 4" '
        'fill="none"/>'
        f'<text x="{where[0]:.1f}" y="{where[1]:.1f}" class="loop-label" fill="{COLOUR}">'
        f"{text(shown(loop.name))}</text></g>"
    )


def across(loops: Sequence[Loop], at: At, row: float, whole: bool) -> tuple[list[str], float]:
    """Left to right: each loop an arc bowing below its links' rows.

    Returns the drawn loops and the lowest point they reach (to size the picture).
    """
    drawn, lowest = [], 0.0
    for k, loop in enumerate(loops):
        (x0, y0), (x1, y1) = at(loop.first), at(loop.second)
        bottom = max(y0, y1) + row * (1.2 + 0.8 * (k % 6))
        path = f"M{x0:.1f},{y0:.1f} C{x0:.1f},{bottom:.1f} {x1:.1f},{bottom:.1f} {x1:.1f},{y1:.1f}"
        label_y = 0.125 * (y0 + y1) + 0.75 * bottom + 14
        drawn.append(_edge(loop, path, ((x0 + x1) / 2 + 4, label_y), whole))
        lowest = max(lowest, label_y + 4)
    return drawn, lowest


def beside(
    loops: Sequence[Loop], at: At, right: float, whole: bool, width: Callable[[str], float]
) -> tuple[list[str], float]:
    """An outline: each loop runs under its links' labels to a lane right of every label.

    The lanes lie side by side, `LANE` pixels apart, and each loop's label right of the
    last lane, level with the loop's upper run. Returns the drawn loops and the rightmost
    point they reach (to size the picture); ``width`` bounds a label's width in pixels.
    """
    drawn, rightmost = [], right
    labels_at = right + LANE * (len(loops) + 1) + 4
    for k, loop in enumerate(loops):
        (x0, y0), (x1, y1) = at(loop.first), at(loop.second)
        lane = right + LANE * (k + 1)
        path = (
            f"M{x0:.1f},{y0:.1f} L{x0 + 6:.1f},{y0 + 9:.1f} H{lane:.1f} V{y1 + 9:.1f} "
            f"H{x1 + 6:.1f} L{x1:.1f},{y1:.1f}"
        )
        drawn.append(_edge(loop, path, (labels_at, min(y0, y1) + 13), whole))
        rightmost = max(rightmost, labels_at + width(shown(loop.name)))
    return drawn, rightmost
