"""The bounds that sampling uses, factor by factor, checked before any number is drawn."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

from .errors import ConfigurationError, UnboundedSamplingError, UnknownJointError
from .factors import Circle, Line

if TYPE_CHECKING:
    from .space import ConfigurationSpace


def resolve_bounds(
    space: ConfigurationSpace, given: Mapping[str, tuple[float, float]]
) -> dict[str, tuple[float, float]]:
    """(lower, upper) by factor name: every R^1 factor, and the S^1 factors in ``given``.

    Args:
        space: The configuration space.
        given: Bounds by coordinate name (a one-coordinate joint's name is its
            coordinate's name), for R^1 and S^1 coordinates only.

    Raises:
        UnknownJointError: A name is not an R^1 or S^1 coordinate.
        ConfigurationError: Given bounds are not finite or lower > upper.
        UnboundedSamplingError: An R^1 coordinate has no finite bounds.
    """
    scalar = [s.name for s in space.slots if isinstance(s.factor, Line | Circle)]
    for name, pair in given.items():
        if name not in scalar:
            raise UnknownJointError(
                f"cannot bound '{name}': not an R^1 or S^1 coordinate", name=name, valid=scalar
            )
        lower, upper = _pair(name, pair)
        if not (math.isfinite(lower) and math.isfinite(upper) and lower <= upper):
            raise ConfigurationError(
                f"bounds of '{name}' must be finite with lower <= upper, got {pair!r}",
                coordinate=name,
            )
    chosen: dict[str, tuple[float, float]] = {}
    for slot in space.slots:
        if slot.name in given:
            chosen[slot.name] = _pair(slot.name, given[slot.name])
        elif isinstance(slot.factor, Line):
            if not slot.factor.bounded:
                raise UnboundedSamplingError(coordinate=slot.name, joint=slot.joint)
            chosen[slot.name] = (slot.factor.lower, slot.factor.upper)
    return chosen


def _pair(name: str, pair: tuple[float, float]) -> tuple[float, float]:
    try:
        lower, upper = pair
        return float(lower), float(upper)
    except (TypeError, ValueError):
        raise ConfigurationError(
            f"bounds of '{name}' must be a pair (lower, upper), got {pair!r}", coordinate=name
        ) from None
