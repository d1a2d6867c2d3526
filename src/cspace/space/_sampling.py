"""Uniform sampling of a configuration space, its bounds checked before any number is drawn.

Every configuration takes its random numbers in turn from one ``Generator.random`` call
for the whole batch, (n, k) in row-major order, k the numbers one configuration needs
(1 per R^1 or S^1 factor, 3 per SO(3) factor). So the first m configurations of a
sample of n do not depend on n, and sampling in chunks from one generator gives the
same configurations as sampling all at once. The numbers are mapped in one pass by
`_sampling_kernel` (numba) or, for small batches, by the same
arithmetic in plain Python (`sample`): bit-identical, so
which runs does not change a configuration. Limited ball joints are mapped in NumPy.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from cspace._sizes import check_size
from cspace.errors import (
    ArgumentError,
    ArgumentTypeError,
    UnboundedSamplingError,
    UnknownJointError,
)
from cspace.space._arguments import count, generator, real_number
from cspace.space._checks import FloatArray
from cspace.space._geometry.factors import PI, TWO_PI, Circle, Line, Rotation
from cspace.space._geometry.layout import assemble
from cspace.space._sampling_plan import SamplingPlan

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


def sample(
    data: SpaceData,
    n: object,
    rng: object,
    bounds: Mapping[str, tuple[float, float]] | None,
) -> FloatArray:
    """``n`` uniform canonical configurations, shape (n, size); see the module docstring.

    Raises:
        The errors of `cspace.space.ConfigurationSpace.sample`.
    """
    rows = count(n, "the number of samples n")
    rng = generator(rng)
    check_size((rows, data.size), f"sample({rows:,})")
    chosen = resolve_bounds(data, {} if bounds is None else bounds)
    out = np.empty((rows, data.size))
    plan = _plan(data, chosen)
    if plan is None:  # a limited ball joint: NumPy, factor by factor
        u = rng.random((rows, data.layout.draws))
        return assemble(
            data.slots,
            out,
            "columns",
            lambda slot: slot.factor.from_uniform(u[:, slot.draws], chosen.get(slot.name)),
        )
    from cspace.space._compute import rowwise as rowwise

    if not rowwise.takes(rows, data.size, exact=True):
        from cspace.space._compute import sampling_kernel as sampling_kernel

        sampling_kernel.draw_and_map(rng, plan, out, data.layout.draws)
        return out
    u = rng.random((rows, data.layout.draws))
    rowwise.sample(u, plan, out)
    return out


def _plan(data: SpaceData, chosen: Mapping[str, tuple[float, float]]) -> SamplingPlan | None:
    """What the kernels need to sample the space; None when a rotation is a limited ball."""
    lines: list[tuple[int, int, float, float]] = []
    circles: list[tuple[int, int, float, float]] = []
    rotations: list[tuple[int, int]] = []
    for slot in data.slots:
        factor = slot.factor
        if isinstance(factor, Rotation):
            if factor.max_angle < PI:
                return None
            rotations.append((slot.column, slot.draw_column))
            continue
        lower, upper = chosen.get(slot.name, (-PI, PI))
        target = lines if isinstance(factor, Line) else circles
        target.append((slot.column, slot.draw_column, lower, upper - lower))

    def columns(rows: Sequence[tuple[Any, ...]], width: int) -> list[np.ndarray[Any, Any]]:
        table = list(zip(*rows, strict=True)) if rows else [()] * width
        kinds = (np.int64, np.int64, np.float64, np.float64)[:width]
        return [np.array(column, dtype=kind) for column, kind in zip(table, kinds, strict=True)]

    return SamplingPlan(*columns(lines, 4), *columns(circles, 4), *columns(rotations, 2))


def resolve_bounds(
    data: SpaceData, given: Mapping[str, tuple[float, float]]
) -> dict[str, tuple[float, float]]:
    """(lower, upper) by factor name: every R^1 factor, and the S^1 factors in ``given``.

    Args:
        data: The configuration space's data.
        given: Bounds by coordinate name (a one-coordinate joint's name is its
            coordinate's name), for R^1 and S^1 coordinates only: finite, lower <=
            upper, within the joint's limits on R^1, at most one turn (2 pi) on S^1.

    Raises:
        ArgumentTypeError: ``given`` is not a mapping, or a bound is not a number.
        UnknownJointError: A name is not an R^1 or S^1 coordinate.
        ArgumentError: Bounds are not finite, lower > upper, outside the limits, more
            than a turn, or (given or the joint's own) too far apart for a double.
        UnboundedSamplingError: An R^1 coordinate has no finite bounds.
    """
    if not isinstance(given, Mapping):
        raise ArgumentTypeError(
            f"bounds must map coordinate names to (lower, upper), got {type(given).__name__}",
            argument="bounds",
        )
    scalar = {s.name: s.factor for s in data.slots if isinstance(s.factor, Line | Circle)}
    chosen: dict[str, tuple[float, float]] = {}
    for name, pair in given.items():
        factor = scalar.get(name)
        if factor is None:
            raise UnknownJointError(
                f"cannot bound '{name}': not an R^1 or S^1 coordinate",
                name=str(name),
                valid=list(scalar),
            )
        lower, upper = bound_pair(name, pair)
        if isinstance(factor, Line) and not (factor.lower <= lower and upper <= factor.upper):
            raise ArgumentError(
                f"bounds of '{name}' [{lower!r}, {upper!r}] leave its limits "
                f"[{factor.lower!r}, {factor.upper!r}]; bounds can only narrow them",
                argument="bounds",
                coordinate=name,
            )
        if isinstance(factor, Circle) and upper - lower > TWO_PI:
            raise ArgumentError(
                f"bounds of '{name}' [{lower!r}, {upper!r}] span more than one turn (2 pi)",
                argument="bounds",
                coordinate=name,
            )
        chosen[name] = (lower, upper)
    for slot in data.slots:
        if isinstance(slot.factor, Line) and slot.name not in chosen:
            if not slot.factor.bounded:
                raise UnboundedSamplingError(coordinate=slot.name, joint=slot.joint)
            chosen[slot.name] = (slot.factor.lower, slot.factor.upper)
        lower, upper = chosen.get(slot.name, (0.0, 0.0))
        if not math.isfinite(upper - lower):
            raise ArgumentError(
                f"the range [{lower!r}, {upper!r}] of '{slot.name}' is wider than a double "
                "holds: give narrower bounds for it",
                argument="bounds",
                coordinate=slot.name,
            )
    return chosen


def bound_pair(name: str, pair: object, *, strict: bool = False) -> tuple[float, float]:
    """(lower, upper) as finite floats with lower <= upper (lower < upper when ``strict``).

    Raises:
        ArgumentTypeError: Not a pair of real numbers.
        ArgumentError: A bound not finite, or lower above upper (or equal, when ``strict``).
    """
    try:
        low, high = cast("tuple[object, object]", pair)
    except (TypeError, ValueError):
        raise ArgumentTypeError(
            f"bounds of '{name}' must be a pair (lower, upper), got {pair!r}",
            argument="bounds",
            coordinate=name,
        ) from None
    lower = real_number(low, f"lower bound of '{name}'", coordinate=name)
    upper = real_number(high, f"upper bound of '{name}'", coordinate=name)
    if lower > upper or (strict and lower == upper):
        relation = "<" if strict else "<="
        raise ArgumentError(
            f"bounds of '{name}' must have lower {relation} upper, got ({lower!r}, {upper!r})",
            argument="bounds",
            coordinate=name,
        )
    return lower, upper
