"""What ``cspace convert --to mujoco-ctrl`` says when MuJoCo would clamp the ctrl it writes.

MuJoCo clamps the ctrl of an actuator with a ``ctrlrange`` (``ctrllimited``) into that
range before the actuator acts (``clampctrl``); the map writes ``gear * qpos`` all the
same. A target within its joint's range but beyond a narrower ctrlrange is one MuJoCo
does not reach: the joint stops where the range ends. One warning per such actuator,
after the vectors: how many of them it clamps, and the line of the first.
"""

from __future__ import annotations

import math
from typing import Any

from ..output import finding

_SLACK = 1e-9
"""How far (relative to the bound, at least absolutely) a ctrl may pass its range: the
product ``gear * qpos`` rounds."""


class CtrlClamps:
    """The converted ctrl that limited actuators' ranges clamp, counted per actuator."""

    def __init__(self, conventions: Any) -> None:
        """Read the actuators' ranges from the robot's `Conventions` (its mujoco-ctrl map)."""
        actuators = conventions.maps("mujoco-ctrl").mujoco.plan.layout.actuators
        self.ranges: list[tuple[int, str, float, float]] = []
        for index, actuator in enumerate(actuators):
            low_high = actuator.ctrlrange
            if low_high is not None and all(math.isfinite(x) for x in low_high):
                self.ranges.append((index, actuator.label(index), *low_high))
        self.found: dict[int, list[int]] = {}  # entry -> [vectors clamped, first line]

    def add(self, ctrl: Any, lines: list[int]) -> None:
        """Count the rows of ``ctrl`` (vectors, nu) outside each range; ``lines``: theirs."""
        for index, _, low, high in self.ranges:
            values = ctrl[:, index]
            slack = _SLACK * max(1.0, abs(low), abs(high))
            outside = ((values < low - slack) | (values > high + slack)).nonzero()[0]
            if len(outside):
                seen = self.found.setdefault(index, [0, lines[int(outside[0])]])
                seen[0] += len(outside)

    def say(self, path: str) -> None:
        """A warning per actuator whose ctrl MuJoCo clamps, at the first vector's line."""
        for index, label, low, high in self.ranges:
            if index not in self.found:
                continue
            count, line = self.found[index]
            finding(
                "warning",
                f"{path}:{line}: ctrl[{index}] of actuator {label} is outside its ctrlrange "
                f"[{low:.8g}, {high:.8g}] in {count:,} vector{'s' if count != 1 else ''} (the "
                "first here): MuJoCo clamps it, and the joint stops where the range ends",
            )
