"""What changed in a mechanism's closed chains between two reports (`diff_reports`).

A pull request that breaks a loop must not pass: a change of the loops' count, the
mobility, whether the mechanism assembles, or whether its actuated joints are a chart of
it is a ``mechanism`` change (a tree on one
side, a mechanism on the other, too), and each closing constraint (a cut) added,
removed, or changed (its kind, the two links it holds, its equations) is a change of
its own; a cut renamed is not. A cut's line, the samples, ranks, residuals and
singularities found are not either: they move with the file's layout and with the
search, not with the mechanism.
"""

from __future__ import annotations

from collections.abc import Callable

from cspace._reports._changes import Change
from cspace._reports.closure import Closure, Cut


def _mechanism(closure: Closure | None) -> str:
    """What a diff says of a side's mechanism: ``1 loop, mobility 1 (Grübler 0)``."""
    if closure is None:
        return "no loops"
    said = closure.summary.removeprefix("closed chains: ")
    if closure.chart is None:
        return said
    actuated = ", ".join(closure.actuated)
    return f"{said}; actuated {actuated}: {'a chart' if closure.chart else 'no chart'}"


def cut_text(cut: Cut) -> str:
    """A cut in a diff's words: ``connect 'pin': rocker to world (3 equations)``."""
    first, second = cut.links
    return f"{cut.kind} '{cut.name}': {first} to {second} ({cut.rows} equations)"


def _what(cut: Cut) -> tuple[str, frozenset[str], int]:
    """What a cut holds, whatever its name: its kind, its two links, its equations."""
    return (cut.kind, frozenset(cut.links), cut.rows)


def _paired(
    before: list[Cut], after: list[Cut], same: Callable[[Cut], object]
) -> list[tuple[Cut, Cut]]:
    """Cuts of the two sides that are ``same`` paired (in order), taken out of the lists."""
    waiting: dict[object, list[Cut]] = {}
    for cut in reversed(before):  # each list last to first: pop() takes the first
        waiting.setdefault(same(cut), []).append(cut)
    pairs, left = [], []
    for cut in after:
        match = waiting.get(same(cut))
        if match:
            pairs.append((match.pop(), cut))
        else:
            left.append(cut)
    taken = {id(old) for old, _ in pairs}
    before[:] = [cut for cut in before if id(cut) not in taken]
    after[:] = left
    return pairs


def closure_changes(old: Closure | None, new: Closure | None) -> dict[str, list[Change]]:
    """The changes of kind ``mechanism``, ``cut-added``, ``cut-removed``, ``cut-changed``.

    Cuts are paired by name and what they hold, then by what they hold alone (a cut
    renamed, or one the file leaves unnamed, whose made-up name follows its index, holds
    the same links: no change), then by name alone (a change of what it holds).
    """
    out: dict[str, list[Change]] = {
        "mechanism": [],
        "cut-added": [],
        "cut-removed": [],
        "cut-changed": [],
    }
    if old is None and new is None:
        return out

    def key(c: Closure | None) -> tuple[int, int | None, bool | None, bool | None] | None:
        return None if c is None else (c.loops, c.mobility, c.assembled, c.chart)

    if key(old) != key(new):
        out["mechanism"].append(Change("mechanism", None, _mechanism(old), _mechanism(new)))
    before = list(old.cuts if old is not None else ())
    after = list(new.cuts if new is not None else ())
    _paired(before, after, lambda c: (c.name, _what(c)))
    _paired(before, after, _what)
    for was, cut in _paired(before, after, lambda c: c.name):
        out["cut-changed"].append(Change("cut-changed", None, cut_text(was), cut_text(cut)))
    out["cut-removed"] = [Change("cut-removed", None, cut_text(c), "-") for c in before]
    out["cut-added"] = [Change("cut-added", None, "-", cut_text(c)) for c in after]
    return out
