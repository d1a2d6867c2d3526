"""A robot's configuration space as the product of its factors, with batched operations.

A configuration is a float64 array of shape ``(n,)``, with ``n = space.size``
canonical coordinates (see `_layout` for their order and names); a batch
has shape ``(N, n)`` (any leading axes work). Tangent vectors have ``space.dimension``
entries, factor by factor: R^1 and S^1 one each, SO(3) the rotation vector of a^-1 b in
the frame of a (rad). Angles in rad, lengths in m, quaternions (w, x, y, z).

The metric is the weighted product metric:
``d(a, b) = sqrt(sum over factors f of (w_f * d_f(a_f, b_f))^2)`` with ``d_f`` = |b - a|
on R^1, the shortest way round on S^1 (in [0, pi]), and the rotation angle of a^-1 b on
SO(3) (in [0, pi], h and -h one point); ``w_f`` is the weight of the factor's joint
(default 1; see `ConfigurationSpace.with_weights`).

Distance, interpolation and canonicalization run in compiled kernels
(`_kernels`), or for a few rows in plain Python
(`_rowwise`: no numba to load); everything else delegates factor by
factor to
`_factors`, whole batches at a time. Every method hands the space's data
(`SpaceData`, built once from the fields) to the module that does the work.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from cspace._factor_kinds import Coordinate
from cspace.space import _validation as validation
from cspace.space._checks import (
    BoolArray,
    FloatArray,
)
from cspace.space._compute import engines as engines
from cspace.space._data import SpaceData, check_fields, neutral, space_data
from cspace.space._geometry.layout import Layout, Slot
from cspace.space._geometry.rotations import UNIT_TOLERANCE

if TYPE_CHECKING:
    from cspace._findings import Diagnostic
    from cspace._model.closure import LoopModel
    from cspace._reports.report import JointReport, Report
    from cspace._slots import MujocoLayout
    from cspace.space._closure import Closure
    from cspace.space._conventions._conventions import Conventions
    from cspace.space._ompl import OmplSpace


@dataclass(frozen=True, eq=False)
class ConfigurationSpace:
    """The configuration space of one robot: C = product of its joints' factors.

    Build it with `cspace.load` (or `from_report`). Immutable.

    Attributes:
        robot: The robot's name.
        layout: Coordinates, factors, and how they map to Pinocchio's q.
        nq: Length of Pinocchio's q.
        weights: One metric weight per factor (``layout.slots``): finite, >= 0, with a
            square a double holds.
        other_joints: Joints without coordinates (fixed, mimic, locked), for messages.
        tolerance: How far a quaternion's norm may be from 1 in inputs, in [0, 1).
        report_joints: The report's joints (kinds, mimic relations, Pinocchio's v
            layout), for `conventions`.
        mujoco: MuJoCo's qpos/qvel layout when the robot came from an MJCF file.
        source_format: The robot file's format (``urdf``, ``xacro``, ``mjcf``, ``sdf``, ``usd``),
            for the conventions whose order depends on it (Drake's); empty when unknown.
        drake_findings: The report's findings on where Drake's model of the file
            differs (``drake-mjcf-differs``, ``drake-urdf-differs``), which its Drake
            convention carries.
        loops: What the mechanism's loop constraints are built from (the tree's
            Pinocchio model and the cuts), when the robot file closes loops and was
            loaded with `cspace.space.load`; None otherwise (see `closure`).

    Raises:
        ArgumentError, ArgumentTypeError: On construction (also by
            ``dataclasses.replace``), weights or tolerance that are not so.
    """

    robot: str
    layout: Layout
    nq: int
    weights: tuple[float, ...]
    other_joints: tuple[str, ...] = ()
    tolerance: float = UNIT_TOLERANCE
    report_joints: tuple[JointReport, ...] = ()
    mujoco: MujocoLayout | None = None
    source_format: str = ""
    drake_findings: tuple[Diagnostic, ...] = ()
    loops: LoopModel | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        check_fields(self.layout, self.weights, self.tolerance)

    @classmethod
    def from_report(cls, report: Report) -> ConfigurationSpace:
        """The configuration space of a report's robot.

        Raises:
            ArgumentTypeError: ``report`` is not a `Report`.
            RobotHasErrorsError: The report has error-level findings (an empty or
                non-finite limit, an invalid axis): its space is not well defined.
            UnsupportedConfigurationError: A joint has no canonical coordinates (an
                Euler-angle spherical joint), or a mimic joint's leader has several.
            JointMatchError: An MJCF file's report whose joints are not at the qpos and
                qvel entries MuJoCo gives them (an edited saved report).
        """
        from cspace.space._of_report import space_parts

        return cls(*space_parts(report))

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
        return self._data.names

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
        return self._data.tangent_names

    @cached_property
    def _data(self) -> SpaceData:
        """What the helpers work on, built once from the fields, when first used."""
        return space_data(
            self.robot,
            self.layout,
            self.nq,
            self.weights,
            self.other_joints,
            self.tolerance,
            self.report_joints,
            self.mujoco,
            self.source_format,
            self.drake_findings,
        )

    @cached_property
    def closure(self) -> Closure | None:
        """The mechanism's loop-closure constraints (a `cspace.space.Closure`), or None.

        None for a tree, and for a space without the robot's model: one made by
        `from_report` (a saved report holds the mechanism's summary, not its model: load
        the robot file with `cspace.space.load`), or a group's space (``group=``). None
        too when the report's closure was not searched (finding ``closure-not-analysed``:
        a reader that does not place every joint, constraints costlier than cspace spends).
        """
        if self.loops is None:
            return None
        from cspace.space._closure import Closure

        return Closure(self._data, self.loops, self)

    def __getstate__(self) -> dict[str, Any]:
        """The fields, without what is derived from them (rebuilt after unpickling)."""
        return {k: v for k, v in self.__dict__.items() if k not in ("_data", "closure")}

    def with_weights(self, weights: Mapping[str, float]) -> ConfigurationSpace:
        """The same space with other metric weights.

        Args:
            weights: Weight (finite, >= 0, with a square a double holds: < 1.3e154) by
                joint name (all its factors) or by factor name (``base.rotation``,
                ``base.x``, ...); others keep theirs.

        Raises:
            ArgumentTypeError: ``weights`` is not a mapping, or a weight not a number.
            UnknownJointError: A name is neither a joint with coordinates nor a factor.
            ArgumentError: A weight is negative, not finite, or too large.
        """
        new = validation.reweighted(self._data, weights)
        return replace(self, weights=new)

    # --- operations ----------------------------------------------------------------

    def canonicalize(self, x: ArrayLike, out: FloatArray | None = None) -> FloatArray:
        """The canonical form of configurations, shape (..., n) -> (..., n).

        Angles on S^1 go to [-pi, pi); quaternions are normalized and put on the upper
        hemisphere (h and -h give bit-identical output). Idempotent. ``out``: an optional
        C-contiguous float64 array of the result's shape to write into (reused buffers
        spare the allocation of large batches).

        ``out`` may be the input array itself (canonicalized in place), but no other
        array that overlaps it.

        Raises:
            ConfigurationError: ``x`` is of the wrong type or shape, not finite, holds a
                quaternion that is not unit, or is too large (``ArgumentTypeError``,
                ``ConfigurationShapeError``, ``NonFiniteValueError``,
                ``NotUnitQuaternionError``, ``SizeLimitError``).
            ArgumentError: ``out`` overlaps ``x``.
        """
        return engines.canonicalize(self._data, x, out)

    def distance(
        self, a: ArrayLike, b: ArrayLike, out: FloatArray | None = None
    ) -> FloatArray | float:
        """The product-metric distance (see the module docstring).

        Args:
            a: Configurations, shape (..., n).
            b: Configurations, shape (..., n), broadcast against ``a``.
            out: Optional C-contiguous float64 array of the leading shape to write into,
                overlapping neither input.

        Returns:
            A float for two single configurations, else an array of the leading shape.

        Raises:
            ConfigurationError: An input of the wrong type or shape, not finite, with a
                quaternion that is not unit, or too large (as `canonicalize`).
            ArgumentError: ``out`` overlaps an input.
            ValueOverflowError: The weighted squares overflow a double.
        """
        return engines.distance(self._data, a, b, out)

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
            t: Parameters, finite, shape broadcastable with the leading shapes (usually
                in [0, 1]; outside it, the path is extended).
            out: Optional C-contiguous float64 array of the result's shape to write into,
                overlapping no input.

        Returns:
            Shape (*broadcast leading shape, n).

        Raises:
            ConfigurationError: An input of the wrong type or shape, not finite (``t``
                too), with a quaternion that is not unit, or too large.
            ArgumentError: ``out`` overlaps an input.
            ValueOverflowError: A point is beyond a double.
        """
        return engines.interpolate(self._data, a, b, t, out)

    def difference(self, a: ArrayLike, b: ArrayLike) -> FloatArray:
        """The tangent vector from a to b, shape (..., dimension); ``integrate`` inverts it.

        R^1: b - a; S^1: the signed shortest way in [-pi, pi); SO(3): log(a^-1 b), the
        rotation vector in a's frame, norm in [0, pi]. Batches broadcast.

        Raises:
            ConfigurationError: As for `distance`.
        """
        from cspace.space._geometry.tangents import difference

        return difference(self._data, a, b)

    def integrate(self, a: ArrayLike, v: ArrayLike) -> FloatArray:
        """The configuration reached from a along the tangent vector v; canonical.

        Args:
            a: Configurations, shape (..., n).
            v: Tangent vectors, shape (..., dimension), broadcast against ``a``.

        Raises:
            ConfigurationError: As for `distance`.
        """
        from cspace.space._geometry.tangents import integrate

        return integrate(self._data, a, v)

    def neutral(self) -> FloatArray:
        """The neutral configuration, shape (n,): 0 clipped into limits, identity rotations."""
        return neutral(self._data)

    def sample(
        self,
        n: int,
        rng: np.random.Generator,
        bounds: Mapping[str, tuple[float, float]] | None = None,
    ) -> FloatArray:
        """Draw n configurations uniformly, shape (n, size), canonical.

        Uniform within the limits on R^1 factors, uniform on S^1, Haar-uniform on SO(3).
        Each configuration takes its random numbers from ``rng.random`` in turn, so
        drawing n1 then n2 from a generator gives the same configurations as drawing
        n1 + n2 from one in the same state: results do not depend on chunking.

        Args:
            n: How many (an integer >= 0).
            rng: The only source of randomness.
            bounds: (lower, upper) by coordinate name (or joint name, for a
                one-coordinate joint), for R^1 coordinates without finite limits (a
                floating base's x, y, z) or to narrow others (within the limits).

        Raises:
            ArgumentTypeError: ``n`` is not an integer, ``rng`` not a Generator.
            ArgumentError: ``n`` < 0, or bad bounds (see
                `resolve_bounds`).
            SizeLimitError: The result would be larger than ``cspace.MAX_ARRAY_BYTES``.
            UnboundedSamplingError: An R^1 coordinate has no finite bounds.
            UnknownJointError: A name in ``bounds`` is not an R^1 or S^1 coordinate.
        """
        from cspace.space._sampling import sample

        return sample(self._data, n, rng, bounds)

    def contains(self, x: ArrayLike, tolerance: float = 0.0) -> bool | BoolArray:
        """Whether configurations lie within the joint limits (each bound +- tolerance).

        Args:
            x: Configurations, shape (..., n).
            tolerance: Slack on each bound (finite, >= 0), in the coordinate's unit.

        Returns:
            A bool for one configuration, else a bool array of the leading shape.
        """
        return validation.contains(self._data, x, tolerance)

    def check(self, x: ArrayLike, tolerance: float = 0.0) -> None:
        """Raise `OutOfLimitsError` for the first coordinate outside its limits.

        For a limited ball joint the value is its rotation angle from the identity (rad).
        ``tolerance`` as for `contains`.
        """
        validation.check(self._data, x, tolerance)

    # --- conversions ---------------------------------------------------------------

    def from_pinocchio(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations from Pinocchio's q, shape (..., nq) -> (..., n).

        Quaternions in q are (x, y, z, w); unbounded revolute joints (cos, sin).
        Entries of mimic joints that Pinocchio keeps free are ignored.
        """
        from cspace.space._conventions._pinocchio import from_q

        return from_q(self._data, q)

    def to_pinocchio(self, x: ArrayLike) -> FloatArray:
        """Pinocchio's q of configurations, shape (..., n) -> (..., nq).

        Mimic joints that Pinocchio keeps free get ``multiplier * leader + offset``;
        locked joints their locked value.
        """
        from cspace.space._conventions._pinocchio import to_q

        return to_q(self._data, x)

    def conventions(self, mujoco: object = None) -> Conventions:
        """Maps between this robot's conventions.

        Canonical, Pinocchio, MuJoCo, Drake, Isaac, PyBullet, named.

        Args:
            mujoco: Where MuJoCo keeps the joints, for a robot not read from MJCF (a
                URDF whose MuJoCo model has the same joint names): an MJCF file's path or
                report, a ``mujoco.MjModel`` or a
                `MujocoLayout`. None: the robot's own MJCF
                layout, if it has one.

        Returns:
            A `Conventions`.

        Raises:
            JointMatchError: The MuJoCo model's joints do not match the robot's.
        """
        from cspace.space._conventions._conventions import conventions_of

        return conventions_of(self, self._data, mujoco)

    def to_ompl(self, bounds: Mapping[str, tuple[float, float]] | None = None) -> OmplSpace:
        """This C-space as an OMPL state space, with maps to and from its states.

        One subspace per factor (real vector, SO(2), SO(3)), weighted by this space's
        weights; see `cspace.space` for how OMPL's distance relates to this one's. It is
        the tree's space: for a mechanism with loops, ``closure.to_ompl`` gives OMPL's
        constrained planning its constraint (`cspace.space.Closure.to_ompl`).

        Args:
            bounds: (lower, upper) by coordinate name for lines without limits.

        Raises:
            UnboundedSamplingError: A line has neither limits nor bounds.
            ArgumentError: OMPL's Python bindings are not installed (``pip install ompl``).
        """
        from cspace.space._ompl import ompl_space

        return ompl_space(self._data, bounds, self)

    def from_dict(self, values: Mapping[str, Any], default: ArrayLike | None = None) -> FloatArray:
        """A canonical configuration, shape (n,), from ``{joint: value}``.

        A value is a number for a one-coordinate joint, else a list in coordinate order
        (planar [x, y, theta]; floating [x, y, z, qw, qx, qy, qz]; spherical [w, x, y, z]).

        Args:
            values: Values by joint name.
            default: Where joints missing from ``values`` take their values (e.g.
                ``space.neutral()``); None: every joint must be given.

        Raises:
            ConfigurationError: A joint unknown (``UnknownJointError``) or missing
                (``MissingJointError``), a value of the wrong shape (``JointValueError``),
                or as `canonicalize`.
        """
        from cspace.space._mapping import from_mapping

        return from_mapping(self._data, values, default)

    def to_dict(self, x: ArrayLike) -> dict[str, float | list[float]]:
        """``{joint: value}`` of one configuration, shape (n,), canonicalized first."""
        from cspace.space._mapping import to_mapping

        return to_mapping(self._data, x)

    def matrix(self, x: ArrayLike, name: str) -> FloatArray:
        """The rotation matrix of one factor of configurations (..., n).

        Args:
            x: Configurations.
            name: An SO(3) factor (``base.rotation``, a ball joint) or an S^1 factor
                (``base.theta``, a continuous joint); a joint name picks its only one.

        Returns:
            (..., 3, 3) for SO(3), (..., 2, 2) for SO(2) = S^1.
        """
        from cspace.space._geometry.matrices import matrix

        return matrix(self._data, x, name)

    def with_matrix(self, x: ArrayLike, name: str, matrix: ArrayLike) -> FloatArray:
        """Configurations (..., n) with one S^1 or SO(3) factor set from rotation matrices.

        Args:
            x: Configurations.
            name: As for `matrix`.
            matrix: (..., 3, 3) or (..., 2, 2) rotation matrices, broadcast against x.

        Raises:
            ConfigurationShapeError: The matrices are not 3 x 3 (or 2 x 2).
            NotARotationError: A matrix is not a rotation.
        """
        from cspace.space._geometry.matrices import with_matrix

        return with_matrix(self._data, x, name, matrix)
