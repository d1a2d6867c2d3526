"""A saved report's JSON, parsed strictly, and its values named in messages.

Strict: UTF-8; no ``NaN``, ``Infinity`` or ``-Infinity``; no number beyond a double
(``1e400``, an integer of more than `MAX_INTEGER_DIGITS` digits, refused before Python
converts it); no key twice in one object; no nesting deeper than Python's recursion
limit. A value named in a message is described in a few words (`describe`), never
quoted whole, and placed by its JSON Pointer (`pointer`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable
from typing import Any, NoReturn

from cspace.errors import ReportFileError

MAX_INTEGER_DIGITS = 309
"""No finite double has more digits before its point; a longer JSON integer is refused
before Python converts it (which takes time quadratic in its length)."""


class _NotStrictJson(ValueError):
    """Raised by the parser's hooks; becomes a `ReportFileError`."""


def _constant(name: str) -> NoReturn:
    raise _NotStrictJson(f"{name} is not a JSON number")


def _integer(text: str) -> int:
    digits = len(text) - text.startswith("-")
    if digits > MAX_INTEGER_DIGITS:
        raise _NotStrictJson(f"an integer of {digits:,} digits is beyond any double")
    return int(text)


def _float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise _NotStrictJson(f"the number {text[:40]} is beyond any double")
    return value


def _object(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    document = dict(pairs)
    if len(document) != len(pairs):
        seen: set[str] = set()
        for key, _ in pairs:
            if key in seen:
                raise _NotStrictJson(f"the key {key!r} appears twice in one object")
            seen.add(key)
    return document


def parse_strict_json(path: str, data: bytes) -> Any:
    """The JSON value of ``data``, parsed strictly (see the module's docstring).

    Raises:
        ReportFileError: Not UTF-8, not JSON, or not strict JSON.
    """
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ReportFileError(path, f"not a JSON report: not UTF-8 (byte {exc.start})") from None
    try:
        return json.loads(
            text,
            parse_constant=_constant,
            parse_int=_integer,
            parse_float=_float,
            object_pairs_hook=_object,
        )
    except json.JSONDecodeError as exc:
        problem = f"not a JSON report: {exc.msg} (column {exc.colno})"
        raise ReportFileError(path, problem, line=exc.lineno) from None
    except _NotStrictJson as exc:
        raise ReportFileError(path, f"not a JSON report cspace reads: {exc}") from None
    except RecursionError:
        raise ReportFileError(path, "not a JSON report cspace reads: nested too deeply") from None


def describe(value: Any) -> str:
    """A short description of a JSON value for a message (never a huge or deep repr)."""
    if value is None or isinstance(value, bool):
        return json.dumps(value)
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return repr(value) if len(value) <= 40 else f"{value[:40]!r}... ({len(value):,} chars)"
    if isinstance(value, list):
        return f"an array of {len(value):,} items"
    return "an object"


def pointer(path: Iterable[str | int]) -> str:
    """The JSON Pointer (RFC 6901) of a path of keys and indices; ``""`` for the root."""
    return "".join("/" + str(part).replace("~", "~0").replace("/", "~1") for part in path)
