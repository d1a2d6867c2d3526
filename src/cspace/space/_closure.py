"""Configurations on a mechanism with loops: `Closure`, ``space.closure``.

A robot whose file closes loops (MJCF ``connect`` and ``weld``, ...) is its kinematic
tree, whose C-space is the `ConfigurationSpace`, and one closing constraint per cut:
the mechanism's configurations are the tree's where every residual row is 0 (an
algebraic variety; LaValle, *Planning Algorithms*, section 4.4). Everything here is in
the space's canonical coordinates and tangent: configurations go to Pinocchio's q
(`ConfigurationSpace.to_pinocchio`), the constraints are evaluated on the tree's
Pinocchio model with a frame on each side of each cut, and results come back
(`ConfigurationSpace.from_pinocchio`), so angles stay wrapped and quaternions unit.

The residual rows are the cuts' in the file's order (as the report's ``closure.cuts``,
less any cut a ``closure-invalid`` finding leaves out): 3 for a ball (``connect``:
the two anchors' offset, m, in the first anchor's frame), 6 for a weld (offset, then
the rotation vector between the frames, rad), 5 for a hinge or a slider.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from cspace._joint_kind import JointKind
from cspace.errors import ArgumentError
from cspace.space._arguments import count, generator, real_number
from cspace.space._checks import BoolArray, FloatArray, as_rows
from cspace.space._compute.engines import canonicalize
from cspace.space._conventions._pinocchio import from_q, to_q
from cspace.space._data import neutral
from cspace.space._geometry.factors import Circle, Line, Rotation
from cspace.space._validation import contains

if TYPE_CHECKING:
    from collections.abc import Iterable, Mapping

    from cspace._model.closure import LoopModel
    from cspace.space._data import SpaceData
    from cspace.space._ompl_constrained import ConstrainedOmplSpace

CLOSED_TOLERANCE = 1e-9
"""Default largest residual row (m, rad) of a configuration that closes the loops."""

MAX_ITERATIONS = 60
"""Default most Levenberg-Marquardt steps of one projection."""

ITERATION_LIMIT = 10_000
"""Most steps a caller may ask of one projection."""


class Closure:
    """The loop-closure constraints of a mechanism, on its tree's configuration space.

    ``space.closure`` of a space `cspace.space.load` made from a robot file with loops;
    None for a tree. A space made by `ConfigurationSpace.from_report` (a saved report
    holds no model) has none either: load the robot file to work on its mechanism (see
    `ConfigurationSpace.closure` for the other cases).

    Configurations are the space's canonical ones, shape (n,) or a batch (..., n), and
    are checked as every operation of the space checks them (shape, finite values,
    unit quaternions). Holds its own Pinocchio data: not for use from two threads at
    once.

    Attributes:
        space: The tree's configuration space (a `ConfigurationSpace`).
        cuts: The closing constraints' names, in row order.
        cut_rows: Each cut's number of rows.
        rows: The residual's length.
    """

    def __init__(self, data: SpaceData, loops: LoopModel, space: object) -> None:
        """The closure of a space's mechanism, from the tree's model and its cuts.

        Args:
            data: The space's data, which every method works on.
            loops: The tree's Pinocchio model and the cuts.
            space: The `ConfigurationSpace` itself, which the closure names and never calls.
        """
        from cspace.space._conventions._joint_blocks import joint_blocks

        self.space: Any = space
        self._data = data
        self._constraints = loops.constraints()
        self.cuts: tuple[str, ...] = tuple(cut.name for cut in loops.cuts)
        self.cut_rows: tuple[int, ...] = tuple(cut.rows for cut in loops.cuts)
        self.rows: int = int(self._constraints.rows)
        lower, upper = np.full(data.nq, -np.inf), np.full(data.nq, np.inf)
        for slot in data.slots:
            if isinstance(slot.factor, Line):
                coordinate = data.coordinates[slot.column]
                lower[slot.q_index], upper[slot.q_index] = coordinate.lower, coordinate.upper
        self._bounds = (lower, upper)
        self._blocks, self._followers = joint_blocks(data)
        self._to_v = self._constant_to_v()
        self._plan = self._q_plan()

    def _velocity_map(self, xs: FloatArray) -> FloatArray:
        """Pinocchio's v of each unit tangent vector at each configuration: (M, dim, nv)."""
        from cspace.space._conventions._pinocchio import to_v

        dim = self._data.dimension
        if dim == 0:  # no tangent: nothing to map
            return np.zeros((len(xs), 0, self._constraints.nv))
        at = np.repeat(xs, dim, axis=0)
        units = np.tile(np.eye(dim), (len(xs), 1))
        v = to_v(self._data, self._blocks, self._followers, at, units)
        return np.asarray(v).reshape(len(xs), dim, -1)

    def _constant_to_v(self) -> FloatArray | None:
        """The tangent-to-v map when it does not depend on the configuration, else None.

        It depends on it only through a floating or planar joint's rotation (Pinocchio's
        v holds their translation in the body frame).
        """
        kinds = {j.kind for j in self._data.report_joints}
        if kinds & {JointKind.FLOATING, JointKind.PLANAR}:
            return None
        return np.asarray(self._velocity_map(neutral(self._data)[None, :])[0])

    def __repr__(self) -> str:
        return f"Closure(robot={self._data.robot!r}, cuts={self.cuts!r}, rows={self.rows})"

    def _q(self, x: ArrayLike) -> tuple[FloatArray, tuple[int, ...]]:
        """Pinocchio's q of configurations (M, nq), and their leading shape."""
        data = self._data
        rows, lead = as_rows(x, data.size, f"a configuration of robot '{data.robot}'")
        return np.atleast_2d(to_q(data, rows)), lead

    def residual(self, x: ArrayLike) -> FloatArray:
        """The closure residual of configurations, shape (..., n) -> (..., rows) (m, rad).

        Raises:
            ConfigurationError: ``x`` is not configurations of the space (as
                `ConfigurationSpace.to_pinocchio`).
        """
        qs, lead = self._q(x)
        out = np.empty((len(qs), self.rows))
        for i, q in enumerate(qs):
            out[i] = self._constraints.residual(q)
        return out.reshape(*lead, self.rows)

    def jacobian(self, x: ArrayLike) -> FloatArray:
        """The residual's Jacobian in the space's tangent coordinates, (..., rows, dimension).

        Column j is the residual's rate along the space's tangent coordinate j
        (``space.tangent_names``; ``space.integrate(x, h e_j)`` moves along it), which
        is Pinocchio's v but for a floating or planar joint's translation (world-frame
        rates here, body-frame in Pinocchio's v).

        Raises:
            ConfigurationError: As `residual`.
        """
        qs, lead = self._q(x)
        dim = self._data.dimension
        to_v = (
            np.broadcast_to(self._to_v, (len(qs), *self._to_v.shape))
            if self._to_v is not None
            else self._velocity_map(from_q(self._data, qs))
        )
        out = np.empty((len(qs), self.rows, dim))
        for i, q in enumerate(qs):
            _, jacobian = self._constraints.residual_and_jacobian(q)
            out[i] = jacobian @ to_v[i].T
        return out.reshape(*lead, self.rows, dim)

    def _fast_q(self, x: FloatArray) -> FloatArray:
        """Pinocchio's q of one configuration (n,), unchecked (finite, unit quaternions).

        OMPL's projection calls this thousands of times.
        """
        plan = self._plan
        if plan is None:  # mimic or locked joints: the space's own map fills them
            return np.asarray(to_q(self._data, x))
        q = np.empty(self._data.nq)
        q[plan[0]] = x[plan[1]]
        q[plan[2]] = np.cos(x[plan[3]])
        q[plan[2] + 1] = np.sin(x[plan[3]])
        for qi, col in zip(plan[4], plan[5], strict=True):
            q[qi : qi + 3] = x[col + 1 : col + 4]
            q[qi + 3] = x[col]
        return q

    def _q_plan(self) -> tuple[Any, ...] | None:
        """Index arrays of `_fast_q`: copied entries, (cos, sin) pairs, quaternions."""
        if self._data.layout.fills:
            return None
        copy_q, copy_x, pair_q, pair_x, turn_q, turn_x = [], [], [], [], [], []
        for slot in self._data.slots:
            f = slot.factor
            if isinstance(f, Circle) and f.pinocchio == "cos_sin":
                pair_q.append(slot.q_index)
                pair_x.append(slot.column)
            elif isinstance(f, Rotation):
                turn_q.append(slot.q_index)
                turn_x.append(slot.column)
            else:
                copy_q.append(slot.q_index)
                copy_x.append(slot.column)
        arrays = (copy_q, copy_x, pair_q, pair_x, turn_q, turn_x)
        return tuple(np.asarray(a, dtype=np.intp) for a in arrays)

    def _residual_unchecked(self, x: FloatArray) -> FloatArray:
        """`residual` of one configuration (n,), finite with unit quaternions, unchecked."""
        return np.asarray(self._constraints.residual(self._fast_q(x)))

    def _jacobian_unchecked(self, x: FloatArray) -> FloatArray:
        """`jacobian` of one configuration (n,), finite with unit quaternions, unchecked."""
        q = self._fast_q(x)
        to_v = self._to_v if self._to_v is not None else self._velocity_map(x[None, :])[0]
        _, jacobian = self._constraints.residual_and_jacobian(q)
        return np.asarray(jacobian @ to_v.T)

    def is_closed(self, x: ArrayLike, tolerance: float = CLOSED_TOLERANCE) -> bool | BoolArray:
        """Whether configurations close every loop: each residual row within ``tolerance``.

        Returns:
            A bool for one configuration, else a bool array of the leading shape.

        Raises:
            ArgumentError: ``tolerance`` is negative or not finite.
            ConfigurationError: As `residual`.
        """
        tol = real_number(tolerance, "tolerance", minimum=0.0)
        worst = np.max(np.abs(self.residual(x)), axis=-1, initial=0.0)
        closed = worst <= tol
        return bool(closed) if np.ndim(closed) == 0 else np.asarray(closed)

    def chart(self, x: ArrayLike, joints: Iterable[str]) -> bool | BoolArray:
        """Whether the given joints are coordinates of the mechanism at configurations.

        The joints on no loop count as given too. At a configuration on the mechanism,
        they are when the passive joints' block of the constraint Jacobian has full
        column rank, its rank the constraints': the
        passive joints then follow from the given ones, which move freely. The report's
        ``closure.chart`` answers this for the file's actuated joints.

        Args:
            x: Configurations, shape (..., n).
            joints: Joint names (of joints with coordinates).

        Returns:
            A bool for one configuration, else a bool array of the leading shape.

        Raises:
            ArgumentError: A name that is no joint with coordinates.
            ConfigurationError: As `residual`.
        """
        from cspace._model.closure import is_chart

        by_name = {j.name: j for j in self._data.report_joints if j.v_index is not None}
        columns: list[int] = []
        for name in [joints] if isinstance(joints, str) else joints:
            joint = by_name.get(str(name))
            if joint is None or joint.v_index is None:
                raise ArgumentError(
                    f"'{name}' is no joint with coordinates of the mechanism",
                    argument="joints",
                )
            columns.extend(range(joint.v_index, joint.v_index + joint.nv))
        qs, lead = self._q(x)
        out = np.array(
            [is_chart(self._constraints.residual_and_jacobian(q)[1], columns) for q in qs]
        )
        return bool(out[0]) if not lead else out.reshape(lead)

    def project(
        self,
        x: ArrayLike,
        *,
        tolerance: float = CLOSED_TOLERANCE,
        max_iterations: int = MAX_ITERATIONS,
    ) -> tuple[FloatArray, bool | BoolArray]:
        """Configurations moved onto the constraints, and which of them close the loops.

        Each configuration is moved by Levenberg-Marquardt steps on the residual, in
        the tree's tangent space (angles wrap, quaternions stay unit), each step's
        result clipped into the limits of the joints that have them; it stops when every
        row is within ``tolerance``, after ``max_iterations`` steps, or when no step
        lowers the residual. A configuration that does not converge (the loops cannot
        close near it, or the mechanism cannot assemble at all) comes back where the
        steps left it, with False in the mask: a planner keeps ``projected[closed]``.

        Args:
            x: Configurations, shape (..., n).
            tolerance: The largest residual row (m, rad) counted as closed, > 0.
            max_iterations: Most steps per configuration, in [1, 10000].

        Returns:
            The configurations reached (..., n), canonical; whether each closes the loops
            within ``tolerance`` (a bool for one configuration, else a bool array of the
            leading shape).

        Raises:
            ArgumentError, ArgumentTypeError: A bad ``tolerance`` or ``max_iterations``.
            ConfigurationError: As `residual`.
        """
        tol = real_number(tolerance, "tolerance", minimum=math.ulp(0.0))
        steps = count(max_iterations, "max_iterations", minimum=1)
        if steps > ITERATION_LIMIT:
            raise ArgumentError(
                f"max_iterations must be in [1, {ITERATION_LIMIT}], got {steps}",
                argument="max_iterations",
            )
        qs, lead = self._q(x)
        out = np.empty_like(qs)
        for i, q in enumerate(qs):
            out[i] = self._constraints.project(
                q, self._bounds, tolerance=tol / 2.0, max_iterations=steps
            )[0]
        size = self._data.size
        projected = canonicalize(self._data, from_q(self._data, out), None)
        closed = self.is_closed(projected, tol)
        if lead == ():
            return projected.reshape(size), bool(closed)
        return projected.reshape(*lead, size), np.asarray(closed).reshape(lead)

    def sample(
        self,
        n: int,
        rng: np.random.Generator,
        *,
        attempts: int | None = None,
        bounds: Mapping[str, tuple[float, float]] | None = None,
        tolerance: float = CLOSED_TOLERANCE,
    ) -> FloatArray:
        """Up to n configurations of the mechanism: closed and within the limits.

        Draws configurations of the tree uniformly (`ConfigurationSpace.sample`), projects
        them (`project`) and keeps those that close the loops within ``tolerance`` and
        lie within the limits, until n are kept or ``attempts`` have been drawn. The
        result is not uniform on the mechanism (projection crowds it where the variety
        is steep in the tree's coordinates), but every part of it that a projection
        reaches is covered.

        Args:
            n: How many (>= 0).
            rng: The only source of randomness.
            attempts: Most configurations drawn (default ``20 * n + 20``).
            bounds: As for `ConfigurationSpace.sample` (a floating base's x, y, z).
            tolerance: As for `project`.

        Returns:
            Shape (m, n_coordinates) with m <= n: fewer than n when the attempts ran out
            (none when the mechanism does not assemble); ``len(result)`` says how many.

        Raises:
            ArgumentError, ArgumentTypeError: A bad ``n``, ``rng``, ``attempts`` or
                ``tolerance``; the errors of `ConfigurationSpace.sample`.
        """
        from cspace.space._sampling import sample

        wanted = count(n, "the number of samples n")
        rng = generator(rng)
        most = 20 * wanted + 20 if attempts is None else count(attempts, "attempts")
        kept: list[FloatArray] = []
        drawn = 0
        while len(kept) < wanted and drawn < most:
            chunk = min(most - drawn, 2 * (wanted - len(kept)) + 4)
            drawn += chunk
            starts = sample(self._data, chunk, rng, bounds)
            projected, closed = self.project(starts, tolerance=tolerance)
            inside = np.asarray(contains(self._data, projected, 1e-12)) & np.asarray(closed)
            kept.extend(projected[inside])
        if not kept:
            return np.zeros((0, self._data.size))
        return np.asarray(kept[:wanted])

    def to_ompl(
        self,
        bounds: Mapping[str, tuple[float, float]] | None = None,
        *,
        tolerance: float = 1e-6,
    ) -> ConstrainedOmplSpace:
        """The mechanism for OMPL's constrained planning (a ``ProjectedStateSpace``).

        See `cspace.space.ConstrainedOmplSpace` for the ambient space, the constraint
        given to OMPL, and the maps between its states and configurations.

        Args:
            bounds: (lower, upper) by coordinate name, for lines without limits and for
                circles (default [-2 pi, 2 pi]: a circle is unwrapped in OMPL's space).
            tolerance: OMPL's projection tolerance (the norm of its constraint rows).

        Raises:
            ArgumentError: OMPL's Python bindings are not installed, or no configuration
                closing the loops was found (the constraint's rank is unknown).
            UnboundedSamplingError: A line has neither limits nor bounds.
        """
        from cspace.space._ompl_constrained import Functions, constrained_space

        functions = Functions(
            self._residual_unchecked, self._jacobian_unchecked, self.sample, self.jacobian
        )
        return constrained_space(self._data, functions, self, bounds, tolerance)
