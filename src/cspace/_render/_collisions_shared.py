"""What the pages of ``cspace collisions`` share: the pairs to look at first, a file's word.

A pair goes against its file when what the file says and the samples disagree: the file
skips the pair (an SRDF's ``<disable_collisions>``, MuJoCo's or PhysX's filters) though
it collides in some samples and is neither adjacent nor always in collision, nor in
collision at the default configuration unless the SRDF gives it another reason than
``Default`` (`disabled_but_reachable`), nor skipped by MuJoCo's parent-child filter, a
filter by design; or checks it though it is always in collision (or, an SRDF, at the
default configuration). Those are the pairs the findings are about; with the pairs that collide
sometimes or always (the ones a planner must check), they are the pairs a reader looks
at first. The rest (never in collision, adjacent, in collision at the default
configuration, each as the file says) are the ones MoveIt's setup assistant disables.
"""

from collections.abc import Sequence

from cspace._render._collisions_text import ORDER
from cspace._reports.collisions import (
    ALWAYS_SHARE,
    MUJOCO_PARENT,
    PairReport,
    disabled_but_reachable,
)

FILES = {
    "srdf": "the SRDF",
    "mjcf": "MuJoCo's filters",
    "usd": "PhysX's filters",
    "none": "no file",
}
"""Who says which pairs are checked, by `CollisionReport.matrix`."""


def against_file(pair: PairReport, matrix: str) -> bool:
    """Whether the file's word on the pair goes against its samples (see the module).

    Args:
        pair: The pair.
        matrix: Which file says which pairs are checked (`CollisionReport.matrix`):
            ``none`` says nothing a pair could go against.
    """
    share = pair.collisions
    if pair.rule is None or share is None or matrix not in ("srdf", "mjcf", "usd"):
        return False
    if pair.rule.checked:
        always = share.samples > 0 and share.hits >= ALWAYS_SHARE * share.samples
        return always or (matrix == "srdf" and pair.kind == "default")
    if matrix == "srdf":
        return disabled_but_reachable(pair)
    by_design = matrix == "mjcf" and pair.rule.reason == MUJOCO_PARENT  # no finding either
    return pair.kind == "sometimes" and not by_design


def first_look(pair: PairReport, matrix: str) -> bool:
    """Whether a reader looks at the pair first: it collides sometimes or always, or disagrees.

    A pair disagrees with its file as `against_file` says.
    """
    return pair.kind in ("sometimes", "always") or against_file(pair, matrix)


def _hits(pair: PairReport) -> int:
    return -1 if pair.collisions is None else pair.collisions.hits


def split(pairs: Sequence[PairReport], matrix: str) -> tuple[list[PairReport], list[PairReport]]:
    """The pairs to look at first and the others, each in the order they are listed.

    ``matrix`` is the report's (`against_file`).

    First: those against their file, then by class (`ORDER`) and share, the largest
    first. The others: by class, then by name.
    """
    first = sorted(
        (p for p in pairs if first_look(p, matrix)),
        key=lambda p: (
            not against_file(p, matrix),
            ORDER.index(p.kind),
            -_hits(p),
            p.link1,
            p.link2,
        ),
    )
    rest = sorted(
        (p for p in pairs if not first_look(p, matrix)),
        key=lambda p: (ORDER.index(p.kind), p.link1, p.link2),
    )
    return first, rest


def checked_word(pair: PairReport, matrix: str) -> str:
    """What the file does to the pair: ``checked``, ``disabled`` (SRDF), ``filtered``.

    ``skipped`` for an adjacent pair no file names; "" when no file says.
    """
    if pair.rule is None:
        return "skipped" if not pair.checked else ""
    if pair.rule.checked:
        return "checked"
    return {"srdf": "disabled", "mjcf": "filtered", "usd": "filtered"}.get(matrix, "skipped")


def where(pair: PairReport) -> str | None:
    """Where the file says it: ``ur5.srdf:15`` (the file's last part), ``line 15``, or None."""
    rule = pair.rule
    if rule is None or rule.line is None:
        return None
    if rule.file is None:
        return f"line {rule.line}"
    return f"{rule.file.replace(chr(92), '/').rsplit('/', 1)[-1]}:{rule.line}"
