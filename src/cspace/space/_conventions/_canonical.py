"""cspace's own convention: canonical coordinates and tangent vectors.

An angle in [-pi, pi) per circle, a quaternion (w, x, y, z) with w >= 0 per rotation,
every other coordinate as its value; a tangent vector holds a rate per line and circle
and, per rotation, the angular velocity in the body frame (see `cspace.space`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from cspace.space._compute.engines import canonicalize
from cspace.space._conventions._maps import Robot
from cspace.space._geometry.rotations import FloatArray


class Maps:
    """The canonical convention's `Maps <cspace.space._conventions._maps.Maps>`.

    Canonicalization.
    """

    def __init__(self, robot: Robot) -> None:
        self.data = robot.data

    def names(self, velocity: bool) -> tuple[str, ...]:
        """The space's coordinate names (``base.qw``), or its tangent's."""
        return self.data.tangent_names if velocity else self.data.names

    def to_tool(self, x: ArrayLike) -> FloatArray:
        """Canonical configurations of configurations (..., n)."""
        return canonicalize(self.data, x, None)

    def from_tool(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations of configurations (..., n)."""
        return canonicalize(self.data, q, None)

    def to_velocity(self, at: ArrayLike, dx: ArrayLike) -> FloatArray:
        """Tangent vectors as they are (float64)."""
        return np.array(dx, dtype=np.float64)

    def from_velocity(self, at: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors as they are (float64)."""
        return np.array(v, dtype=np.float64)
