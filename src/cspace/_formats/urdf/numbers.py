"""Numbers in URDF, as the specification writes them and as urdfdom reads them.

A URDF number is a C-locale decimal (``-1.5``, ``.5``, ``2e-3``; surrounding XML white
space allowed), and `parse_number` reads ``nan`` and ``inf`` too, which the
reader reports as findings. urdfdom, Pinocchio's parser, is stricter
(`URDFDOM_NUMBER`, `URDFDOM_VECTOR`): what it would refuse is given to it
as `for_urdfdom` writes it.
"""

from __future__ import annotations

import math
import re

_DECIMAL = r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
_NUMBER = rf"(?ia:{_DECIMAL}|[+-]?(?:nan|inf|infinity))"  # compiled on first use (re's cache)
URDFDOM_NUMBER = re.compile(rf"[ \t\n\r]*{_DECIMAL}", re.ASCII)
URDFDOM_VECTOR = re.compile(rf" *{_DECIMAL} +{_DECIMAL} +{_DECIMAL} *", re.ASCII)
_XML_SPACE = " \t\n\r"
_LARGEST = "1.7976931348623157e+308"


def parse_number(text: str) -> float | None:
    """A URDF number, or None when ``text`` is not one.

    Accepts C-locale decimals with optional surrounding XML white space, and ``nan``,
    ``inf``, ``infinity`` in any case; a decimal too large for a double is infinite.
    Underscores, hexadecimal, commas and non-ASCII digits (which Python's ``float``
    would take) are refused.
    """
    stripped = text.strip(_XML_SPACE)
    return float(stripped) if re.fullmatch(_NUMBER, stripped) else None


def urdfdom_accepts(text: str, value: float) -> bool:
    """Whether urdfdom's own number parser accepts ``text``, which reads as ``value``."""
    return math.isfinite(value) and bool(URDFDOM_NUMBER.fullmatch(text))


def for_urdfdom(value: float) -> str:
    """``value`` as urdfdom accepts it: NaN as 0, an infinity as the largest double."""
    if math.isnan(value):
        return "0"
    if math.isinf(value):
        return _LARGEST if value > 0 else "-" + _LARGEST
    return repr(value)
