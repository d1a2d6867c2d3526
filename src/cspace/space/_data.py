"""What the space's helpers work on: one frozen record of a configuration space's data.

`ConfigurationSpace` is the facade users hold; every helper it delegates to (the
engines, sampling, validation, tangents, matrices, trajectories, the conventions' maps,
OMPL) takes a `SpaceData` instead, and calls functions on it (the engines,
``layout.assemble``), never the facade: the facade calls the helpers, and nothing calls
back. `check_fields` checks the facade's fields when it is made, and `space_data` builds
the record from them once, when it is first used; the record holds only immutable values
(tuples, the layout, read-only arrays).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from cspace.errors import ArgumentError, ArgumentTypeError
from cspace.space._arguments import real_number, weight
from cspace.space._checks import FloatArray
from cspace.space._geometry.factors import Circle, Line, Rotation

if TYPE_CHECKING:
    from cspace._factor_kinds import Coordinate
    from cspace._findings import Diagnostic
    from cspace._reports.report import JointReport
    from cspace._slots import MujocoLayout
    from cspace.space._geometry.layout import Layout, Slot


@dataclass(frozen=True)
class Columns:
    """Column index arrays and squared weights, as the kernels take them (read-only)."""

    lines: NDArray[np.int64]
    line_w2: FloatArray
    w2: FloatArray  # per column: the squared weight on R^1 columns, 0 elsewhere
    circles: NDArray[np.int64]
    circle_w2: FloatArray
    rotations: NDArray[np.int64]
    rotation_w2: FloatArray


@dataclass(frozen=True, eq=False)
class SpaceData:
    """A configuration space's data, as its helpers read it (see the module docstring).

    Attributes:
        robot: The robot's name, for messages.
        layout: Coordinates, factors, fills, and their places in each vector.
        nq: Length of Pinocchio's q.
        weights: One metric weight per factor (``layout.slots``), checked.
        tolerance: How far a quaternion's norm may be from 1 in inputs, checked.
        columns: The factors' columns and squared weights, as the kernels take them.
        other_joints: Joints without coordinates (fixed, mimic, locked).
        report_joints: The report's joints (kinds, mimic relations, Pinocchio's v layout).
        mujoco: MuJoCo's qpos/qvel layout when the robot came from an MJCF file.
        source_format: The robot file's format; empty when unknown.
        drake_findings: The report's findings on Drake's model of the file.
        size: Number of canonical coordinates.
        dimension: Length of a tangent vector.
        names: Each canonical coordinate's name.
        tangent_names: Each tangent coordinate's name (``base.wx`` for a rotation's x).
    """

    robot: str
    layout: Layout
    nq: int
    weights: tuple[float, ...]
    tolerance: float
    columns: Columns
    other_joints: tuple[str, ...]
    report_joints: tuple[JointReport, ...]
    mujoco: MujocoLayout | None
    source_format: str
    drake_findings: tuple[Diagnostic, ...]
    size: int
    dimension: int
    names: tuple[str, ...]
    tangent_names: tuple[str, ...]

    @property
    def slots(self) -> tuple[Slot, ...]:
        """The factors of the product, in order."""
        return self.layout.slots

    @property
    def joints(self) -> tuple[str, ...]:
        """The joints with coordinates, in tree order."""
        return self.layout.joints

    @property
    def coordinates(self) -> tuple[Coordinate, ...]:
        """Each canonical coordinate: joint, factor, unit, bounds, wraps."""
        return self.layout.coordinates


def space_data(
    robot: str,
    layout: Layout,
    nq: int,
    weights: Sequence[float],
    other_joints: Sequence[str],
    tolerance: float,
    report_joints: Sequence[JointReport],
    mujoco: MujocoLayout | None,
    source_format: str,
    drake_findings: Sequence[Diagnostic],
) -> SpaceData:
    """The data of a space with these fields (`ConfigurationSpace`'s, in its order).

    The fields are those `check_fields` has passed.
    """
    weights = tuple(weights)
    return SpaceData(
        robot=robot,
        layout=layout,
        nq=nq,
        weights=weights,
        tolerance=tolerance,
        columns=_columns(layout, weights),
        other_joints=tuple(other_joints),
        report_joints=tuple(report_joints),
        mujoco=mujoco,
        source_format=source_format,
        drake_findings=tuple(drake_findings),
        size=layout.size,
        dimension=layout.dimension,
        names=tuple(c.name for c in layout.coordinates),
        tangent_names=_tangent_names(layout.slots),
    )


def neutral(data: SpaceData) -> FloatArray:
    """The neutral configuration, shape (n,): 0 clipped into limits, identity rotations."""
    return np.array([c.neutral for c in data.coordinates], dtype=np.float64)


def check_fields(layout: Layout, weights: object, tolerance: object) -> None:
    """Raise unless a space's weights and tolerance are usable (run on construction).

    Raises:
        ArgumentTypeError: ``weights`` is not a sequence, or an entry is not a number.
        ArgumentError: Not one weight per factor, a weight negative, not finite or with
            a square beyond a double, or a tolerance outside [0, 1) (at 1, a zero
            quaternion would pass as unit).
    """
    slots = layout.slots
    if not isinstance(weights, Sequence):
        raise ArgumentTypeError(
            f"weights must be a sequence, got {type(weights).__name__}", argument="weights"
        )
    if len(weights) != len(slots):
        raise ArgumentError(
            f"weights has {len(weights)} entries; the space has {len(slots)} "
            "factors, one weight each",
            argument="weights",
        )
    for slot, w in zip(slots, weights, strict=True):
        weight(w, slot.name)
    real_number(tolerance, "tolerance", minimum=0.0, below=1.0)


def _tangent_names(slots: tuple[Slot, ...]) -> tuple[str, ...]:
    names: list[str] = []
    for slot in slots:
        if isinstance(slot.factor, Rotation):
            names.extend(f"{slot.joint}.w{a}" for a in "xyz")
        else:
            names.append(slot.name)
    return tuple(names)


def _readonly(a: np.ndarray[Any, Any]) -> np.ndarray[Any, Any]:
    a.setflags(write=False)
    return a


def _columns(layout: Layout, weights: tuple[float, ...]) -> Columns:
    """The R^1, S^1 and SO(3) columns with their factors' squared weights."""
    kinds: dict[type, tuple[list[int], list[float]]] = {
        Line: ([], []),
        Circle: ([], []),
        Rotation: ([], []),
    }
    for slot, w in zip(layout.slots, weights, strict=True):
        columns, w2 = kinds[type(slot.factor)]
        columns.append(slot.column)
        w2.append(w * w)

    def arrays(kind: type) -> tuple[NDArray[np.int64], FloatArray]:
        columns, w2 = kinds[kind]
        return (
            _readonly(np.array(columns, dtype=np.int64)),
            _readonly(np.array(w2, dtype=np.float64)),
        )

    lines, line_w2 = arrays(Line)
    per_column = np.zeros(layout.size)
    per_column[lines] = line_w2
    return Columns(lines, line_w2, _readonly(per_column), *arrays(Circle), *arrays(Rotation))
