"""An SRDF's collision elements as MoveIt applies them, and the block cspace writes.

MoveIt builds its allowed collision matrix from the SRDF (``AllowedCollisionMatrix(const
srdf::Model&)``): each ``<disable_default_collisions link>`` makes the link's default
entry *allowed*, then each ``<enable_collisions>`` sets its pair's entry to checked,
and *finally* each ``<disable_collisions>`` sets its pair's entry to allowed. A pair's
own entry wins over the links' defaults. srdfdom drops a pair naming a link the robot
lacks (with a warning): `srdf_rules` makes that a `collision-unknown-link` finding.

`srdf_text` writes the matrix cspace suggests as an SRDF document MoveIt reads: a
``<disable_collisions>`` element for each pair MoveIt's setup assistant would disable,
with its reason (``Adjacent``, ``Default``, ``Always``, ``Never``), pairs sorted.
"""

from collections.abc import Iterable, Sequence

from cspace._findings import Diagnostic, finding
from cspace._formats.srdf._collisions import unknown_links
from cspace._formats.srdf.reader import Srdf
from cspace._model._collision_pairs import LinkPair, link_pair
from cspace._reports.collisions import MOVEIT_REASONS, FileRule, PairReport
from cspace._safetext import printable

MAX_UNKNOWN = 200
"""Most `collision-unknown-link` findings of one SRDF."""


def srdf_rules(
    srdf: Srdf, pairs: Sequence[LinkPair], links: Iterable[str]
) -> "tuple[dict[LinkPair, FileRule], list[Diagnostic]]":
    """What the SRDF's matrix says of each of ``pairs``, and its elements naming unknown links.

    Args:
        srdf: The `Srdf` read.
        pairs: The link pairs (sorted names).
        links: Every link of the robot.
    """
    path = srdf.path
    known = set(links)
    written = unknown_links(srdf.collision_pairs, known)
    defaults = {d.name: d for d in srdf.no_default}
    own: dict[LinkPair, FileRule] = {}
    for enabled in (p for p in written if not p.disable and not p.unknown):
        own[link_pair(enabled.link1, enabled.link2)] = FileRule(
            True, "enable_collisions", enabled.line, path
        )
    for disabled in (p for p in written if p.disable and not p.unknown):
        own[link_pair(disabled.link1, disabled.link2)] = FileRule(
            False, disabled.reason if disabled.reason is not None else "User", disabled.line, path
        )
    rules: dict[LinkPair, FileRule] = {}
    for pair in pairs:
        rule = own.get(pair)
        if rule is None:
            default = defaults.get(pair[0]) or defaults.get(pair[1])
            rule = (
                FileRule(True, None, None, path)
                if default is None
                else FileRule(False, "disable_default_collisions", default.line, path)
            )
        rules[pair] = rule
    findings = [
        finding(
            "collision-unknown-link",
            None,
            f"<{'disable' if p.disable else 'enable'}_collisions> names "
            + " and ".join(f"'{name}'" for name in p.unknown)
            + ", which the robot lacks: MoveIt drops the pair",
            p.line,
            path,
        )
        for p in written
        if p.unknown
    ]
    findings += [  # srdfdom drops these too (loadCollisionDefaults), with a warning
        finding(
            "collision-unknown-link",
            None,
            f"<disable_default_collisions> names '{d.name}', which the robot lacks: MoveIt "
            "drops it",
            d.line,
            path,
        )
        for d in srdf.no_default
        if d.name not in known
    ]
    findings.sort(key=lambda d: (d.line is None, d.line or 0))
    return rules, findings[:MAX_UNKNOWN]


def srdf_text(robot: str, pairs: Iterable[PairReport], samples: int, seed: int) -> str:
    """An SRDF document disabling each pair MoveIt's setup assistant would disable.

    Raises:
        ValueError: A name that XML 1.0 cannot hold (a control character).
    """
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        f"<!-- cspace collisions: {samples} samples, seed {seed}; the pairs MoveIt's setup "
        "assistant disables (Adjacent, Default, Always, Never) -->",
        f"<robot name={_attribute(robot)}>",
    ]
    for pair in sorted(pairs, key=lambda p: (p.link1, p.link2)):
        reason = MOVEIT_REASONS.get(pair.kind)
        if reason is not None:
            lines.append(
                f"  <disable_collisions link1={_attribute(pair.link1)} "
                f'link2={_attribute(pair.link2)} reason="{reason}"/>'
            )
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def _attribute(value: str) -> str:
    """``value`` as a double-quoted XML attribute."""
    if any((ord(c) < 0x20 and c not in "\t\n\r") or 0xFFFE <= ord(c) <= 0xFFFF for c in value):
        raise ValueError(f"the name '{printable(value)}' holds a character XML cannot hold")
    from xml.sax.saxutils import quoteattr

    return quoteattr(value, {"\n": "&#10;", "\r": "&#13;", "\t": "&#9;"})
