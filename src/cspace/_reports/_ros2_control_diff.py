"""What changed in a URDF's ``<ros2_control>`` bounds between two reports (`diff_reports`).

Controllers read a joint's position bounds and start from its initial value as the
``<ros2_control>`` elements give them, whatever the URDF's limits: a bound or an initial
value moved by more than the tolerance, given or dropped, is a ``ros2-control`` change
(the C-space is the same; the diff fails), each with the line it is written on; so is
the ``min`` or ``max`` of a velocity, effort, acceleration or jerk command interface,
which ros2_control applies too (the tighter of it and the URDF's). Joints
are paired as the diff pairs them (names, renames); a joint's interfaces are read from
every component that names it, the first of each name counting.
Only two URDF or xacro reports are compared (another format has no ``<ros2_control>``).
"""

from __future__ import annotations

from collections.abc import Mapping

from cspace._reports._changes import Change, within
from cspace._reports.report import Report
from cspace._ros2_control import ControlJoint, control_number

KIND = "ros2-control"
"""The kind of change this module gives."""

_URDF = ("urdf", "xacro")

Said = tuple[str | None, str | None, str | None, int | None]
"""A joint's position ``min``, ``max``, ``initial_value`` as written, and their line."""

RATES = ("velocity", "effort", "acceleration", "jerk")
"""The command interfaces other than position whose bounds ros2_control applies."""

Bounds = tuple[str | None, str | None, int | None]
"""An interface's ``min`` and ``max`` as applied (None when turned off), and its line."""


def _said(joint: ControlJoint) -> Said:
    command = joint.interface("command", "position")
    state = joint.interface("state", "position")
    low = high = initial = None
    line = joint.line
    if command is not None and command.limits_enabled and joint.limits_enabled:
        low, high = command.min, command.max
        line = command.line
    source = state if state is not None and state.initial_value is not None else command
    if source is not None:
        initial = source.initial_value
    return low, high, initial, line


def _joints(report: Report) -> dict[str, ControlJoint]:
    """Each joint's entries in every component as one, its interfaces in file order.

    ros2_control takes a joint's interfaces from every component that names it (one
    component's state interface, another's command interfaces); an entry's
    ``<limits enable="false"/>`` turns off its own interfaces' bounds only.
    """
    out: dict[str, ControlJoint] = {}
    for component in report.ros2_control:
        for joint in component.joints:
            own = joint.limits_enabled
            command = tuple(
                i._replace(limits_enabled=i.limits_enabled and own) for i in joint.command
            )
            first = out.get(joint.name)
            if first is None:
                out[joint.name] = joint._replace(command=command, limits_enabled=True)
            else:
                out[joint.name] = first._replace(
                    command=first.command + command, state=first.state + joint.state
                )
    return out


def _bounds(joint: ControlJoint | None, rate: str) -> Bounds | None:
    item = None if joint is None else joint.interface("command", rate)
    if joint is None or item is None:
        return None
    if not (joint.limits_enabled and item.limits_enabled):
        return None, None, item.line
    return item.min, item.max, item.line


def _rate_changes(
    name: str, was: ControlJoint | None, now: ControlJoint | None, tolerance: float, rel: float
) -> list[Change]:
    out = []
    for rate in RATES:
        a, b = _bounds(was, rate), _bounds(now, rate)
        unbounded = [x is None or x[:2] == (None, None) for x in (a, b)]
        if all(unbounded):
            continue
        if _moved(a, b, tolerance, rel):
            out.append(Change(KIND, name, _rate_text(rate, a), _rate_text(rate, b)))
    return out


def _moved(a: Bounds | None, b: Bounds | None, tolerance: float, rel: float) -> bool:
    if a is None or b is None:
        return True
    return not (_same(a[0], b[0], tolerance, rel) and _same(a[1], b[1], tolerance, rel))


def _rate_text(rate: str, bounds: Bounds | None) -> str:
    if bounds is None:
        return "-"
    low, high, line = bounds
    where = f" (line {line})" if line is not None else ""
    if low is None and high is None:
        return f"{rate}: none{where}"
    return f"{rate} [{low or '-'}, {high or '-'}]{where}"


def _same(a: str | None, b: str | None, tolerance: float, rel: float) -> bool:
    x, y = control_number(a), control_number(b)
    if x is None or y is None:
        return a == b
    return within(x, y, tolerance, rel)


def _text(said: Said | None) -> str:
    if said is None:
        return "-"
    low, high, initial, line = said
    parts = []
    if low is not None or high is not None:
        parts.append(f"position [{low or '-'}, {high or '-'}]")
    if initial is not None:
        parts.append(f"initial {initial}")
    where = f" (line {line})" if line is not None else ""
    return (", ".join(parts) or "no bounds") + where


def control_changes(
    old: Report, new: Report, matched: Mapping[str, str], tolerance: float, rel: float
) -> list[Change]:
    """The ``ros2-control`` changes between two reports (see the module's docstring).

    Args:
        old: The old report.
        new: The new report.
        matched: Old joint name -> new joint name, for the joints the diff paired.
        tolerance: Numbers closer than this are the same.
        rel: So are those whose difference is at most this fraction of the larger one.
    """
    if old.source.format not in _URDF or new.source.format not in _URDF:
        return []
    if not old.ros2_control and not new.ros2_control:
        return []
    before, after = _joints(old), _joints(new)
    changes: list[Change] = []
    names = [j.name for j in new.joints]
    back = {v: k for k, v in matched.items()}
    seen: set[str] = set()
    for name in [*names, *after, *(matched.get(n, n) for n in before)]:
        if name in seen:
            continue
        seen.add(name)
        old_joint, new_joint = before.get(back.get(name, name)), after.get(name)
        if old_joint is None and new_joint is None:
            continue
        was = None if old_joint is None else _said(old_joint)
        now = None if new_joint is None else _said(new_joint)
        if not _unchanged(was, now, tolerance, rel) and (
            (was is None) == (now is None) or _bounded(was) or _bounded(now)
        ):  # not a joint named without bounds or initial value, added or dropped
            changes.append(Change(KIND, name, _text(was), _text(now)))
        changes.extend(_rate_changes(name, old_joint, new_joint, tolerance, rel))
    return changes


def _unchanged(was: Said | None, now: Said | None, tolerance: float, rel: float) -> bool:
    if was is None or now is None:
        return False
    return all(_same(a, b, tolerance, rel) for a, b in zip(was[:3], now[:3], strict=True))


def _bounded(said: Said | None) -> bool:
    return said is not None and any(v is not None for v in said[:3])
