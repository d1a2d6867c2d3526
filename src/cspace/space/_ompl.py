"""A robot's C-space as an OMPL state space, and configurations as OMPL states.

One subspace per factor, in the layout's order: ``RealVectorStateSpace(1)`` for a line
or interval (with its limits, or the bounds given for a line without them: a planner
samples), ``SO2StateSpace`` for a circle, ``SO3StateSpace`` for a rotation (OMPL keeps
its quaternion as x, y, z, w). The weights are cspace's: a factor of weight ``w`` has
OMPL weight ``w``, and ``2 w`` for a rotation, since OMPL's SO(3) distance is the angle
between quaternions, half the rotation angle cspace measures.

OMPL combines subspaces by a weighted *sum* of their distances, cspace by the root of
the sum of squares (the product metric). Each factor's term is the same, so the two
agree on configurations that differ in one factor, and in general ``d_cspace <= d_ompl
<= sqrt(k) d_cspace`` for k factors that differ. Interpolation agrees exactly: each
factor along its own shortest path (lines linearly, circles the short way round,
rotations by slerp), in both. OMPL's SO(3) has no bounds: a ball joint with a largest
angle is all of SO(3) to its sampler, and `OmplSpace.valid` (for the validity checker)
keeps its limit.

OMPL is imported only here, when a space is asked for.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from cspace.errors import ArgumentError
from cspace.space._geometry.factors import Circle, Line, Rotation
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space._shape import Space


@dataclass(frozen=True)
class OmplSpace:
    """A robot's C-space in OMPL, and the maps between its states and configurations.

    Attributes:
        space: The ``ompl.base.CompoundStateSpace`` (set up, ready for a planner).
        robot: The robot's name.
        kinds: Each subspace's factor (``"line"``, ``"circle"``, ``"rotation"``).
        columns: Each subspace's first canonical column.
        size: The length of a canonical configuration.
        configurations: The configuration space it is made from.
        bounds: (column, lower, upper) of each line's bounds in OMPL (its limits, or
            those given).
    """

    space: Any
    robot: str
    kinds: tuple[str, ...]
    columns: tuple[int, ...]
    size: int
    configurations: Space = field(repr=False)
    bounds: tuple[tuple[int, float, float], ...] = ()

    def valid(self, state: Any) -> bool:
        """Whether a state is within the limits and bounds, for OMPL's validity checker.

        Each line within its bounds in OMPL (its limits, or those given), and the whole
        within the robot's limits. OMPL's SO(3) has no bounds: a ball joint with a
        largest angle is all of SO(3) to OMPL's sampler, and its limit is this check
        (``setStateValidityChecker``).
        """
        x = self.from_state(state)
        inside = all(lower <= x[column] <= upper for column, lower, upper in self.bounds)
        return inside and bool(self.configurations.contains(x, 1e-12))

    def to_state(self, x: ArrayLike, state: Any = None) -> Any:
        """An OMPL state of a canonical configuration (n,), into ``state`` if given.

        Raises:
            ConfigurationShapeError, NonFiniteValueError: ``x`` is not one configuration.
        """
        from cspace.space._checks import as_rows, check_finite

        rows, _ = as_rows(x, self.size, f"a configuration of robot '{self.robot}'")
        if rows.shape[0] != 1:
            raise ArgumentError("to_state takes one configuration", argument="x")
        check_finite(rows, [f"x[{i}]" for i in range(self.size)], ())
        row = self.configurations.canonicalize(rows[0])  # angles wrapped, unit quaternions
        if state is None:
            state = self.space.allocState()
        for k, (kind, column) in enumerate(zip(self.kinds, self.columns, strict=True)):
            part = state[k]
            if kind == "line":
                part[0] = float(row[column])
            elif kind == "circle":
                part.value = float(row[column])
            else:  # (w, x, y, z) -> OMPL's x, y, z, w fields
                w, qx, qy, qz = (float(v) for v in row[column : column + 4])
                part.w, part.x, part.y, part.z = w, qx, qy, qz
        return state

    def from_state(self, state: Any) -> FloatArray:
        """The canonical configuration (n,) of an OMPL state of this space.

        An angle is wrapped into [-pi, pi) (OMPL's SO(2) holds pi too); a quaternion is
        turned to w >= 0 (OMPL's slerp may end on -h, the same rotation).
        """
        from cspace.space._geometry.factors import wrap_angle
        from cspace.space._geometry.rotations import canonicalize

        x = np.zeros(self.size)
        for k, (kind, column) in enumerate(zip(self.kinds, self.columns, strict=True)):
            part = state[k]
            if kind == "line":
                x[column] = part[0]
            elif kind == "circle":
                x[column] = wrap_angle(np.array(part.value))
            else:
                h = np.array([[part.w, part.x, part.y, part.z]])
                x[column : column + 4] = canonicalize(h, check=False)[0]
        return x


def ompl_space(space: Space, bounds: Mapping[str, tuple[float, float]] | None = None) -> OmplSpace:
    """The OMPL state space of ``space`` (see the module docstring).

    Args:
        space: The configuration space.
        bounds: (lower, upper) by coordinate name, for lines without limits (as for
            `ConfigurationSpace.sample`).

    Raises:
        UnboundedSamplingError: A line has neither limits nor bounds (OMPL samples).
        ArgumentError: OMPL's Python bindings are not installed, the robot cannot move,
            bounds are given for a circle (OMPL's SO(2) has none), or a factor has
            weight 0 (OMPL's motion checks would not see it move).
    """
    try:
        from ompl import base as ob
    except ImportError:
        raise ArgumentError(
            "an OMPL space needs OMPL's Python bindings: pip install ompl", argument="ompl"
        ) from None
    from cspace.space._sampling import resolve_bounds

    if not space.slots:
        raise ArgumentError(
            f"robot '{space.robot}' cannot move (its C-space is a point): OMPL has no "
            "space of dimension 0",
            argument="space",
        )
    given = dict(bounds or {})
    circles = {s.name for s in space.slots if isinstance(s.factor, Circle)}
    for name in given:
        if name in circles:
            raise ArgumentError(
                f"OMPL's SO(2) has no bounds: '{name}' turns all the way round in OMPL "
                "(keep an arc in the state validity checker)",
                argument="bounds",
                coordinate=name,
            )
    zero = [slot.name for slot, w in zip(space.slots, space.weights, strict=True) if w == 0]
    if zero:
        raise ArgumentError(
            f"factor '{zero[0]}' has weight 0: OMPL checks motions by distance, and would "
            "not see it move (give every factor a weight above 0)",
            argument="weights",
        )
    limits = resolve_bounds(space, given)
    compound = ob.CompoundStateSpace()
    kinds: list[str] = []
    columns: list[int] = []
    for slot, weight in zip(space.slots, space.weights, strict=True):
        factor = slot.factor
        if isinstance(factor, Line):
            sub = ob.RealVectorStateSpace(1)
            box = ob.RealVectorBounds(1)
            lower, upper = limits[slot.name]
            box.setLow(lower)
            box.setHigh(upper)
            sub.setBounds(box)
            kinds.append("line")
        elif isinstance(factor, Circle):
            sub = ob.SO2StateSpace()
            kinds.append("circle")
        elif isinstance(factor, Rotation):
            sub = ob.SO3StateSpace()
            weight *= 2.0  # OMPL's SO(3) distance is half the rotation angle
            kinds.append("rotation")
        else:  # every factor is one of these three
            raise ArgumentError(f"factor '{slot.name}' has no OMPL state space")
        sub.setName(slot.name)
        compound.addSubspace(sub, weight)
        columns.append(slot.column)
    compound.setup()
    narrowed = tuple(
        (slot.column, *limits[slot.name])
        for slot in space.slots
        if isinstance(slot.factor, Line) and slot.name in limits
    )
    return OmplSpace(
        compound, space.robot, tuple(kinds), tuple(columns), space.size, space, narrowed
    )
