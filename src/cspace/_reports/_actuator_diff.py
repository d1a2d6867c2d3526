"""What changed in MuJoCo's ctrl vector between two MJCF reports (`diff_reports`).

A policy or a controller writes ctrl by position: an actuator moved, added or removed
shifts what every later entry drives, and an actuator that drives another joint, is of
another kind, or has another gear (any of its numbers MuJoCo reads: a site's six) or
ctrlrange puts the robot elsewhere for the same ctrl. Each is an ``actuators`` change
(the C-space is the same; the diff fails).
Actuators are paired by name (one without a name by its entry, never with a named
one, whatever its name); a side that is not an MJCF report has no ctrl and is not
compared. An actuator's line is not a change.
When only the new side lists actuators, they are not compared but noted
(``actuators-listed``): a report saved by an earlier version of cspace lists none, and a
baseline of it must not fail for that. When only the old side lists them, the new robot
has none: each is a change (removed), so a pull request that deletes every actuator
fails as one that deletes a few does.
"""

from __future__ import annotations

from collections.abc import Sequence

from cspace._actuators import Actuator
from cspace._reports._changes import Change, within

KIND = "actuators"
"""The kind of change this module gives."""

NOTE = "actuators-listed"
"""The kind of note: only one side lists actuators."""

_LISTED = 12
"""Most names an order change lists on each side."""


def _key(actuator: Actuator, index: int) -> tuple[str, str | int]:
    """How an actuator is paired: by name, or by entry when it has none.

    The actuator without a name at entry 3 and the one named ``#3`` are not paired.
    """
    return ("name", actuator.name) if actuator.name else ("entry", index)


def _label(key: tuple[str, str | int]) -> str:
    """``shoulder``, or ``#3`` for the actuator without a name at entry 3."""
    kind, value = key
    return str(value) if kind == "name" else f"#{value}"


def _drives(actuator: Actuator) -> str:
    """``position on joint 'elbow', gear 2, ctrlrange [-1, 1]``."""
    ranged = actuator.ctrlrange_text()
    ctrl = "no ctrlrange" if ranged is None else f"ctrlrange {ranged}"
    target = f"'{actuator.target}'" if actuator.target else "?"
    gear = actuator.gear_text()
    return f"{actuator.kind} on {actuator.transmission} {target}, gear {gear}, {ctrl}"


def _same(a: Actuator, b: Actuator, tolerance: float, rel: float) -> bool:
    """Whether two actuators drive the same thing alike (their lines aside)."""
    if (a.kind, a.transmission, a.target) != (b.kind, b.transmission, b.target):
        return False
    if not within(a.gear, b.gear, tolerance, rel) or len(a.gears) != len(b.gears):
        return False
    if not all(within(x, y, tolerance, rel) for x, y in zip(a.gears, b.gears, strict=True)):
        return False
    if (a.ctrlrange is None) != (b.ctrlrange is None):
        return False
    if a.ctrlrange is None or b.ctrlrange is None:
        return True
    return all(within(x, y, tolerance, rel) for x, y in zip(a.ctrlrange, b.ctrlrange, strict=True))


def _names(keys: Sequence[tuple[str, str | int]]) -> str:
    shown = ", ".join(_label(key) for key in keys[:_LISTED])
    return shown + (f", ... ({len(keys):,} in all)" if len(keys) > _LISTED else "")


def actuator_changes(
    old: Sequence[Actuator],
    new: Sequence[Actuator],
    formats: tuple[str, str],
    tolerance: float,
    rel_tolerance: float,
) -> list[Change]:
    """The ``actuators`` changes (and ``actuators-listed`` note) between two reports' actuators.

    See the module docstring.

    Args:
        old: The old report's actuators, in ctrl order.
        new: The new report's.
        formats: The two reports' formats: only two MJCF reports are compared.
        tolerance: Gears and ctrlranges closer than this are the same.
        rel_tolerance: So are those whose difference is at most this fraction of the
            larger magnitude.
    """
    if formats != ("mjcf", "mjcf"):
        return []
    if not old:
        return [Change(NOTE, None, "none listed", f"{len(new):,} actuators")] if new else []
    before = {_key(a, i): a for i, a in enumerate(old)}
    after = {_key(a, i): a for i, a in enumerate(new)}
    out: list[Change] = []
    for key, actuator in before.items():
        if key not in after:
            gone = f"{_label(key)}: {_drives(actuator)}"
            out.append(Change(KIND, actuator.target, gone, "-"))
    for key, actuator in after.items():
        was = before.get(key)
        if was is None:
            added = f"{_label(key)}: {_drives(actuator)}"
            out.append(Change(KIND, actuator.target, "-", added))
        elif not _same(was, actuator, tolerance, rel_tolerance):
            said = (f"{_label(key)}: {_drives(was)}", f"{_label(key)}: {_drives(actuator)}")
            out.append(Change(KIND, actuator.target, *said))
    kept_old = [k for k in before if k in after]
    kept_new = [k for k in after if k in before]
    if kept_old != kept_new:
        out.append(Change(KIND, None, f"ctrl {_names(kept_old)}", f"ctrl {_names(kept_new)}"))
    return out
