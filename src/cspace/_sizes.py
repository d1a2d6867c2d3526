"""The one cap on the memory a configuration operation may ask for at once.

Every operation that makes a batch (``sample``, ``interpolate``, ``distance`` and the
others of `ConfigurationSpace`, the functions of
`_rotations`, the conversions) checks the bytes of each array it is about to
allocate, a result or an internal copy, against `MAX_ARRAY_BYTES` before
allocating it, and raises `SizeLimitError` above it. A batch too
large for one call can be processed in chunks; a result written into ``out=`` is not
allocated and so is not capped. This module does not import NumPy.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from cspace.errors import SizeLimitError

MAX_ARRAY_BYTES = 1 << 30
"""Most bytes (1 GiB) that one array allocated by a `cspace` operation may take: 134
million float64 numbers, e.g. ``sample(n)`` of 19 million 7-coordinate configurations."""

FLOAT_BYTES = 8
"""Bytes of one float64 number."""


def check_size(shape: Sequence[int], what: str | None = None, itemsize: int = FLOAT_BYTES) -> None:
    """Raise unless an array of ``shape`` and ``itemsize`` fits in `MAX_ARRAY_BYTES`.

    Args:
        shape: The shape of the array about to be allocated.
        what: What asks for it, for the message (e.g. ``"sample(1,000,000,000)"``);
            default: ``"an array of shape (...)"``.
        itemsize: Bytes per entry.

    Raises:
        SizeLimitError: The array would take more than `MAX_ARRAY_BYTES`.
    """
    requested = math.prod(int(n) for n in shape) * itemsize
    if requested > MAX_ARRAY_BYTES:
        shown = tuple(int(n) for n in shape)
        raise SizeLimitError(
            what or f"an array of shape {shown}", requested=requested, limit=MAX_ARRAY_BYTES
        )
