"""What changed in a mechanism's closed chains between two reports (`diff_reports`).

A pull request that breaks a loop must not pass: a change of the loops' count, the
mobility, whether the mechanism assembles, or whether its actuated joints are a chart of
it is a ``mechanism`` change (a tree on one
side, a mechanism on the other, too), and each closing constraint (a cut) added,
removed, or changed (its kind, the two links it holds, its equations, where it holds
them: its frames and free axis) is a change of its own; a cut renamed is not. A cut's
line, the samples, ranks, residuals and singularities found are not either: they move
with the file's layout and with the search, not with the mechanism.
"""

from __future__ import annotations

import math
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


def _where(cut: Cut) -> str:
    """Where a cut holds its links: ``at (x, y, z) in A and (x, y, z) in B``.

    With the frames' rotations and the free axis when they count.
    """
    a, b = cut.frames[:7], cut.frames[7:]
    first, second = cut.links

    def place(frame: tuple[float, ...], link: str) -> str:
        turned = "" if cut.free == "rotation" else f" turned {_numbers(frame[3:])}"
        return f"{_numbers(frame[:3])}{turned} in {link}"

    axis = f", axis {_numbers(cut.axis)}" if cut.free in ("revolute", "prismatic") else ""
    return f"at {place(a, first)} and {place(b, second)}{axis}"


def _numbers(values: tuple[float, ...]) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in values) + ")"


def _moved(was: Cut, cut: Cut, tolerance: float) -> bool:
    """Whether a cut holds its links elsewhere.

    Each link's frame is compared with the same link's frame on the other side (a cut
    written end for end, its links and frames both exchanged, is the same cut): its
    origin moved by more than ``tolerance`` (m), or, when the rotation counts, turned by
    more than ``tolerance`` (rad); and the free axis, which is the same in both frames
    when the loop is closed.
    """
    if was.free != cut.free or len(was.frames) != len(cut.frames):
        return True
    before = {was.links[0]: was.frames[:7], was.links[1]: was.frames[7:]}
    after = {cut.links[0]: cut.frames[:7], cut.links[1]: cut.frames[7:]}
    if before.keys() != after.keys():
        return True
    for link, frame in after.items():
        old = before[link]
        if any(abs(old[i] - frame[i]) > tolerance for i in range(3)):
            return True
        if cut.free != "rotation" and _angle(old[3:], frame[3:]) > tolerance:
            return True
    if cut.free not in ("revolute", "prismatic"):
        return False
    return any(abs(p - q) > tolerance for p, q in zip(was.axis, cut.axis, strict=True))


def _angle(a: tuple[float, ...], b: tuple[float, ...]) -> float:
    """The angle (rad) between the rotations of two quaternions, whatever their signs.

    ``4 atan2(|a - b|, |a + b|)`` of the two normalised, ``b`` turned to ``a``'s side:
    accurate near 0, where the tolerance is (the inner product of a unit quaternion with
    itself rounds to below 1, and its ``acos`` is then some 1e-8 rad). Quaternions that
    cannot be normalised (zero, not finite) are infinitely apart unless written alike.
    """
    na, nb = math.sqrt(sum(x * x for x in a)), math.sqrt(sum(x * x for x in b))
    if not (0.0 < na < math.inf and 0.0 < nb < math.inf):
        return 0.0 if a == b else math.inf
    ua, ub = [x / na for x in a], [x / nb for x in b]
    if sum(x * y for x, y in zip(ua, ub, strict=True)) < 0.0:
        ub = [-x for x in ub]
    apart = math.sqrt(sum((x - y) ** 2 for x, y in zip(ua, ub, strict=True)))
    along = math.sqrt(sum((x + y) ** 2 for x, y in zip(ua, ub, strict=True)))
    return 4.0 * math.atan2(apart, along)


def closure_changes(
    old: Closure | None, new: Closure | None, tolerance: float = 1e-6
) -> dict[str, list[Change]]:
    """The changes of kind ``mechanism``, ``cut-added``, ``cut-removed``, ``cut-changed``.

    Cuts are paired by name and what they hold, then by what they hold alone (a cut
    renamed, or one the file leaves unnamed, whose made-up name follows its index, holds
    the same links: no change), then by name alone (a change of what it holds). A pair
    whose frames moved by more than ``tolerance`` (m, rad) is a change too: the same links
    held elsewhere are another mechanism.
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
    same = _paired(before, after, lambda c: (c.name, _what(c)))
    same += _paired(before, after, _what)
    for was, cut in same:
        if _moved(was, cut, tolerance):
            said = (f"{cut_text(was)} {_where(was)}", f"{cut_text(cut)} {_where(cut)}")
            out["cut-changed"].append(Change("cut-changed", None, *said))
    for was, cut in _paired(before, after, lambda c: c.name):
        out["cut-changed"].append(Change("cut-changed", None, cut_text(was), cut_text(cut)))
    out["cut-removed"] = [Change("cut-removed", None, cut_text(c), "-") for c in before]
    out["cut-added"] = [Change("cut-added", None, "-", cut_text(c)) for c in after]
    return out
