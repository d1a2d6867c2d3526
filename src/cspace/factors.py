"""The factors of a configuration space, one class a kind (public name).

:class:`Line` (R), :class:`Circle` (S^1, SO(2)) and :class:`Rotation` (SO(3)), from
:mod:`cspace.space.factors`, where they live.
"""

from cspace.space.factors import (
    PI,
    TWO_PI,
    Circle,
    Factor,
    Line,
    Rotation,
    short_way,
    wrap_angle,
)

__all__ = ["PI", "TWO_PI", "Circle", "Factor", "Line", "Rotation", "short_way", "wrap_angle"]
