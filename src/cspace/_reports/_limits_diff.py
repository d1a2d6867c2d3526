"""What changed in the limits MoveIt plans with between two reports (`diff_reports`).

A side read with a joint_limits.yaml (``--limits``, ``--old-limits``, ``--new-limits``)
has the report's ``limits_file``: the position limits a ``limits`` change shows are then
said with where each bound came from, and the velocity, acceleration, jerk and effort
limits are compared too, each change a ``limits`` change of its joint with its value and
origin on each side (``velocity 2.175 (panda.urdf:46)`` against ``velocity 3
(joint_limits.yaml:13)``), and so are the default scaling factors (a ``limits`` change
of no joint). Where neither side has one, nothing is added: the robot file's rate limits
are no part of the report.
"""

from __future__ import annotations

from collections.abc import Mapping

from cspace._reports._changes import Change, within
from cspace._reports.limits import Bound, JointLimitsView
from cspace._reports.report import Report

KIND = "limits"
"""The kind of change this module gives."""

RATES = ("velocity", "acceleration", "jerk", "effort")

SCALING = (
    ("velocity_scaling", "default_velocity_scaling_factor"),
    ("acceleration_scaling", "default_acceleration_scaling_factor"),
)
"""The report's default scaling factors, each with the YAML's key."""


def _origin(bound: Bound, report: Report) -> str:
    """``panda.urdf:46`` or ``joint_limits.yaml:13``: the file's name, and the line."""
    summary = report.limits_file
    path = summary.file if bound.origin == "limits" and summary else report.source.path
    name = path.replace("\\", "/").rsplit("/", 1)[-1]
    return name if bound.line is None else f"{name}:{bound.line}"


def _said(name: str, bound: Bound | None, report: Report) -> str:
    if bound is None:
        return "-"
    value = "none" if bound.value is None else f"{bound.value:g}"
    return f"{name} {value} ({_origin(bound, report)})"


def _same(a: float | None, b: float | None, tolerance: float, rel: float) -> bool:
    """Whether two limits count as unchanged: both none, or `within` the tolerances."""
    if a is None or b is None:
        return a is None and b is None
    return within(a, b, tolerance, rel)


def limits_changes(
    old: Report,
    new: Report,
    matched: Mapping[str, str],
    changes: list[Change],
    tolerance: float,
    rel: float,
) -> list[Change]:
    """The ``limits`` changes with their origins, and the rate limits' changes.

    Args:
        old: The old report.
        new: The new report.
        matched: Each old joint's name on the new side.
        changes: The position limits' changes `diff_reports` found (by new name).
        tolerance: Limits closer than this count as unchanged.
        rel: So do limits whose difference is at most this fraction of the larger.
    """
    if old.limits_file is None and new.limits_file is None:
        return changes
    same = old.source.sha256 == new.source.sha256  # one robot file: its own limits known
    was = {matched.get(n, n): v for n, v in _views(old).items()}
    now = _views(new)
    if old.limits_file is None and same:
        was = {n: _own(v) for n, v in now.items()}
    elif new.limits_file is None and same:
        now = {n: _own(v) for n, v in was.items()}
    out = []
    for change in changes:
        name = change.joint or ""
        before, after = was.get(name), now.get(name)
        out.append(
            Change(
                KIND,
                change.joint,
                change.before + _positions(before, old),
                change.after + _positions(after, new),
            )
        )
    for joint in new.joints:
        before, after = was.get(joint.name), now.get(joint.name)
        if before is None and after is None:
            continue
        for rate in RATES:
            a = None if before is None else getattr(before, rate)
            b = None if after is None else getattr(after, rate)
            if a is not None and b is not None and _same(a.value, b.value, tolerance, rel):
                continue
            if a is None and b is None:
                continue
            out.append(
                Change(
                    KIND,
                    joint.name,
                    _said(rate, a, old),
                    _said(rate, b, new),
                )
            )
    out.extend(_scaling(old, new, tolerance, rel))
    return out


def _scaling(old: Report, new: Report, tolerance: float, rel: float) -> list[Change]:
    """The default scaling factors' changes: MoveIt scales every plan's speed by them."""
    out = []
    for field, key in SCALING:
        a = None if old.limits_file is None else getattr(old.limits_file, field)
        b = None if new.limits_file is None else getattr(new.limits_file, field)
        if _same(a, b, tolerance, rel):
            continue
        out.append(Change(KIND, None, _factor(key, a, old), _factor(key, b, new)))
    return out


def _factor(key: str, value: float | None, report: Report) -> str:
    if value is None or report.limits_file is None:
        return "-"
    name = report.limits_file.file.replace("\\", "/").rsplit("/", 1)[-1]
    return f"{key} {value:g} ({name})"


def _views(report: Report) -> dict[str, JointLimitsView]:
    return {} if report.limits_file is None else report.limits_file.by_joint()


def _own(view: JointLimitsView) -> JointLimitsView:
    """The robot file's own limits of a joint (those the YAML replaced put back)."""
    bounds = [getattr(view, k).robot_file() for k in ("lower", "upper", *RATES)]
    return JointLimitsView(view.joint, *bounds)


def _positions(view: JointLimitsView | None, report: Report) -> str:
    """`` (lower from joint_limits.yaml:10, upper ...)``: the bounds the YAML gave."""
    if view is None or report.limits_file is None:
        return ""
    said = [
        f"{side} from {_origin(bound, report)}"
        for side, bound in (("lower", view.lower), ("upper", view.upper))
        if bound.origin == "limits"
    ]
    return f" ({', '.join(said)})" if said else ""
