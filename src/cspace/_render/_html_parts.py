"""The page's large parts, made here as HTML text: joint cards and coordinate strips.

A page has a card per joint and a cell per coordinate of each convention: up to 5,001
cards and 42,000 cells a side in a diff of saved reports. Made in the template, each
would be a dozen objects; here each is one string, escaped as the template escapes
(``markupsafe``), and the whole part reaches the page through `Pieces` without
a copy. The template keeps what little is around them.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from typing import Any

from cspace._render.drawing import SPACES, name_key, picture, shown, space_class
from cspace._safetext import printable

CARD_MESSAGE_CHARS = 200
"""Longest finding shown in a joint's card (cut in the middle, like the text report's
600): a report may hold 10,000 findings of 600 characters, each ``&`` five bytes of
HTML. The page's list of findings (and the JSON report) has them whole."""


def _strips() -> dict[str, str]:
    """The conventions drawn as strips of cells (those reports carry), and their titles."""
    from cspace._tools import TOOLS

    return {tool.slots[0]: tool.label() for tool in TOOLS.values() if tool.slots}


class Pieces:
    """The page's large parts (trees, cards, strips), joined in after Jinja's pass.

    Jinja copies each value it writes (a large one twice) and holds every copy until it
    joins them, so a page cost about 3.5 times its size at its peak. Here each large
    part reaches Jinja as a short token, replaced by the part when the page is joined:
    once, without a copy. The token is random, so no text of a file can stand for one.
    """

    def __init__(self) -> None:
        """No parts yet."""
        self.token = f"\x00{os.urandom(8).hex()}\x00"
        self.parts: list[str] = []

    def put(self, html: str) -> Any:
        """A stand-in for ``html`` (HTML, already escaped), for the template."""
        from markupsafe import Markup

        self.parts.append(html)
        return Markup(f"{self.token}{len(self.parts) - 1}{self.token}")

    def join(self, rendered: str) -> str:
        """The page: ``rendered`` with each stand-in replaced by its part."""
        pieces = rendered.split(self.token)  # text, part number, text, ..., text
        return "".join(p if k % 2 == 0 else self.parts[int(p)] for k, p in enumerate(pieces))


def cards_html(
    joints: Sequence[Mapping[str, Any]],
    findings: Mapping[str, Sequence[Mapping[str, Any]]],
    marked: set[str],
) -> str:
    """Each moving joint's card, each fixed joint folded into its parent's card.

    A card holds the joint's name, kind and space, limits, picture, indices and findings,
    and a line of the fixed joints below it (down to the next moving joint), each with
    its findings: a fixed joint is a point of the C-space, and a humanoid has dozens
    (sensor frames, soles, tool flanges). Fixed joints above every moving one share a
    first card, "fixed to the base".

    Args:
        joints: The report's joints.
        findings: The findings (``severity``, ``code``, ``message``) by joint name.
        marked: Keys of joints drawn as changed (a diff).
    """
    folded = _folded(joints)
    out: list[str] = []
    if folded.get(None):
        out.append(
            '\n<div class="card base" style="--c: #bbbbbb">\n<h3>fixed to the base</h3>\n'
            f"{_chips(folded[None], findings, marked)}\n</div>"
        )
    for index, joint in enumerate(joints):
        if _is_fixed(joint):
            continue
        out.append(_card(joint, findings, marked, _chips(folded.get(index, []), findings, marked)))
    return "".join(out)


def _is_fixed(joint: Mapping[str, Any]) -> bool:
    return bool(joint["kind"] == "fixed" and not joint.get("mimic"))


def _folded(joints: Sequence[Mapping[str, Any]]) -> dict[int | None, list[Mapping[str, Any]]]:
    """The fixed joints each moving joint's card holds (by its index; None: the base).

    A fixed joint goes to the nearest moving joint above it. Each link is climbed from
    once (the answers are kept), so this is linear in the joints, and a link reached
    again (which a checked report never has) ends the climb.
    """
    into: dict[str, int] = {}  # a link -> the last joint that ends at it (MuJoCo's order)
    for index, joint in enumerate(joints):
        into[str(joint["child_link"])] = index
    host: dict[str, int | None] = {}  # a link -> the moving joint above it (None: none)

    def above(link: str) -> int | None:
        path: dict[str, None] = {}  # the links climbed, in order
        found: int | None = None
        while link not in host:
            index = into.get(link)
            if index is None or link in path:
                break
            path[link] = None
            if not _is_fixed(joints[index]):
                found = index
                break
            link = str(joints[index]["parent_link"])
        else:
            found = host[link]
        for visited in path:
            host[visited] = found
        return found

    folded: dict[int | None, list[Mapping[str, Any]]] = {}
    for joint in joints:
        if _is_fixed(joint):
            folded.setdefault(above(str(joint["parent_link"])), []).append(joint)
    return folded


def _card(
    joint: Mapping[str, Any],
    findings: Mapping[str, Sequence[Mapping[str, Any]]],
    marked: set[str],
    chips: str,
) -> str:
    """One moving joint's card, with the chips of the fixed joints folded into it."""
    from markupsafe import escape

    key = name_key(joint["name"])
    title = escape(printable(str(joint["name"]), limit=None))  # whole, should the card cut it
    changed = " changed" if key in marked else ""
    q, qpos = joint.get("q_index"), joint.get("qposadr")
    where = ""
    if q is not None:
        at = f" · MuJoCo qpos[{escape(str(qpos))}]" if qpos is not None else ""
        where = f'<div class="kind">q[{escape(_range(q, joint["nq"]))}]{at}</div>'
    elif qpos is not None:  # an MJCF mimic joint: its qpos entry, set from its leader
        where = f'<div class="kind">MuJoCo qpos[{escape(str(qpos))}], from its leader</div>'
    return (
        f'\n<div class="card{changed}" data-joint="{escape(key)}" '
        f'style="--c: {SPACES[space_class(joint)][0]}">\n'
        f'<h3 title="{title}">{breakable(joint["name"])}</h3>\n'
        f'<div class="kind">{escape(joint["kind"])} · {escape(joint["manifold"])}'
        f"{_limits(joint.get('limits'))}</div>\n{picture(joint)}\n{where}\n"
        f"{_notes(findings.get(str(joint['name']), ()))}\n{chips}</div>"
    )


def _chips(
    fixed: Sequence[Mapping[str, Any]],
    findings: Mapping[str, Sequence[Mapping[str, Any]]],
    marked: set[str],
) -> str:
    """The fixed joints of a card: a line of their names, then their findings.

    Each name hovers as its joint does elsewhere; each finding starts with its joint's name.
    """
    from markupsafe import escape

    if not fixed:
        return ""
    chips = []
    for joint in fixed:
        key = name_key(joint["name"])
        title = escape(printable(str(joint["name"]), limit=None))
        changed = " changed" if key in marked else ""
        chips.append(
            f'<span class="chip{changed}" data-joint="{escape(key)}" title="{title}">'
            f"{breakable(joint['name'])}</span>"
        )
    notes = "".join(
        _notes(findings.get(str(joint["name"]), ()), f"{shown(joint['name'])}: ") for joint in fixed
    )
    count = f"{len(fixed)} fixed joint{'s' if len(fixed) > 1 else ''}"
    return f'<div class="fixed"><span class="kind">{count}:</span> {" ".join(chips)}{notes}</div>\n'


def _notes(said: Sequence[Mapping[str, Any]], about: str = "") -> str:
    """Findings in a card, each cut to `CARD_MESSAGE_CHARS` characters."""
    from markupsafe import escape

    return "".join(
        f'<div class="finding {escape(f["severity"])}">{escape(about)}{escape(f["code"])}: '
        f"{escape(printable(f['message'], limit=CARD_MESSAGE_CHARS))}</div>"
        for f in said
    )


def breakable(name: object) -> str:
    """A name as drawn (`shown`), HTML-escaped, with a break allowed between its words.

    After each ``_``, ``-``, ``.``, ``/`` and ``:``, and before a capital that follows a
    lower-case letter: a long name wraps between its words, never inside one.
    """
    from markupsafe import escape

    return _BREAKS.sub("<wbr>", str(escape(shown(name))))


_BREAKS = re.compile(r"(?<=[_\-./:])|(?<=[a-z])(?=[A-Z])")
"""Where a name may wrap: after a separator, and between a lower-case letter and a capital
(``LeftShoulderPitch``). The text is HTML-escaped, whose entities hold neither."""


def strips_html(joints: Sequence[Mapping[str, Any]]) -> list[tuple[str, str]]:
    """One strip of labelled cells per convention the report knows: its title and HTML."""
    from markupsafe import escape

    strips = []
    for convention, title in _strips().items():
        cells: list[tuple[int, str]] = []
        for joint in joints:
            slot = joint.get("slots", {}).get(convention)
            if not slot or slot["index"] is None:  # a saved report may hold a null index
                continue
            head = (
                f'<div class="slot" data-joint="{escape(name_key(joint["name"]))}" '
                f'style="--c: {SPACES[space_class(joint)][0]}"><b>'
            )
            for k, name in enumerate(slot["names"]):
                index = slot["index"] + k
                cells.append((index, f"{head}{index}</b>{escape(shown(name))}</div>"))
        if cells:
            cells.sort(key=lambda cell: cell[0])
            strips.append((title, "".join(cell for _, cell in cells)))
    return strips


def _limits(limits: Mapping[str, Any] | None) -> str:
    """`` · [-1, 1] rad``, or nothing for a joint without limits."""
    from markupsafe import escape

    if not limits:
        return ""
    pairs = [
        f"[{_number(lo)}, {_number(hi)}]"
        for lo, hi in zip(limits["lower"], limits["upper"], strict=True)
    ]
    return f" · {escape(' '.join(pairs) + ' ' + str(limits['unit']))}"


def _range(first: int, count: int) -> str:
    return str(first) if count == 1 else f"{first}..{first + count - 1}"


def _number(x: float | None) -> str:
    return "None" if x is None else f"{x:.6g}"
