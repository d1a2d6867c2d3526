"""A robot's C-space as an OMPL state space, and configurations as OMPL states.

One subspace per factor, in the layout's order: ``RealVectorStateSpace(1)`` for a line
or interval (with its limits, or the bounds given for a line without them: a planner
samples), ``SO2StateSpace`` for a circle, ``SO3StateSpace`` for a rotation (OMPL keeps
its quaternion as x, y, z, w); a floating joint is one ``SE3StateSpace`` and a planar
joint one ``SE2StateSpace`` (its translation weighed as one Euclidean part, as cspace
weighs it), when its lines weigh the same. The weights are cspace's: a factor of weight ``w`` has
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

from cspace._joint_kind import JointKind
from cspace.errors import ArgumentError
from cspace.space._compute.engines import canonicalize
from cspace.space._geometry.factors import Circle, Line, Rotation
from cspace.space._geometry.rotations import FloatArray
from cspace.space._validation import contains

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


@dataclass(frozen=True)
class OmplSpace:
    """A robot's C-space in OMPL, and the maps between its states and configurations.

    Attributes:
        space: The ``ompl.base.CompoundStateSpace`` (set up, ready for a planner).
        robot: The robot's name.
        kinds: Each subspace's factor (``"line"``, ``"circle"``, ``"rotation"``).
        columns: Each subspace's first canonical column.
        size: The length of a canonical configuration.
        configurations: The configuration space it is made from (a
            `ConfigurationSpace`).
        bounds: (column, lower, upper) of each line's bounds in OMPL (its limits, or
            those given).
    """

    space: Any
    robot: str
    kinds: tuple[str, ...]
    columns: tuple[int, ...]
    size: int
    configurations: Any = field(repr=False)
    bounds: tuple[tuple[int, float, float], ...] = ()
    _data: SpaceData = field(repr=False, compare=False, kw_only=True)

    def valid(self, state: Any) -> bool:
        """Whether a state is within the limits and bounds, for OMPL's validity checker.

        Each line within its bounds in OMPL (its limits, or those given), and the whole
        within the robot's limits. OMPL's SO(3) has no bounds: a ball joint with a
        largest angle is all of SO(3) to OMPL's sampler, and its limit is this check
        (``setStateValidityChecker``).
        """
        x = self.from_state(state)
        inside = all(lower <= x[column] <= upper for column, lower, upper in self.bounds)
        return inside and bool(contains(self._data, x, 1e-12))

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
        row = canonicalize(self._data, rows[0], None)  # angles wrapped, unit quaternions
        if state is None:
            state = self.space.allocState()
        for k, (kind, column) in enumerate(zip(self.kinds, self.columns, strict=True)):
            part = state[k]
            if kind == "line":
                part[0] = float(row[column])
            elif kind == "circle":
                part.value = float(row[column])
            elif kind == "se2":
                part.setXY(float(row[column]), float(row[column + 1]))
                part.setYaw(float(row[column + 2]))
            elif kind == "se3":
                part.setXYZ(*(float(v) for v in row[column : column + 3]))
                _set_quaternion(part.rotation(), row[column + 3 : column + 7])
            else:
                _set_quaternion(part, row[column : column + 4])
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
            elif kind == "se2":
                x[column : column + 2] = part.getX(), part.getY()
                x[column + 2] = wrap_angle(np.array(part.getYaw()))
            else:
                turn = part
                if kind == "se3":
                    x[column : column + 3] = part.getX(), part.getY(), part.getZ()
                    column, turn = column + 3, part.rotation()
                h = np.array([[turn.w, turn.x, turn.y, turn.z]])
                x[column : column + 4] = canonicalize(h, check=False)[0]
        return x


def _set_quaternion(part: Any, h: FloatArray) -> None:
    """An OMPL SO(3) state (fields x, y, z, w) set to the quaternion (w, x, y, z)."""
    part.w, part.x, part.y, part.z = (float(v) for v in h)


def ompl_space(
    data: SpaceData,
    bounds: Mapping[str, tuple[float, float]] | None,
    configurations: object,
) -> OmplSpace:
    """The OMPL state space of a configuration space (see the module docstring).

    Args:
        data: The configuration space's data.
        bounds: (lower, upper) by coordinate name, for lines without limits (as for
            `ConfigurationSpace.sample`).
        configurations: The `ConfigurationSpace` itself, which the result names
            (`OmplSpace.configurations`) and never calls.

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

    if not data.slots:
        raise ArgumentError(
            f"robot '{data.robot}' cannot move (its C-space is a point): OMPL has no "
            "space of dimension 0",
            argument="space",
        )
    given = dict(bounds or {})
    circles = {s.name for s in data.slots if isinstance(s.factor, Circle)}
    for name in given:
        if name in circles:
            raise ArgumentError(
                f"OMPL's SO(2) has no bounds: '{name}' turns all the way round in OMPL "
                "(keep an arc in the state validity checker)",
                argument="bounds",
                coordinate=name,
            )
    zero = [slot.name for slot, w in zip(data.slots, data.weights, strict=True) if w == 0]
    if zero:
        raise ArgumentError(
            f"factor '{zero[0]}' has weight 0: OMPL checks motions by distance, and would "
            "not see it move (give every factor a weight above 0)",
            argument="weights",
        )
    limits = resolve_bounds(data, given)
    compound = ob.CompoundStateSpace()
    kinds: list[str] = []
    columns: list[int] = []
    slots = list(zip(data.slots, data.weights, strict=True))
    joint_kinds = {j.name: j.kind for j in data.report_joints}
    k = 0
    while k < len(slots):
        slot, weight = slots[k]
        group = _rigid(joint_kinds, slots, k)
        if group is not None:  # a floating or planar joint: OMPL's SE(3) or SE(2)
            kind, size = group
            sub = _rigid_space(ob, kind, [limits[s.name] for s, _ in slots[k : k + size - 1]])
            sub.setSubspaceWeight(0, weight)
            turn = slots[k + size - 1][1]
            sub.setSubspaceWeight(1, 2.0 * turn if kind == "se3" else turn)
            weight = 1.0
            kinds.append(kind)
            k += size
        else:
            sub = _factor_space(ob, slot, limits)
            weight *= 2.0 if isinstance(slot.factor, Rotation) else 1.0  # half angles
            kinds.append(_KINDS[type(slot.factor)])
            k += 1
        sub.setName(slot.joint if group is not None else slot.name)
        compound.addSubspace(sub, weight)
        columns.append(slot.column)
    compound.setup()
    narrowed = tuple(
        (slot.column, *limits[slot.name])
        for slot in data.slots
        if isinstance(slot.factor, Line) and slot.name in limits
    )
    return OmplSpace(
        compound,
        data.robot,
        tuple(kinds),
        tuple(columns),
        data.size,
        configurations,
        narrowed,
        _data=data,
    )


_KINDS = {Line: "line", Circle: "circle", Rotation: "rotation"}
"""Each factor's kind of OMPL subspace."""


def _rigid(
    kinds: Mapping[str, JointKind], slots: list[tuple[Any, float]], k: int
) -> tuple[str, int] | None:
    """OMPL's SE(3) or SE(2) for the joint whose factors start at slot ``k``.

    (``"se3"``, 4) or (``"se2"``, 3) when slot ``k`` starts a floating or planar joint
    whose lines weigh the same (OMPL's SE(3) and SE(2) weigh their translation as one),
    else None.
    """
    slot = slots[k][0]
    kind = kinds.get(slot.joint)
    size = {JointKind.FLOATING: 4, JointKind.PLANAR: 3}.get(kind) if kind else None
    if size is None or k + size > len(slots):
        return None
    group = slots[k : k + size]
    lines, turn = group[:-1], group[-1][0]
    shaped = all(isinstance(s.factor, Line) and s.joint == slot.joint for s, _ in lines)
    last = Rotation if kind is JointKind.FLOATING else Circle
    if not (shaped and isinstance(turn.factor, last) and turn.joint == slot.joint):
        return None
    if len({w for _, w in lines}) != 1:
        return None
    return ("se3", 4) if kind is JointKind.FLOATING else ("se2", 3)


def _rigid_space(ob: Any, kind: str, bounds: list[tuple[float, float]]) -> Any:
    """OMPL's SE(3) or SE(2) state space, its translation within ``bounds``."""
    sub = ob.SE3StateSpace() if kind == "se3" else ob.SE2StateSpace()
    box = ob.RealVectorBounds(len(bounds))
    for i, (lower, upper) in enumerate(bounds):
        box.setLow(i, lower)
        box.setHigh(i, upper)
    sub.setBounds(box)
    return sub


def _factor_space(ob: Any, slot: Any, limits: Mapping[str, tuple[float, float]]) -> Any:
    """OMPL's space of one factor: a bounded real line, SO(2) or SO(3)."""
    if isinstance(slot.factor, Line):
        sub = ob.RealVectorStateSpace(1)
        box = ob.RealVectorBounds(1)
        lower, upper = limits[slot.name]
        box.setLow(lower)
        box.setHigh(upper)
        sub.setBounds(box)
        return sub
    if isinstance(slot.factor, Circle):
        return ob.SO2StateSpace()
    if isinstance(slot.factor, Rotation):
        return ob.SO3StateSpace()
    raise ArgumentError(f"factor '{slot.name}' has no OMPL state space")  # never: 3 kinds
