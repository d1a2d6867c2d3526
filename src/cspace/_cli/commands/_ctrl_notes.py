"""What ``cspace convert --to mujoco-ctrl`` says when MuJoCo would clamp the ctrl it writes.

MuJoCo clamps the ctrl of an actuator with a ``ctrlrange`` (``ctrllimited``) into that
range before the actuator acts (``clampctrl``); the map writes ``gear * qpos`` all the
same. A target within its joint's range but beyond a narrower ctrlrange is one MuJoCo
does not reach: the joint stops where the range ends. One warning per such actuator
(the first `_SHOWN`), after the vectors: how many of them it clamps, and the line of the
first.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..output import finding

_SHOWN = 20
"""Most actuators warned of one by one; one more line counts the rest."""

_SLACK = 1e-9
"""How far (relative to the bound, at least absolutely) a ctrl may pass its range: the
product ``gear * qpos`` rounds."""


class CtrlClamps:
    """The converted ctrl that limited actuators' ranges clamp, counted per actuator."""

    def __init__(self, conventions: Any) -> None:
        """Read the actuators' ranges from the robot's `Conventions` (its mujoco-ctrl map)."""
        actuators = conventions.maps("mujoco-ctrl").mujoco.plan.layout.actuators
        limited = [
            (index, actuator)
            for index, actuator in enumerate(actuators)
            if actuator.ctrlrange is not None and all(math.isfinite(x) for x in actuator.ctrlrange)
        ]
        self.labels = [actuator.label(index) for index, actuator in limited]
        self.entries = np.array([index for index, _ in limited], dtype=np.intp)
        bounds = np.array([a.ctrlrange for _, a in limited], dtype=float).reshape(-1, 2)
        slack = _SLACK * np.maximum(1.0, np.abs(bounds).max(axis=1, initial=0.0))
        self.low, self.high = bounds[:, 0] - slack, bounds[:, 1] + slack
        self.bounds = bounds
        self.counts = np.zeros(len(limited), dtype=np.int64)
        self.first = np.zeros(len(limited), dtype=np.int64)  # the line of the first clamped

    def add(self, ctrl: Any, lines: list[int]) -> None:
        """Count the rows of ``ctrl`` (vectors, nu) outside each range; ``lines``: theirs."""
        if not len(self.entries) or not len(ctrl):
            return
        values = np.asarray(ctrl)[:, self.entries]
        outside = (values < self.low) | (values > self.high)
        new = outside.any(axis=0) & (self.counts == 0)
        rows = outside.argmax(axis=0)
        self.first[new] = np.asarray(lines)[rows[new]]
        self.counts += outside.sum(axis=0)

    def say(self, path: str) -> None:
        """A warning per actuator whose ctrl MuJoCo clamps, at the first vector's line.

        The first `_SHOWN` actuators are each a line; one more counts the others.
        """
        clamped = self.counts.nonzero()[0]
        for k in clamped[:_SHOWN]:
            count = int(self.counts[k])
            low, high = float(self.bounds[k, 0]), float(self.bounds[k, 1])
            finding(
                "warning",
                f"{path}:{self.first[k]}: ctrl[{self.entries[k]}] of actuator {self.labels[k]} "
                f"is outside its ctrlrange [{low:.8g}, {high:.8g}] in {count:,} "
                f"vector{'s' if count != 1 else ''} (the first here): MuJoCo clamps it, and "
                "the joint stops where the range ends",
            )
        if len(clamped) > _SHOWN:
            more = len(clamped) - _SHOWN
            finding("warning", f"{path}: and the ctrl of {more:,} more actuators MuJoCo clamps")
