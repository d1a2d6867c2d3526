"""Joint renames for ``cspace diff``: ``--map`` pairs, prefix rules, and a hint.

``--map OLD=NEW`` names one joint; ``--map 'OLD*=NEW*'`` (one ``*`` on each side) maps
every old joint whose name fits ``OLD*`` to the new joint of the same name with the
other prefix and suffix, where the new side has it. When the joints a diff finds added
and removed differ only by a prefix (and suffix), `prefix_hint` says which rule would
match them.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence


def expand_renames(
    pairs: Sequence[tuple[str, str]], old: Iterable[str], new: Iterable[str]
) -> dict[str, str]:
    """Old joint name -> new joint name, prefix rules expanded (exact pairs win).

    Args:
        pairs: ``(OLD, NEW)`` as given; a pair with ``*`` on both sides is a rule.
        old: The old side's joint names.
        new: The new side's joint names.

    Raises:
        ValueError: A rule with ``*`` on one side only, or more than one ``*``.
    """
    targets = set(new)
    renames: dict[str, str] = {}
    for before, after in pairs:
        if "*" not in before and "*" not in after:
            continue
        if before.count("*") != 1 or after.count("*") != 1:
            raise ValueError(f"--map {before}={after}: a rule has one * on each side")
        head, tail = before.split("*")
        new_head, new_tail = after.split("*")
        for name in old:
            if name.startswith(head) and name.endswith(tail) and len(name) >= len(head + tail):
                stem = name[len(head) : len(name) - len(tail)]
                if new_head + stem + new_tail in targets:
                    renames[name] = new_head + stem + new_tail
    renames.update({b: a for b, a in pairs if "*" not in b and "*" not in a})
    return renames


def prefix_hint(removed: Sequence[str], added: Sequence[str]) -> str | None:
    """The ``--map`` rule under which every removed joint is an added one, or None.

    Tried from the first removed joint against each added one: what they share at the
    end is the stem; the rest is the rule, which must then match all of them.
    """
    if not removed or len(removed) != len(added):
        return None
    first = removed[0]
    for other in added:
        stem = _common_end(first, other)
        if not stem or first == other:
            continue
        head, new_head = first[: -len(stem)], other[: -len(stem)]
        mapped = {new_head + name[len(head) :] for name in removed if name.startswith(head)}
        if len(mapped) == len(removed) and mapped == set(added):
            return f"{head}*={new_head}*"
    return None


def _common_end(a: str, b: str) -> str:
    """The longest string both end with."""
    n = 0
    while n < min(len(a), len(b)) and a[-1 - n] == b[-1 - n]:
        n += 1
    return a[len(a) - n :]
