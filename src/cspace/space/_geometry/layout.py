"""Where each canonical coordinate comes from: the joints of a report, as factors.

`_joint_table` says which factors and coordinates a joint has; the layout
makes the factor objects, places them (columns of a configuration, of a tangent vector,
of Pinocchio's q), and says which q entries are filled otherwise: locked joints, and
mimic joints that Pinocchio had to keep as free joints (value = multiplier * leader +
offset).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cached_property
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal

from cspace._factor_kinds import Coordinate, FactorKind, FactorSpec
from cspace._joint_kind import JointKind
from cspace._joint_table import coordinates_of, dotted, joint_factors, locked
from cspace.space._geometry.factors import Circle, Factor, Line, Rotation
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace._reports.report import JointReport


@dataclass(frozen=True)
class Slot:
    """One factor of the product, and where it sits.

    Attributes:
        name: The factor's name: the joint's, or ``joint.x`` / ``joint.rotation``.
        joint: The joint.
        factor: The factor.
        column: Its first canonical coordinate (a column of a batch of configurations).
        tangent_column: Its first tangent coordinate.
        q_index: Its first entry in Pinocchio's q.
        draw_column: Its first uniform number in a sampling draw.
    """

    name: str
    joint: str
    factor: Factor
    column: int
    tangent_column: int
    q_index: int
    draw_column: int = 0

    @property
    def columns(self) -> slice:
        """Its canonical coordinates' columns."""
        return slice(self.column, self.column + self.factor.size)

    @property
    def tangent(self) -> slice:
        """Its tangent coordinates' columns."""
        return slice(self.tangent_column, self.tangent_column + self.factor.dimension)

    @property
    def q(self) -> slice:
        """Its entries in Pinocchio's q."""
        return slice(self.q_index, self.q_index + self.factor.pinocchio_size)

    @property
    def draws(self) -> slice:
        """Its uniform numbers in a sampling draw."""
        return slice(self.draw_column, self.draw_column + self.factor.draws)


@dataclass(frozen=True)
class Fill:
    """A q entry (or (cos, sin) pair) that no coordinate gives.

    ``value = multiplier * leader + offset`` (leader None: ``value = offset``).
    """

    joint: str
    q_index: int
    cos_sin: bool
    leader: str | None
    multiplier: float
    offset: float


@dataclass(frozen=True)
class Layout:
    """The coordinates, factors and fills of one robot.

    Attributes:
        coordinates: Every canonical coordinate, in order.
        slots: Every factor, in order.
        fills: Pinocchio q entries set from leaders or locked values.
        joints: The joints with coordinates, in tree order.
        unsupported: (joint, reason) for joints without canonical coordinates.
    """

    coordinates: tuple[Coordinate, ...]
    slots: tuple[Slot, ...]
    fills: tuple[Fill, ...]
    joints: tuple[str, ...]
    unsupported: tuple[tuple[str, str, str], ...]

    @property
    def size(self) -> int:
        """Number of canonical coordinates."""
        return len(self.coordinates)

    @property
    def dimension(self) -> int:
        """Length of a tangent vector."""
        return sum(s.factor.dimension for s in self.slots)

    @property
    def draws(self) -> int:
        """Uniform numbers one sampled configuration takes."""
        return sum(s.factor.draws for s in self.slots)

    def __getstate__(self) -> dict[str, Any]:
        """The fields, without the cached `joint_columns` (rebuilt when first used).

        It is a mapping proxy, which does not pickle.
        """
        return {k: v for k, v in self.__dict__.items() if k != "joint_columns"}

    @cached_property
    def joint_columns(self) -> Mapping[str, slice]:
        """Each joint with coordinates -> its columns (a joint's coordinates are adjacent).

        Read-only, like the rest of the layout.
        """
        columns: dict[str, slice] = {}
        for i, c in enumerate(self.coordinates):
            start = columns[c.joint].start if c.joint in columns else i
            columns[c.joint] = slice(start, i + 1)
        return MappingProxyType(columns)


Target = Literal["columns", "tangent", "q"]


def assemble(
    slots: tuple[Slot, ...], out: FloatArray, target: Target, part: Callable[[Slot], FloatArray]
) -> FloatArray:
    """The one per-factor loop: ``out[:, slot.<target>] = part(slot)`` for every factor.

    Every operation that is not a compiled kernel delegates to the factors through this:
    the factor computes its block, the layout says where it goes (configuration columns,
    tangent columns or Pinocchio's q), and the blocks together are the result.

    Args:
        slots: The factors, in order.
        out: The result, (rows, width) for the target.
        target: Where each factor's block goes.
        part: The block of one factor, (rows, its width in the target).

    Returns:
        ``out``.
    """
    for slot in slots:
        out[:, getattr(slot, target)] = part(slot)
    return out


def _factor(spec: FactorSpec) -> Factor:
    if spec.kind is FactorKind.ROTATION:
        return Rotation(max_angle=spec.upper)
    if spec.kind is FactorKind.CIRCLE:
        return Circle("cos_sin" if spec.encoding == "cos_sin" else "angle")
    return Line(spec.lower, spec.upper, spec.unit)


def _fill(joint: JointReport, q_index: int) -> Fill | None:
    if joint.kind is JointKind.MIMIC and joint.mimic is not None:
        m = joint.mimic
        return Fill(joint.name, q_index, joint.nq == 2, m.joint, m.multiplier, m.offset)
    if locked(joint.limits) and joint.limits is not None and joint.nq == 1:
        return Fill(joint.name, q_index, False, None, 0.0, joint.limits.lower[0])
    return None


def build_layout(joints: tuple[JointReport, ...]) -> Layout:
    """The layout of a robot's joints (as a report lists them, in tree order)."""
    coordinates: list[Coordinate] = []
    slots: list[Slot] = []
    fills: list[Fill] = []
    names: list[str] = []
    unsupported: list[tuple[str, str, str]] = []
    tangent = draw = 0
    for joint in joints:
        found = joint_factors(joint)
        if found.unsupported is not None:
            unsupported.append((joint.name, joint.pinocchio_model or "", found.unsupported))
            continue
        if not found.factors:
            fill = None if joint.q_index is None else _fill(joint, joint.q_index)
            if fill is not None:
                fills.append(fill)
            continue
        names.append(joint.name)
        q_index = joint.q_index or 0
        for spec in found.factors:
            factor = _factor(spec)
            name = dotted(joint.name, spec.suffix)
            slots.append(Slot(name, joint.name, factor, len(coordinates), tangent, q_index, draw))
            tangent += factor.dimension
            draw += factor.draws
            q_index += factor.pinocchio_size
            coordinates.extend(coordinates_of(joint.name, spec))
    return Layout(tuple(coordinates), tuple(slots), tuple(fills), tuple(names), tuple(unsupported))
