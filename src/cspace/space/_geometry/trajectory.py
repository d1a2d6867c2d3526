"""Trajectories: the continuous lift of a sequence of configurations, and back.

Canonical coordinates keep each angle in [-pi, pi) and each quaternion on the upper
hemisphere (w >= 0): one representative per configuration, which is what comparing and
storing need. A trajectory needs the opposite: values that change continuously from one
sample to the next. At the wrap, a continuous joint going from 3.1 to -3.1 has moved by
0.08 rad, not 6.2; a quaternion that crosses w = 0 flips sign in canonical form although
the rotation moved a little. The *lift* undoes both:

- every S^1 coordinate is unwrapped: each step is taken as the representative of the
  angle difference in [-pi, pi) (``numpy.unwrap``), so the lift never jumps by more than
  pi between samples;
- every quaternion keeps the sign that is nearer the previous sample's (a positive dot
  product), so the lift never jumps between q and -q;
- lines are left as they are.

The inverse (`wrap`) is the canonical form, sample by sample. Time runs along the
second-to-last axis: a trajectory is (T, n), a batch of trajectories (..., T, n).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace.errors import ConfigurationShapeError
from cspace.space._compute.engines import canonicalize
from cspace.space._geometry.factors import Circle, Rotation
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


def unwrap(data: SpaceData, x: ArrayLike, start: ArrayLike | None = None) -> FloatArray:
    """The continuous lift of canonical configurations (..., T, n), time on axis -2.

    Each sample after the first is the representative of its configuration nearest the
    previous sample's.

    Args:
        data: The robot's configuration space's data.
        x: The trajectory.
        start: The lifted sample just before ``x[..., 0, :]`` (..., n), to continue a
            lift chunk by chunk; None: the first sample is kept in canonical form.

    Raises:
        ConfigurationShapeError: ``x`` has no time axis (fewer than 2 dimensions).
        The errors of `canonicalize`.
    """
    lift = canonicalize(data, x, None).copy()
    if lift.ndim < 2:
        raise ConfigurationShapeError(
            f"a trajectory is (T, {data.size}) samples, got shape {lift.shape}",
            expected=data.size,
            shape=lift.shape,
        )
    before = None
    if start is not None:  # lift [canonical(start), x...], then move it onto start
        before = np.broadcast_to(
            np.asarray(start, dtype=np.float64)[..., None, :], (*lift.shape[:-2], 1, data.size)
        )
        lift = np.concatenate([canonicalize(data, before, None), lift], axis=-2)
    for slot in data.slots:
        block = lift[..., slot.columns]
        if isinstance(slot.factor, Circle):
            block[:] = np.unwrap(block, axis=-2)
            if before is not None:  # start and its canonical form differ by turns
                block += before[..., slot.columns] - block[..., :1, :]
        elif isinstance(slot.factor, Rotation):
            dots = np.sum(block[..., 1:, :] * block[..., :-1, :], axis=-1)
            flips = np.cumprod(np.where(dots < 0.0, -1.0, 1.0), axis=-1)
            block[..., 1:, :] *= flips[..., None]
            if before is not None:  # start and its canonical form differ by a sign
                same = np.sum(before[..., slot.columns] * block[..., :1, :], axis=-1) >= 0.0
                block *= np.where(same, 1.0, -1.0)[..., None]
    return lift if before is None else lift[..., 1:, :]


def wrap(data: SpaceData, lift: ArrayLike) -> FloatArray:
    """The canonical form of a lifted trajectory (..., T, n): `unwrap`'s inverse."""
    return canonicalize(data, lift, None)
