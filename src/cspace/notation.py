"""Reading a C-space written by a person, e.g. ``R^6 × T^1``, into a `NormalForm`.

Grammar: factors separated by ``×``, ``x`` or ``*`` (spaces optional). A factor is

- ``R`` or ``R^n`` (n lines or intervals),
- ``S^1`` (a circle), ``T^n`` (the n-torus, n circles), ``(S^1)^n``,
- ``RP^3`` or ``(RP^3)^n``, ``SO(3)`` (= RP^3), ``SO(2)`` (= S^1),
- ``SE(2)`` (= R^2 × S^1), ``SE(3)`` (= R^3 × RP^3),
- ``point`` (nothing; the space of a robot without moving joints).

Exponents may be written as Unicode superscripts (``R⁶``). Products commute up to
homeomorphism, so the order of factors does not matter: ``T^1 x R^6`` == ``R^6 × S^1``.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from cspace._manifold import NormalForm
from cspace.errors import NotationError

__all__ = ["NotationError", "expectation_failures", "parse_notation"]

_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹", "0123456789")
_SEPARATOR = re.compile(r"[×x*]")  # no factor's name contains an x

_POWER = r"(?:\^?(\d+))?"
_FACTORS: tuple[tuple[re.Pattern[str], Callable[[int], NormalForm]], ...] = (
    (re.compile(rf"R{_POWER}"), lambda n: NormalForm(r=n)),
    (re.compile(r"S\^?1"), lambda n: NormalForm(t=1)),
    (re.compile(r"\(S\^?1\)\^?(\d+)"), lambda n: NormalForm(t=n)),
    (re.compile(r"T\^?(\d+)"), lambda n: NormalForm(t=n)),
    (re.compile(r"RP\^?3"), lambda n: NormalForm(rp3=1)),
    (re.compile(r"\(RP\^?3\)\^?(\d+)"), lambda n: NormalForm(rp3=n)),
    (re.compile(r"SO\(3\)"), lambda n: NormalForm(rp3=1)),
    (re.compile(r"SO\(2\)"), lambda n: NormalForm(t=1)),
    (re.compile(r"SE\(3\)"), lambda n: NormalForm(r=3, rp3=1)),
    (re.compile(r"SE\(2\)"), lambda n: NormalForm(r=2, t=1)),
    (re.compile(r"point"), lambda n: NormalForm()),
)


def _factor(term: str, text: str) -> NormalForm:
    for pattern, make in _FACTORS:
        found = pattern.fullmatch(term)
        if found:
            power = found.group(1) if found.groups() else None
            return make(1 if power is None else int(power))
    hint = ""
    if re.fullmatch(r"S\^?\d+", term):
        hint = " (only the circle S^1 is a joint's factor; write T^n for n circles)"
    raise NotationError(
        text,
        f"'{term}' is not a factor{hint}; use R^n, S^1, T^n, RP^3, (RP^3)^n, SO(3), "
        "SE(2), SE(3) or point, separated by × or x",
    )


def parse_notation(text: str) -> NormalForm:
    """The normal form of a product written like ``R^6 × T^1`` or ``R^6xS^1``.

    Args:
        text: The written space.

    Returns:
        Its normal form ``R^a × T^b × (RP^3)^c``.

    Raises:
        NotationError: The text is empty or has a term that is not a factor.
    """
    cleaned = text.translate(_SUPERSCRIPTS).strip()
    if not cleaned:
        raise NotationError(text, "it is empty")
    terms = [t.replace(" ", "") for t in _SEPARATOR.split(cleaned)]
    if any(not t for t in terms):
        raise NotationError(text, "a product sign has no factor on one side")
    return NormalForm.product([_factor(t, text) for t in terms])


def expectation_failures(
    manifold: NormalForm,
    expected: NormalForm | None = None,
    dimension: int | None = None,
) -> list[str]:
    """Why a robot's C-space does not meet what a team pinned; empty when it does.

    Args:
        manifold: The robot's C-space.
        expected: The space it must be (up to the order of factors), or None.
        dimension: The dimension it must have, or None.

    Returns:
        One sentence per failed expectation.
    """
    failures = []
    if expected is not None and expected != manifold:
        failures.append(f"C-space is {manifold.notation}, expected {expected.notation}")
    if dimension is not None and dimension != manifold.dimension:
        failures.append(f"dimension is {manifold.dimension}, expected {dimension}")
    return failures
