"""A mechanism with loops for OMPL's constrained planning: `ConstrainedOmplSpace`.

OMPL plans on an implicit manifold (Kingston, Moll, Kavraki, IJRR 2019) from a
``Constraint`` (a function F of the ambient vector and its Jacobian) over an ambient
space whose state is one dense vector; a ``ProjectedStateSpace`` projects samples and
motions onto F = 0 by Newton's method. Here:

- the ambient space is a ``RealVectorStateSpace`` of the space's canonical coordinates,
  in order: a line within its limits (or the bounds given), a circle as its angle
  *unwrapped* (a path may turn it more than once; bounds [-2 pi, 2 pi] unless given), a
  quaternion (w, x, y, z) as four numbers in [-1, 1];
- F is the closure residual reduced to its rank, then ``|h|^2 - 1`` for each quaternion.
  The residual rows of a mechanism are often dependent (a planar four-bar modelled in
  3-D: 3 rows, rank 2), and OMPL needs independent ones (its co-dimension fixes the
  manifold's dimension, which its atlas and tangent-bundle spaces build charts with).
  At construction, `Closure.sample` finds configurations on the mechanism; at the one
  of highest Jacobian rank r, the SVD ``J = U S V^T`` gives the r leading left singular
  vectors ``U_r``, and F's closure part is ``U_r^T residual``. That is exact when the
  rows' dependence does not change along the mechanism (a planar or spherical linkage,
  whose out-of-plane rows vanish identically); for a linkage whose dependent
  combination turns as it moves (Bennett's), check states with `Closure.is_closed`.
- F's Jacobian is the closure Jacobian (`Closure.jacobian`, in tangent coordinates)
  taken to ambient coordinates: the same column for a line or an angle, and
  ``2 [-v | w I - [v]x] / |h|`` for a quaternion h = (w, v), whose body angular velocity
  that is.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from cspace.errors import ArgumentError, ArgumentTypeError, UnknownJointError
from cspace.space._compute.engines import canonicalize
from cspace.space._geometry.factors import Circle, Line, Rotation
from cspace.space._validation import contains

if TYPE_CHECKING:
    from cspace.space._checks import FloatArray
    from cspace.space._data import SpaceData

SEED = 20_260_404
"""The seed of the configurations the constraint's rank is found at."""

CIRCLE_BOUNDS = (-2.0 * math.pi, 2.0 * math.pi)
"""An unwrapped angle's bounds in the ambient space unless given."""


@dataclass(frozen=True)
class Functions:
    """What the constraint calls of the `Closure`.

    Its residual and Jacobian of one configuration (unchecked), its sampler, and its
    checked Jacobian of a batch.
    """

    residual: Callable[[FloatArray], FloatArray]
    jacobian: Callable[[FloatArray], FloatArray]
    sample: Callable[..., FloatArray]
    jacobians: Callable[[FloatArray], FloatArray]


@dataclass(frozen=True)
class ConstrainedOmplSpace:
    """A mechanism in OMPL's constrained planning (see `Closure.to_ompl`).

    Attributes:
        space: The ``ompl.base.ProjectedStateSpace`` (set up, ready for a planner).
        information: Its ``ompl.base.ConstrainedSpaceInformation`` (give it to
            ``ompl.geometric.SimpleSetup``); its validity checker is `valid`.
        constraint: The ``ompl.base.Constraint`` (ambient dimension n, co-dimension
            `rank` plus one per quaternion).
        ambient: The ``ompl.base.RealVectorStateSpace`` of canonical coordinates.
        closure: The `Closure` it is made from.
        rank: The closure Jacobian's rank the constraint keeps.
        bounds: (lower, upper) of each ambient coordinate.
    """

    space: Any
    information: Any
    constraint: Any
    ambient: Any
    closure: Any = field(repr=False)
    rank: int
    bounds: tuple[tuple[float, float], ...]
    _data: SpaceData = field(repr=False, compare=False, kw_only=True)

    def to_state(self, x: ArrayLike, state: Any = None) -> Any:
        """An OMPL state of one configuration (n,), angles as given (unwrapped too).

        Raises:
            ConfigurationShapeError, NonFiniteValueError: ``x`` is not one configuration.
        """
        from cspace.space._checks import as_rows, check_finite

        data = self._data
        rows, _ = as_rows(x, data.size, f"a configuration of robot '{data.robot}'")
        if rows.shape[0] != 1:
            raise ArgumentError("to_state takes one configuration", argument="x")
        check_finite(rows, list(data.names), ())
        if state is None:
            state = self.space.allocState()
        state.copy(np.ascontiguousarray(rows[0]))
        return state

    def values(self, state: Any) -> FloatArray:
        """The ambient vector of a state (n,): angles unwrapped, quaternions as OMPL left them."""
        n = self._data.size
        return np.array([self.space.getValueAddressAtIndex(state, i) for i in range(n)])

    def from_state(self, state: Any) -> FloatArray:
        """The canonical configuration (n,) of a state: angles wrapped, quaternions unit."""
        return canonicalize(self._data, _normalized(self._data, self.values(state)), None)

    def valid(self, state: Any) -> bool:
        """Whether a state is within the robot's limits (the default validity checker)."""
        x = self.values(state)
        if not np.all(np.isfinite(x)):
            return False
        canonical = canonicalize(self._data, _normalized(self._data, x), None)
        return bool(contains(self._data, canonical, 1e-12))


def _normalized(data: SpaceData, x: FloatArray) -> FloatArray:
    """``x`` with each quaternion scaled to unit length (one of zero length left as is)."""
    out = np.array(x, dtype=float)
    for slot in data.slots:
        if isinstance(slot.factor, Rotation):
            h = out[slot.column : slot.column + 4]
            norm = float(np.linalg.norm(h))
            if norm > 0.0 and math.isfinite(norm):
                out[slot.column : slot.column + 4] = h / norm
    return out


def _quaternion_rate(h: FloatArray) -> FloatArray:
    """The body angular velocity per rate of the unit quaternion h = (w, x, y, z): (3, 4)."""
    w, x, y, z = h
    return 2.0 * np.array([[-x, w, z, -y], [-y, -z, w, x], [-z, y, -x, w]])


class _Reduced:
    """F and its Jacobian on ambient vectors (see the module docstring)."""

    def __init__(self, data: SpaceData, functions: Functions, reduce: FloatArray) -> None:
        self.data = data
        self.functions = functions
        self.reduce = reduce
        self.closing = reduce.shape[0]
        self.rotations = [s for s in data.slots if isinstance(s.factor, Rotation)]
        self.rows = self.closing + len(self.rotations)

    def function(self, x: FloatArray) -> FloatArray:
        unit = _normalized(self.data, x)
        norms = [
            float(x[s.column : s.column + 4] @ x[s.column : s.column + 4]) - 1.0
            for s in self.rotations
        ]
        return np.concatenate([self.reduce @ self.functions.residual(unit), norms])

    def jacobian(self, x: FloatArray) -> FloatArray:
        unit = _normalized(self.data, x)
        tangent = self.reduce @ self.functions.jacobian(unit)
        out = np.zeros((self.rows, self.data.size))
        closing = out[: self.closing]
        for slot in self.data.slots:
            c, t = slot.column, slot.tangent_column
            if isinstance(slot.factor, Rotation):
                norm = float(np.linalg.norm(x[c : c + 4])) or 1.0
                rate = _quaternion_rate(unit[c : c + 4])
                closing[:, c : c + 4] = tangent[:, t : t + 3] @ rate / norm
            else:
                closing[:, c] = tangent[:, t]
        for k, slot in enumerate(self.rotations):
            c = slot.column
            out[self.closing + k, c : c + 4] = 2.0 * x[c : c + 4]
        return out


def _reduction(
    data: SpaceData, functions: Functions, lines: Mapping[str, tuple[float, float]]
) -> tuple[FloatArray, int]:
    """``U_r^T`` (r, rows) at the configuration of highest rank found, and r.

    Raises:
        ArgumentError: No configuration closing the loops was found.
    """
    from cspace._model.closure import rank

    found = functions.sample(8, np.random.default_rng(SEED), attempts=64, bounds=lines)
    if len(found) == 0:
        raise ArgumentError(
            f"robot '{data.robot}': no configuration closing its loops was found, so the "
            "constraint's rank is unknown (the mechanism may not assemble)",
            argument="closure",
        )
    jacobians = functions.jacobians(found)
    ranks = [rank(j) for j in jacobians]
    best = int(np.argmax(ranks))
    u, _, _ = np.linalg.svd(jacobians[best])
    r = ranks[best]
    return np.ascontiguousarray(u[:, :r].T), r


def _ambient_bounds(
    data: SpaceData, bounds: Mapping[str, tuple[float, float]] | None
) -> tuple[list[tuple[float, float]], dict[str, tuple[float, float]]]:
    """(lower, upper) of each canonical coordinate in the ambient space, and by line."""
    from cspace.space._sampling import bound_pair, resolve_bounds

    if bounds is not None and not isinstance(bounds, Mapping):
        raise ArgumentTypeError(
            f"bounds must map coordinate names to (lower, upper), got {type(bounds).__name__}",
            argument="bounds",
        )
    given = dict(bounds or {})
    circles = {s.name for s in data.slots if isinstance(s.factor, Circle)}
    lines = {name: pair for name, pair in given.items() if name not in circles}
    turns = {
        name: bound_pair(name, pair, strict=True) for name, pair in given.items() if name in circles
    }
    limits = resolve_bounds(data, lines)
    out: list[tuple[float, float]] = []
    for slot in data.slots:
        if isinstance(slot.factor, Line):
            out.append(limits[slot.name])
        elif isinstance(slot.factor, Circle):
            out.append(turns.get(slot.name, CIRCLE_BOUNDS))
        elif isinstance(slot.factor, Rotation):
            out.extend([(-1.0, 1.0)] * 4)
        else:  # never: three kinds of factor
            raise UnknownJointError(f"factor '{slot.name}' has no ambient coordinates")
    return out, {s.name: limits[s.name] for s in data.slots if isinstance(s.factor, Line)}


def constrained_space(
    data: SpaceData,
    functions: Functions,
    closure: object,
    bounds: Mapping[str, tuple[float, float]] | None,
    tolerance: float,
) -> ConstrainedOmplSpace:
    """The mechanism's `ConstrainedOmplSpace` (see `Closure.to_ompl`).

    Args:
        data: The configuration space's data.
        functions: The closure's functions the constraint calls.
        closure: The `Closure` itself, which the result names and never calls.
        bounds: As for `Closure.to_ompl`.
        tolerance: As for `Closure.to_ompl`.

    Raises:
        ArgumentError: OMPL's Python bindings are not installed, a bad tolerance, or no
            configuration closes the loops, or they leave no motion.
        UnboundedSamplingError: A line has neither limits nor bounds.
    """
    from cspace.space._arguments import real_number

    tol = real_number(tolerance, "tolerance", minimum=math.ulp(0.0))
    try:
        from ompl import base as ob
    except ImportError:
        raise ArgumentError(
            "an OMPL space needs OMPL's Python bindings: pip install ompl", argument="ompl"
        ) from None
    limits, lines = _ambient_bounds(data, bounds)
    reduce, r = _reduction(data, functions, lines)
    reduced = _Reduced(data, functions, reduce)
    n = data.size
    if reduced.rows >= n:
        raise ArgumentError(
            f"robot '{data.robot}': the loops leave the mechanism no motion (rank {r} in "
            f"dimension {data.dimension}): OMPL has no manifold to plan on",
            argument="closure",
        )

    class _Constraint(ob.Constraint):  # type: ignore[misc]  # OMPL's classes are untyped
        def function(self, x: Any, out: Any) -> None:
            out[:] = reduced.function(np.asarray(x, dtype=float))

        def jacobian(self, x: Any, out: Any) -> None:
            out[:, :] = reduced.jacobian(np.asarray(x, dtype=float))

    constraint = _Constraint(n, reduced.rows, tol)
    ambient = ob.RealVectorStateSpace(n)
    box = ob.RealVectorBounds(n)
    for i, (lower, upper) in enumerate(limits):
        box.setLow(i, lower)
        box.setHigh(i, upper)
    ambient.setBounds(box)
    projected = ob.ProjectedStateSpace(ambient, constraint)
    information = ob.ConstrainedSpaceInformation(projected)
    made = ConstrainedOmplSpace(
        projected, information, constraint, ambient, closure, r, tuple(limits), _data=data
    )
    information.setStateValidityChecker(made.valid)
    projected.setup()
    return made
