"""A report's robot as the parts of its configuration space (``ConfigurationSpace(...)``).

What `ConfigurationSpace.from_report` checks and builds: a report with
error-level findings has no well-defined space; the layout comes from the one joint
table (`build_layout`); a mimic joint follows a leader with
one coordinate; an MJCF robot keeps MuJoCo's qpos/qvel layout; the findings on Drake's
model of the file go to its Drake convention.
"""

from __future__ import annotations

from collections import Counter
from typing import TYPE_CHECKING, Any

from cspace._formats.table import by_name
from cspace.errors import ArgumentTypeError, RobotHasErrorsError, UnsupportedConfigurationError
from cspace.space._geometry.layout import build_layout
from cspace.space._geometry.rotations import UNIT_TOLERANCE

if TYPE_CHECKING:
    from cspace._reports.report import Report


def space_parts(report: Report) -> tuple[Any, ...]:
    """The arguments of ``ConfigurationSpace(...)`` for ``report``'s robot, in order.

    Raises:
        ArgumentTypeError: ``report`` is not a `Report`.
        RobotHasErrorsError: The report has error-level findings.
        UnsupportedConfigurationError: A joint has no canonical coordinates, or a mimic
            joint's leader has several.
    """
    from cspace._findings import BESIDE_CODES, DRAKE_CODES, Severity
    from cspace._reports.report import Report

    if not isinstance(report, Report):
        raise ArgumentTypeError(
            f"from_report takes a cspace.Report, got {type(report).__name__}",
            argument="report",
        )
    beside = BESIDE_CODES  # they leave the space as it is
    errors = [
        d for d in report.diagnostics if d.severity is Severity.ERROR and d.code not in beside
    ]
    if errors:
        more = f" (and {len(errors) - 1:,} more)" if len(errors) > 1 else ""
        raise RobotHasErrorsError(
            report.robot,
            f"{errors[0].message} (finding {errors[0].code}){more}",
            [d.code for d in errors],
        )
    layout = build_layout(report.joints)
    if layout.unsupported:
        joint, model, reason = layout.unsupported[0]
        raise UnsupportedConfigurationError(joint, model, reason)
    per_joint = Counter(c.joint for c in layout.coordinates)
    locked = {f.joint for f in layout.fills if f.leader is None}
    for fill in layout.fills:
        leader = fill.leader
        if leader is not None and leader not in locked and per_joint[leader] != 1:
            raise UnsupportedConfigurationError(
                fill.joint, "mimic", f"its leader '{leader}' is not a one-coordinate joint"
            )
    for mimic in report.joints:  # a mimic joint without q entries (a saved report's too)
        lead = mimic.mimic.joint if mimic.mimic is not None else None
        if lead is not None and lead not in locked and per_joint[lead] != 1:
            raise UnsupportedConfigurationError(
                mimic.name, "mimic", f"its leader '{lead}' is not a one-coordinate joint"
            )
    others = tuple(j.name for j in report.joints if j.name not in per_joint)
    mujoco = None
    if by_name(report.source.format).stores == "mujoco":
        from cspace._slots import MujocoLayout

        mujoco = MujocoLayout.from_report(report)
    weights = (1.0,) * len(layout.slots)
    drake = tuple(d for d in report.diagnostics if d.code in DRAKE_CODES)
    return (
        report.robot,
        layout,
        report.nq,
        weights,
        others,
        UNIT_TOLERANCE,
        report.joints,
        mujoco,
        report.source.format,
        drake,
    )
