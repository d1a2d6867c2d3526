"""Pinocchio's q and a report's canonical configuration, joint by joint, for the closure.

The encodings are the joint table's (`cspace._joint_table`): ``value`` and ``angle``
are one number in both; ``cos_sin`` is Pinocchio's ``(cos, sin)`` for one canonical
angle; ``xyzw`` is Pinocchio's quaternion, ``(qw, qx, qy, qz)`` canonically. A joint of
another encoding (Euler angles, swing and twist) has no canonical values here.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from cspace._joint_table import joint_factors
from cspace._reports.poses import assemble
from cspace._reports.report import Report


def canonical(report: Report, q: Sequence[float]) -> tuple[float, ...] | None:
    """The canonical configuration of Pinocchio's ``q`` (None for an encoding not known)."""
    values: dict[str, list[float]] = {}
    for joint in report.joints:
        found = joint_factors(joint)
        if joint.q_index is None or not found.factors:
            continue
        at = joint.q_index
        out: list[float] = []
        for spec in found.factors:
            if spec.encoding in ("value", "angle"):
                out.append(float(q[at]))
                at += 1
            elif spec.encoding == "cos_sin":
                out.append(math.atan2(float(q[at + 1]), float(q[at])))
                at += 2
            elif spec.encoding == "xyzw":
                x, y, z, w = (float(v) for v in q[at : at + 4])
                out.extend((w, x, y, z))
                at += 4
            else:
                return None
        values[joint.name] = out
    return assemble(report.coordinates, values)


def pinocchio_q(report: Report, x: Sequence[float], neutral: Sequence[float]) -> list[float] | None:
    """Pinocchio's q of a canonical configuration (None for an encoding not known).

    Args:
        report: The robot's report.
        x: A configuration in the report's canonical coordinates.
        neutral: Pinocchio's neutral q, for the entries no coordinate sets.
    """
    q = [float(v) for v in neutral]
    column = 0
    for joint in report.joints:
        found = joint_factors(joint)
        if joint.q_index is None or not found.factors:
            continue
        at = joint.q_index
        for spec in found.factors:
            if spec.encoding in ("value", "angle"):
                q[at] = float(x[column])
                at, column = at + 1, column + 1
            elif spec.encoding == "cos_sin":
                q[at], q[at + 1] = math.cos(x[column]), math.sin(x[column])
                at, column = at + 2, column + 1
            elif spec.encoding == "xyzw":
                w, i, j, k = (float(v) for v in x[column : column + 4])
                q[at : at + 4] = [i, j, k, w]
                at, column = at + 4, column + 4
            else:
                return None
    return q
