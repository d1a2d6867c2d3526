"""The factors of a configuration space, one class a kind (public name).

`Line` (R), `Circle` (S^1, SO(2)) and `Rotation` (SO(3)), from
`_factors`, where they live.
"""

from cspace.space._geometry.factors import (
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
