"""Checking the arguments of configuration operations that are not configurations.

Counts, the random generator, tolerances, metric weights and the interpolation
parameter ``t``. A wrong type raises `ArgumentTypeError` (also a
``TypeError``), a wrong value `ArgumentError` (also a
``ValueError``); both name the parameter. Bools are not numbers here, though Python
and NumPy would take True as 1.
"""

from __future__ import annotations

import math
import numbers
import sys

import numpy as np
from numpy.typing import ArrayLike

from cspace._sizes import check_size
from cspace.errors import ArgumentError, ArgumentTypeError, NonFiniteValueError
from cspace.space._checks import FloatArray, real_array


def count(n: object, name: str, minimum: int = 0) -> int:
    """``n`` as a Python int, ``minimum <= n <= sys.maxsize`` (NumPy's largest length).

    Args:
        n: A Python int or NumPy integer (not a bool, float or string).
        name: The parameter, for messages.
        minimum: The smallest value allowed.

    Raises:
        ArgumentTypeError: ``n`` is not an integer.
        ArgumentError: ``n`` is below ``minimum`` or above ``sys.maxsize``.
    """
    if isinstance(n, bool | np.bool_) or not isinstance(n, int | np.integer):
        raise ArgumentTypeError(
            f"{name} must be an integer, got {type(n).__name__} {_shown(n)}", argument=name
        )
    if not minimum <= n <= sys.maxsize:
        raise ArgumentError(
            f"{name} must be in [{minimum}, {sys.maxsize}], got {_shown(n)}", argument=name
        )
    return int(n)


def generator(rng: object) -> np.random.Generator:
    """``rng`` when it is a ``numpy.random.Generator``, the only source of randomness.

    Raises:
        ArgumentTypeError: Anything else (a seed, ``numpy.random.RandomState``, None).
    """
    if not isinstance(rng, np.random.Generator):
        raise ArgumentTypeError(
            "rng must be a numpy.random.Generator (e.g. numpy.random.default_rng(seed)), "
            f"got {type(rng).__name__} {_shown(rng)}",
            argument="rng",
        )
    return rng


def real_number(
    value: object,
    name: str,
    *,
    minimum: float = -math.inf,
    below: float = math.inf,
    coordinate: str | None = None,
) -> float:
    """``value`` as a finite float with ``minimum <= value < below``.

    Args:
        value: A Python or NumPy real number (not a bool).
        name: What it is, for messages (``"tolerance"``, ``"weight of 'base'"``).
        minimum: The smallest value allowed.
        below: Values must be smaller than this.
        coordinate: The coordinate or joint it belongs to, if any (kept on the error).

    Raises:
        ArgumentTypeError: ``value`` is not a real number.
        ArgumentError: ``value`` is NaN, infinite, beyond a double, or out of range.
    """
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise ArgumentTypeError(
            f"{name} must be a real number, got {type(value).__name__} {_shown(value)}",
            argument=name,
            coordinate=coordinate,
        )
    try:
        v = float(value)
    except OverflowError:  # an int beyond a double
        v = math.inf if value > 0 else -math.inf  # type: ignore[operator]
    if not (math.isfinite(v) and minimum <= v < below):
        if below < math.inf:
            bounds = f" and in [{minimum:g}, {below:g})"
        else:
            bounds = f" and >= {minimum:g}" if minimum > -math.inf else ""
        raise ArgumentError(
            f"{name} must be finite{bounds}, got {_shown(value)}",
            argument=name,
            coordinate=coordinate,
        )
    return v


def weight(value: object, name: str) -> float:
    """A metric weight: finite, >= 0, and with a square that a double holds (< 1.3e154).

    Raises:
        ArgumentTypeError, ArgumentError: As `real_number`; a weight whose square
            overflows is an ArgumentError.
    """
    w = real_number(value, f"weight of '{name}'", minimum=0.0, coordinate=name)
    if not math.isfinite(w * w):
        raise ArgumentError(
            f"weight of '{name}' is {w!r}: its square, which the metric uses, overflows a double",
            argument="weights",
            coordinate=name,
        )
    return w


def parameters(t: ArrayLike, what: str = "interpolation parameter t") -> FloatArray:
    """``t`` as a float64 array of any shape, every entry finite.

    Raises:
        ArgumentTypeError: ``t`` is not an array of real numbers.
        NonFiniteValueError: An entry is NaN or infinite.
    """
    arr = real_array(t, what)
    check_size(arr.shape, what)  # its float64 rows come next; a broadcast view has none
    finite = np.isfinite(arr)
    if not finite.all():
        index = int(np.argmax(~finite.reshape(-1)))
        raise NonFiniteValueError(
            f"{what} is not finite: {float(arr.reshape(-1)[index])!r}",
            coordinate="t",
            row=None if arr.ndim == 0 else index,
        )
    return arr


def _shown(value: object) -> str:
    """``repr(value)``, shortened: messages stay one short line whatever was passed."""
    text = repr(value) if not isinstance(value, int) or abs(value) < 10**30 else "(a huge int)"
    text = " ".join(text.split())
    return text if len(text) <= 80 else text[:77] + "..."
