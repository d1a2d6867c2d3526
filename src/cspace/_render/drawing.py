"""Pictures of a joint's space, as SVG text: limit dials, bars, balls; and names as drawn.

Everything here works from the report's JSON document (`Report.to_dict`), so a
saved report draws as well as a fresh one (the tree is `tree`). Names
from the file are made printable (`printable`), shortened where
drawn (`shown`) and XML-escaped before they reach the SVG. Angles
are in rad, drawn counter-clockwise from the right (the usual mathematical sense), with
y pointing down on the page.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Mapping
from html import escape
from typing import Any

from cspace._safetext import printable

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
    """The class of a joint's space, a key of `SPACES`, from its JSON object."""
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


SHOWN_CHARS = 32
"""Longest name drawn whole (real names have a few dozen characters at most); a longer
one is drawn as its start, ``…`` and its end. Names have up to 256 characters, and
escaped (``&amp;``, ``\\x1b``) up to ten times that: drawn whole in every place, 256
``&`` made a diff page of two 15 MB reports 240 MB (1 GiB of memory)."""

KEY_CHARS = SHOWN_CHARS
"""Longest name that is its own key in the page (``data-joint``, on each of a joint's
coordinate cells too); a longer one's key is its first `_KEY_HEAD` characters and
a digest of the whole."""

_KEY_HEAD = 12


def shown(value: object) -> str:
    """A name as drawn: printable, at most `SHOWN_CHARS` characters (start…end)."""
    plain = printable(str(value), limit=None)
    if len(plain) <= SHOWN_CHARS:
        return plain
    head = SHOWN_CHARS * 2 // 3
    return f"{plain[:head]}…{plain[len(plain) - (SHOWN_CHARS - head - 1) :]}"


def name_key(value: object) -> str:
    """A joint's or link's key in the page (``data-joint``), short and distinct.

    Its name, or for a longer name than `KEY_CHARS` or one with a character that
    prints escaped its printable start and a digest of the whole
    (``left_forearm…#3f9a0c1e22b4``): two names never share a key (a control character
    and its escape, typed out, print alike), so no card collects another joint's findings.
    """
    plain = printable(str(value), limit=None)
    if len(plain) <= KEY_CHARS and plain == str(value):
        return plain
    digest = hashlib.blake2b(str(value).encode("utf-8", "surrogatepass"), digest_size=6)
    return f"{plain[:_KEY_HEAD]}…#{digest.hexdigest()}"


def whole_if_shortened(value: object) -> str | None:
    """The whole printable name, for a tooltip, when `shown` shortens it; else None."""
    plain = printable(str(value), limit=None)
    return plain if len(plain) > SHOWN_CHARS else None


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
