"""SDF ``<axis><initial_position>``: the pose an SDF file stores, checked.

SDFormat (1.8 and later) gives each joint axis an ``<initial_position>`` (default 0), the
position the joint starts at in simulation. The values the file writes are one pose,
``initial_position``, of the robot's C-space (joints without one at neutral): each is
checked against its joint's limits (``pose-out-of-limits``, at the element's line, with
the same 1e-4 of slack as keyframes) and must be a number.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from lxml import etree

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, PoseSpec
from cspace._formats.shared.xmlio import line_of
from cspace._formats.urdf.numbers import parse_number
from cspace._joint_kind import JointKind

SLACK = 1e-4
"""How far past a bound an initial position may be (rad or m), as for keyframes."""

POSE = "initial_position"
"""The name of the pose (and its ``source``)."""


def initial_pose(
    specs: Sequence[JointSpec], elements: Mapping[str, etree._Element]
) -> tuple[PoseSpec | None, list[Diagnostic]]:
    """The pose the ``<initial_position>`` elements store, and its findings.

    Args:
        specs: The joints read, in any order.
        elements: Each joint's ``<joint>`` element, by name.

    Returns:
        The pose (None when the file gives no initial position), and the findings.
    """
    values: list[tuple[str, tuple[float, ...]]] = []
    found: list[Diagnostic] = []
    first: int | None = None
    for spec in specs:
        element = elements.get(spec.name)
        if element is None or spec.kind in (JointKind.FIXED, JointKind.SPHERICAL):
            continue
        axes = ("axis", "axis2") if spec.kind is JointKind.UNIVERSAL else ("axis",)
        given = [element.find(f"{axis}/initial_position") for axis in axes]
        if all(g is None for g in given):
            continue
        numbers = []
        for k, item in enumerate(given):
            number = _number(item)
            numbers.append(0.0 if number is None else number)
            line = line_of(item)
            first = line if first is None or (line is not None and line < first) else first
            if item is not None:
                found.extend(_check(spec, k, numbers[-1], line))
        values.append((spec.name, tuple(numbers)))
    if not values:
        return None, found
    return PoseSpec(POSE, POSE, first, tuple(values)), found


def _number(item: etree._Element | None) -> float | None:
    if item is None:
        return None
    number = parse_number(item.text or "")  # C-locale decimals: no 1_0, as sdformat
    return math.nan if number is None else number


def _check(spec: JointSpec, k: int, value: float, line: int | None) -> list[Diagnostic]:
    unit = "m" if spec.kind is JointKind.PRISMATIC else "rad"
    said = f"initial position of joint '{spec.name}'" + (f" (axis {k + 1})" if k else "")
    if not math.isfinite(value):
        return [finding("pose-out-of-limits", spec.name, f"{said} is {value}: not a number", line)]
    if spec.limited and k < len(spec.lower):
        low, high = spec.lower[k], spec.upper[k]
        if not (low - SLACK <= value <= high + SLACK):
            return [
                finding(
                    "pose-out-of-limits",
                    spec.name,
                    f"{said} is {value:.8g}, outside [{low:.8g}, {high:.8g}] {unit}",
                    line,
                )
            ]
    return []
