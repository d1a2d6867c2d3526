"""A robot's configuration space as the product of its factors, with batched operations.

A configuration is a float64 array of shape ``(n,)``, with ``n = space.size``
canonical coordinates (see :mod:`cspace.layout` for their order and names); a batch
has shape ``(N, n)`` (any leading axes work). Tangent vectors have ``space.dimension``
entries, factor by factor: R^1 and S^1 one each, SO(3) the rotation vector of a^-1 b in
the frame of a (rad). Angles in rad, lengths in m, quaternions (w, x, y, z).

The metric is the weighted product metric:
``d(a, b) = sqrt(sum over factors f of (w_f * d_f(a_f, b_f))^2)`` with ``d_f`` = |b - a|
on R^1, the shortest way round on S^1 (in [0, pi]), and the rotation angle of a^-1 b on
SO(3) (in [0, pi], h and -h one point); ``w_f`` is the weight of the factor's joint
(default 1; see :meth:`ConfigurationSpace.with_weights`).

Distance, interpolation and canonicalization run in compiled kernels
(:mod:`cspace.kernels`); everything else delegates factor by factor to
:mod:`cspace.factors`, whole batches at a time.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import rotations
from .checks import (
    as_rows,
    broadcast_shapes,
    check_finite,
    check_unit,
    expand,
    output,
    unit,
)
from .coordinates import Coordinate
from .errors import (
    ConfigurationError,
    NonFiniteValueError,
    NotARotationError,
    OutOfLimitsError,
    UnknownJointError,
    UnsupportedConfigurationError,
)
from .factors import Circle, Line, Rotation
from .layout import Layout, Slot, build_layout
from .rotations import UNIT_TOLERANCE, BoolArray, FloatArray

if TYPE_CHECKING:
    from .report import Report


@dataclass(frozen=True)
class _Columns:
    """Column index arrays and squared weights, as the kernels take them."""

    lines: NDArray[np.int64]
    line_w2: FloatArray
    w2: FloatArray  # per column: the squared weight on R^1 columns, 0 elsewhere
    circles: NDArray[np.int64]
    circle_w2: FloatArray
    rotations: NDArray[np.int64]
    rotation_w2: FloatArray


def _readonly(a: np.ndarray[Any, Any]) -> np.ndarray[Any, Any]:
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class ConfigurationSpace:
    """The configuration space of one robot: C = product of its joints' factors.

    Build it with :func:`cspace.load` (or :meth:`from_report`). Immutable.

    Attributes:
        robot: The robot's name.
        layout: Coordinates, factors, and how they map to Pinocchio's q.
        nq: Length of Pinocchio's q.
        weights: One metric weight per factor (``layout.slots``).
        other_joints: Joints without coordinates (fixed, mimic, locked), for messages.
        tolerance: How far a quaternion's norm may be from 1 in inputs.
    """

    robot: str
    layout: Layout
    nq: int
    weights: tuple[float, ...]
    other_joints: tuple[str, ...] = ()
    tolerance: float = UNIT_TOLERANCE

    @classmethod
    def from_report(cls, report: Report) -> ConfigurationSpace:
        """The configuration space of a report's robot.

        Raises:
            UnsupportedConfigurationError: A joint has no canonical coordinates (an
                Euler-angle spherical joint), or a mimic joint's leader has several.
        """
        layout = build_layout(report.joints)
        if layout.unsupported:
            joint, model, reason = layout.unsupported[0]
            raise UnsupportedConfigurationError(joint, model, reason)
        single = {c.joint for c in layout.coordinates}
        locked = {f.joint for f in layout.fills if f.leader is None}
        for fill in layout.fills:
            leader = fill.leader
            count = sum(c.joint == leader for c in layout.coordinates)
            if leader is not None and leader not in locked and (leader not in single or count != 1):
                raise UnsupportedConfigurationError(
                    fill.joint, "mimic", f"its leader '{leader}' is not a one-coordinate joint"
                )
        others = tuple(j.name for j in report.joints if j.name not in layout.joints)
        return cls(report.robot, layout, report.nq, (1.0,) * len(layout.slots), others)

    # --- description ---------------------------------------------------------------

    @property
    def size(self) -> int:
        """Number of canonical coordinates n."""
        return self.layout.size

    @property
    def dimension(self) -> int:
        """Dimension of the space: the length of a tangent vector."""
        return self.layout.dimension

    @property
    def names(self) -> tuple[str, ...]:
        """The canonical coordinates' names, e.g. ``("base.x", ..., "base.qw", ...)``."""
        return tuple(c.name for c in self.layout.coordinates)

    @property
    def coordinates(self) -> tuple[Coordinate, ...]:
        """Each canonical coordinate: joint, factor, unit, bounds, wraps."""
        return self.layout.coordinates

    @property
    def joints(self) -> tuple[str, ...]:
        """The joints with coordinates, in tree order."""
        return self.layout.joints

    @property
    def slots(self) -> tuple[Slot, ...]:
        """The factors of the product, in order."""
        return self.layout.slots

    @property
    def tangent_names(self) -> tuple[str, ...]:
        """Names of the tangent coordinates (``base.wx`` for a rotation's x component)."""
        names: list[str] = []
        for slot in self.slots:
            if isinstance(slot.factor, Rotation):
                names.extend(f"{slot.joint}.w{a}" for a in "xyz")
            else:
                names.append(slot.name)
        return tuple(names)

    @cached_property
    def _joint_columns(self) -> dict[str, slice]:
        columns: dict[str, slice] = {}
        for i, c in enumerate(self.layout.coordinates):
            start = columns[c.joint].start if c.joint in columns else i
            columns[c.joint] = slice(start, i + 1)
        return columns

    @cached_property
    def _columns(self) -> _Columns:
        kinds: dict[type, tuple[list[int], list[float]]] = {
            Line: ([], []),
            Circle: ([], []),
            Rotation: ([], []),
        }
        for slot, weight in zip(self.slots, self.weights, strict=True):
            columns, w2 = kinds[type(slot.factor)]
            columns.append(slot.offset)
            w2.append(weight * weight)

        def arrays(kind: type) -> tuple[NDArray[np.int64], FloatArray]:
            columns, w2 = kinds[kind]
            return (
                _readonly(np.array(columns, dtype=np.int64)),
                _readonly(np.array(w2, dtype=np.float64)),
            )

        lines, line_w2 = arrays(Line)
        per_column = np.zeros(self.size)
        per_column[lines] = line_w2
        return _Columns(lines, line_w2, _readonly(per_column), *arrays(Circle), *arrays(Rotation))

    def with_weights(self, weights: Mapping[str, float]) -> ConfigurationSpace:
        """The same space with other metric weights.

        Args:
            weights: Weight (finite, >= 0) by joint name (all its factors) or by factor
                name (``base.rotation``, ``base.x``, ...); others keep theirs.

        Raises:
            UnknownJointError: A name is neither a joint with coordinates nor a factor.
            ConfigurationError: A weight is negative or not finite.
        """
        valid = list(self.joints) + [s.name for s in self.slots if s.name not in self.joints]
        for name, weight in weights.items():
            if name not in valid:
                raise UnknownJointError(
                    f"no joint or factor named '{name}'", name=name, valid=valid
                )
            if not (math.isfinite(weight) and weight >= 0):
                raise ConfigurationError(
                    f"weight of '{name}' must be finite and >= 0, got {weight!r}", coordinate=name
                )
        new = tuple(
            float(weights.get(s.name, weights.get(s.joint, w)))
            for s, w in zip(self.slots, self.weights, strict=True)
        )
        return replace(self, weights=new)

    # --- input checking ------------------------------------------------------------

    def _batch(
        self, x: ArrayLike, what: str = "configuration"
    ) -> tuple[FloatArray, tuple[int, ...]]:
        """The array as a C-contiguous (M, n) float64 array, and its leading shape."""
        return as_rows(x, self.size, f"a {what} of robot '{self.robot}'")

    def _validate(self, rows: FloatArray, lead: tuple[int, ...]) -> None:
        """Raise on NaN/inf or a non-unit quaternion, naming the coordinate and row."""
        check_finite(rows, self.names, lead)
        for slot in self.slots:
            if isinstance(slot.factor, Rotation):
                block = rows[:, slot.offset : slot.offset + 4]
                check_unit(block, slot.name, "quaternion", self.tolerance, lead)

    # --- operations ----------------------------------------------------------------

    def canonicalize(self, x: ArrayLike, out: FloatArray | None = None) -> FloatArray:
        """The canonical form of configurations, shape (..., n) -> (..., n).

        Angles on S^1 go to [-pi, pi); quaternions are normalized and put on the upper
        hemisphere (h and -h give bit-identical output). Idempotent. ``out``: an optional
        C-contiguous float64 array of the result's shape to write into (reused buffers
        spare the allocation of large batches).

        Raises:
            ConfigurationShapeError, NonFiniteValueError, NotUnitQuaternionError.
        """
        from . import kernels

        rows, lead = self._batch(x)
        out = output(out, (*lead, self.size))
        c = self._columns
        bad = kernels.canonicalize(
            rows, c.circles, c.rotations, self.tolerance, out.reshape(rows.shape)
        )
        if bad >= 0:
            self._raise_for_row(bad, lead, rows)
        return out

    def distance(
        self, a: ArrayLike, b: ArrayLike, out: FloatArray | None = None
    ) -> FloatArray | float:
        """The product-metric distance (see the module docstring).

        Args:
            a: Configurations, shape (..., n).
            b: Configurations, shape (..., n), broadcast against ``a``.
            out: Optional C-contiguous float64 array of the leading shape to write into.

        Returns:
            A float for two single configurations, else an array of the leading shape.
        """
        from . import kernels

        (ra, rb), lead = self._broadcast(a, b)
        out = output(out, lead)
        c = self._columns
        bad = kernels.distance(
            ra,
            rb,
            c.w2,
            c.circles,
            c.circle_w2,
            c.rotations,
            c.rotation_w2,
            self.tolerance,
            out.reshape(-1),
        )
        if bad >= 0:
            self._raise_for_row(bad, lead, ra, rb)
        return float(out.reshape(-1)[0]) if lead == () else out

    def interpolate(
        self, a: ArrayLike, b: ArrayLike, t: ArrayLike, out: FloatArray | None = None
    ) -> FloatArray:
        """Points along the shortest path from a to b, canonical.

        Every factor follows its shortest way: R^1 linearly, S^1 across pi ~ -pi when
        shorter, SO(3) by slerp along the shorter of b and -b. t = 0 and t = 1 give
        exactly the canonical a and b.

        Args:
            a: Configurations, shape (..., n).
            b: Configurations, shape (..., n).
            t: Parameters, shape broadcastable with the leading shapes (usually in [0, 1]).
            out: Optional C-contiguous float64 array of the result's shape to write into.

        Returns:
            Shape (*broadcast leading shape, n).
        """
        from . import kernels

        t_arr = np.asarray(t, dtype=np.float64)
        (ra, rb, rt), lead = self._broadcast(a, b, t=t_arr)
        out = output(out, (*lead, self.size))
        c = self._columns
        bad = kernels.interpolate(
            ra,
            rb,
            rt[:, 0],
            c.circles,
            c.rotations,
            self.tolerance,
            out.reshape(math.prod(lead), self.size),
        )
        if bad >= 0:
            if not np.isfinite(rt[min(bad, len(rt) - 1), 0]):
                raise NonFiniteValueError("interpolation parameter t is not finite")
            self._raise_for_row(bad, lead, ra, rb)
        return out

    def difference(self, a: ArrayLike, b: ArrayLike) -> FloatArray:
        """The tangent vector from a to b, shape (..., dimension); ``integrate`` inverts it.

        R^1: b - a; S^1: the signed shortest way in [-pi, pi); SO(3): log(a^-1 b), the
        rotation vector in a's frame, norm in [0, pi].
        """
        (ra, rb), lead = self._broadcast(a, b)
        self._validate(ra, lead)
        self._validate(rb, lead)
        out = np.empty((max(len(ra), len(rb)), self.dimension))
        for slot in self.slots:
            f = slot.factor
            cols = slice(slot.offset, slot.offset + f.size)
            tan = slice(slot.tangent_offset, slot.tangent_offset + f.dimension)
            out[:, tan] = f.difference(unit(f, ra[:, cols]), unit(f, rb[:, cols]))
        return out.reshape(*lead, self.dimension)

    def integrate(self, a: ArrayLike, v: ArrayLike) -> FloatArray:
        """The configuration reached from a along the tangent vector v; canonical.

        Args:
            a: Configurations, shape (..., n).
            v: Tangent vectors, shape (..., dimension).
        """
        rows, lead_a = self._batch(a)
        self._validate(rows, lead_a)
        vs, lead_v = as_rows(v, self.dimension, f"a tangent vector of robot '{self.robot}'")
        check_finite(vs, self.tangent_names, lead_v)
        lead = broadcast_shapes(lead_a, lead_v)
        rows, vs = expand(rows, lead_a, lead), expand(vs, lead_v, lead)
        out = np.empty((max(len(rows), len(vs)), self.size))
        for slot in self.slots:
            f = slot.factor
            cols = slice(slot.offset, slot.offset + f.size)
            tan = slice(slot.tangent_offset, slot.tangent_offset + f.dimension)
            out[:, cols] = f.integrate(unit(f, rows[:, cols]), vs[:, tan])
        return self.canonicalize(out).reshape(*lead, self.size)

    def neutral(self) -> FloatArray:
        """The neutral configuration, shape (n,): 0 clipped into limits, identity rotations."""
        return np.array([c.neutral for c in self.coordinates], dtype=np.float64)

    def sample(
        self,
        n: int,
        rng: np.random.Generator,
        bounds: Mapping[str, tuple[float, float]] | None = None,
    ) -> FloatArray:
        """Draw n configurations uniformly, shape (n, size), canonical.

        Uniform within the limits on R^1 factors, uniform on S^1, Haar-uniform on SO(3).

        Args:
            n: How many.
            rng: The only source of randomness.
            bounds: (lower, upper) by coordinate name (or joint name, for a
                one-coordinate joint), for R^1 coordinates without finite limits (a
                floating base's x, y, z) or to narrow others.

        Raises:
            UnboundedSamplingError: An R^1 coordinate has no finite bounds.
            UnknownJointError: A name in ``bounds`` is not an R^1 or S^1 coordinate.
        """
        from .sampling import resolve_bounds

        if not isinstance(rng, np.random.Generator):
            raise TypeError("rng must be a numpy.random.Generator")
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 0:
            raise ConfigurationError(f"the number of samples must be an integer >= 0, got {n!r}")
        chosen = resolve_bounds(self, bounds or {})
        out = np.empty((int(n), self.size))
        for slot in self.slots:
            f = slot.factor
            cols = slice(slot.offset, slot.offset + f.size)
            out[:, cols] = f.sample(rng, (int(n),), chosen.get(slot.name))
        return out

    def contains(self, x: ArrayLike, tolerance: float = 0.0) -> bool | BoolArray:
        """Whether configurations lie within the joint limits (each bound +- tolerance).

        Returns:
            A bool for one configuration, else a bool array of the leading shape.
        """
        rows, lead = self._batch(x)
        self._validate(rows, lead)
        inside = np.ones(len(rows), dtype=bool)
        for slot in self.slots:
            f = slot.factor
            inside &= f.contains(rows[:, slot.offset : slot.offset + f.size], tolerance)
        return bool(inside[0]) if lead == () else inside.reshape(lead)

    def check(self, x: ArrayLike, tolerance: float = 0.0) -> None:
        """Raise :class:`OutOfLimitsError` for the first coordinate outside its limits.

        For a limited ball joint the value is its rotation angle from the identity (rad).
        """
        rows, lead = self._batch(x)
        self._validate(rows, lead)
        for slot in self.slots:
            f = slot.factor
            block = rows[:, slot.offset : slot.offset + f.size]
            bad = ~f.contains(block, tolerance)
            if not bad.any():
                continue
            row = int(np.argmax(bad))
            if isinstance(f, Rotation):  # a limited ball: its rotation angle, rad
                value = float(rotations.angle_between(block[row], np.array([1.0, 0, 0, 0])))
                lower, upper = 0.0, f.max_angle
            else:
                value, lower, upper = float(block[row, 0]), f.lower, f.upper
            raise OutOfLimitsError(
                coordinate=slot.name,
                joint=slot.joint,
                value=value,
                lower=lower,
                upper=upper,
                row=None if lead == () else row,
            )

    # --- conversions ---------------------------------------------------------------

    def from_pinocchio(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations from Pinocchio's q, shape (..., nq) -> (..., n).

        Quaternions in q are (x, y, z, w); unbounded revolute joints (cos, sin).
        Entries of mimic joints that Pinocchio keeps free are ignored.
        """
        from .pinocchio_q import from_q

        return from_q(self, q)

    def to_pinocchio(self, x: ArrayLike) -> FloatArray:
        """Pinocchio's q of configurations, shape (..., n) -> (..., nq).

        Mimic joints that Pinocchio keeps free get ``multiplier * leader + offset``;
        locked joints their locked value.
        """
        from .pinocchio_q import to_q

        return to_q(self, x)

    def from_dict(self, values: Mapping[str, Any], default: ArrayLike | None = None) -> FloatArray:
        """A canonical configuration, shape (n,), from ``{joint: value}``.

        A value is a number for a one-coordinate joint, else a list in coordinate order
        (planar [x, y, theta]; floating [x, y, z, qw, qx, qy, qz]; spherical [w, x, y, z]).

        Args:
            values: Values by joint name.
            default: Where joints missing from ``values`` take their values (e.g.
                ``space.neutral()``); None: every joint must be given.

        Raises:
            UnknownJointError, MissingJointError, JointValueError, and the errors of
            :meth:`canonicalize`.
        """
        from .mapping import from_mapping

        return from_mapping(self, values, default)

    def to_dict(self, x: ArrayLike) -> dict[str, float | list[float]]:
        """``{joint: value}`` of one configuration, shape (n,), canonicalized first."""
        from .mapping import to_mapping

        return to_mapping(self, x)

    def _rotation_slot(self, name: str) -> Slot:
        """The S^1 or SO(3) factor called ``name`` (or the joint's only such factor)."""
        turning = [s for s in self.slots if not isinstance(s.factor, Line)]
        found = [s for s in turning if s.name == name]
        if not found:
            found = [s for s in turning if s.joint == name]
        if len(found) != 1:
            raise UnknownJointError(
                f"'{name}' is not one S^1 or SO(3) factor",
                name=name,
                valid=[s.name for s in turning],
            )
        return found[0]

    def matrix(self, x: ArrayLike, name: str) -> FloatArray:
        """The rotation matrix of one factor of configurations (..., n).

        Args:
            x: Configurations.
            name: An SO(3) factor (``base.rotation``, a ball joint) or an S^1 factor
                (``base.theta``, a continuous joint); a joint name picks its only one.

        Returns:
            (..., 3, 3) for SO(3), (..., 2, 2) for SO(2) = S^1.
        """
        slot = self._rotation_slot(name)
        rows = self.canonicalize(x)
        block = rows[..., slot.offset : slot.offset + slot.factor.size]
        if isinstance(slot.factor, Rotation):
            return Rotation.matrix_from_wxyz(block)
        return Circle.matrix_from_angle(block)

    def with_matrix(self, x: ArrayLike, name: str, matrix: ArrayLike) -> FloatArray:
        """Configurations (..., n) with one S^1 or SO(3) factor set from rotation matrices.

        Args:
            x: Configurations.
            name: As for :meth:`matrix`.
            matrix: (..., 3, 3) or (..., 2, 2) rotation matrices, broadcast against x.

        Raises:
            NotARotationError: A matrix is not a rotation.
        """
        slot = self._rotation_slot(name)
        r = np.asarray(matrix, dtype=np.float64)
        if isinstance(slot.factor, Rotation):
            value = Rotation.wxyz_from_matrix(r)
        else:
            if (
                r.ndim < 2
                or r.shape[-2:] != (2, 2)
                or not np.all(
                    np.abs(np.einsum("...ji,...jk->...ik", r, r) - np.eye(2)) <= self.tolerance
                )
                or not np.all(np.linalg.det(r) > 0)
            ):
                raise NotARotationError(f"not a 2 x 2 rotation matrix for '{slot.name}'")
            value = Circle.angle_from_matrix(r)
        rows = np.array(self.canonicalize(x))
        lead = broadcast_shapes(rows.shape[:-1], value.shape[:-1])
        rows = np.array(np.broadcast_to(rows, (*lead, self.size)))
        rows[..., slot.offset : slot.offset + slot.factor.size] = value
        return rows

    # --- helpers -------------------------------------------------------------------

    def _broadcast(
        self, *arrays: ArrayLike, t: FloatArray | None = None
    ) -> tuple[list[FloatArray], tuple[int, ...]]:
        """Rows of each array, broadcast so each has 1 or M rows, and the leading shape."""
        batches = [self._batch(a) for a in arrays]
        leads = [lead for _, lead in batches]
        if t is not None:
            leads.append(t.shape)
        lead = broadcast_shapes(*leads)
        rows = [expand(r, lead_r, lead) for r, lead_r in batches]
        if t is not None:
            rows.append(expand(np.ascontiguousarray(t.reshape(-1, 1)), t.shape, lead))
        return rows, lead

    def _raise_for_row(self, row: int, lead: tuple[int, ...], *arrays: FloatArray) -> None:
        for rows in arrays:
            r = row if len(rows) > 1 else 0
            check_finite(rows[r : r + 1], self.names, lead, offset=r)
            for slot in self.slots:
                if isinstance(slot.factor, Rotation):
                    block = rows[r : r + 1, slot.offset : slot.offset + 4]
                    check_unit(block, slot.name, "quaternion", self.tolerance, lead, offset=r)
        raise ConfigurationError(
            "the result is not finite: a coordinate is too large (beyond about 1e154, "
            "squares overflow a double)",
            row=row,
        )


def load(path: str, root_joint: str | None = None) -> ConfigurationSpace:
    """The configuration space of the robot file at ``path``.

    Args:
        path: A robot file (URDF).
        root_joint: None, ``"floating"`` or ``"planar"``: a joint added above the root link.

    Raises:
        RobotFileError: The file cannot be read or is not a valid robot description.
        UnsupportedConfigurationError: A joint has no canonical coordinates.
    """
    from .loader import inspect

    return ConfigurationSpace.from_report(inspect(path, root_joint))
