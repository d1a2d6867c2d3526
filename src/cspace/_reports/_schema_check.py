"""A saved report checked against the report's JSON Schema (``cspace schema``), strictly.

An ``integer`` is a JSON integer (``1.0`` is not), and a ``pattern`` must match the
whole string (a final line break included). `_fast_schema` proves a valid report
valid in a tenth of ``jsonschema``'s time; ``jsonschema`` checks whatever it cannot
prove valid, and says what is wrong. ``jsonschema`` is imported only here, when a saved
report is not proved valid at once (about 100 ms), never by ``cspace inspect``.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from functools import cache
from typing import Any

from cspace._reports._fast_schema import QuickSchema, UnsupportedSchemaError
from cspace._reports._strict_json import describe, pointer
from cspace.errors import ReportFileError


def _pattern(validator: Any, pattern: str, instance: Any, schema: Any) -> Iterator[Any]:
    r"""JSON Schema's ``pattern``, whose ``$`` (ECMA-262's) ends the string.

    Python's ``$`` also matches before a final line break, which would let ``"R^1\n"``
    pass for a normal form.
    """
    from jsonschema.exceptions import ValidationError

    if not validator.is_type(instance, "string"):
        return
    found = re.search(pattern, instance)
    if found is None or (pattern.endswith("$") and found.end() != len(instance)):
        yield ValidationError(f"{describe(instance)} does not match {pattern!r}")


_ANNOTATIONS = frozenset({"description", "title"})


def _inline(node: Any, definitions: dict[str, Any]) -> Any:
    """``node`` with each ``{"$ref": "#/$defs/NAME", ...}`` replaced by the definition.

    The same schema (none of its definitions refers to itself), which jsonschema checks
    about twice as fast: resolving a reference costs more than the check it leads to.
    """
    if isinstance(node, list):
        return [_inline(item, definitions) for item in node]
    if not isinstance(node, dict):
        return node
    inlined = {key: _inline(value, definitions) for key, value in node.items() if key != "$ref"}
    if "$ref" not in node:
        return inlined
    target = _inline(definitions[node["$ref"].removeprefix("#/$defs/")], definitions)
    if (target.keys() & inlined.keys()) - _ANNOTATIONS:
        return {"allOf": [target, inlined]}
    return {**target, **inlined}


def inlined(schema: dict[str, Any]) -> dict[str, Any]:
    """``schema`` with its ``$defs`` inlined where they are referred to (`_inline`)."""
    definitions = schema.pop("$defs")
    out: dict[str, Any] = _inline(schema, definitions)
    return out


@cache
def _inlined_schema() -> dict[str, Any]:
    from cspace._schema import report_schema

    return inlined(report_schema())


@cache
def _quick_schema() -> QuickSchema | None:
    """The schema compiled for a quick check, or None if it cannot be."""
    try:
        return QuickSchema(_inlined_schema())
    except UnsupportedSchemaError:
        return None


def strict_validator(schema: dict[str, Any]) -> Any:
    """A ``jsonschema`` validator of ``schema`` (Draft 2020-12), read as cspace reads it.

    An ``integer`` is a JSON integer, and a ``pattern`` matches the whole string.
    """
    import jsonschema  # only here: saved reports are the only JSON that cspace validates

    base = jsonschema.Draft202012Validator
    types = base.TYPE_CHECKER.redefine(
        "integer", lambda _checker, value: isinstance(value, int) and not isinstance(value, bool)
    )
    strict = jsonschema.validators.extend(base, {"pattern": _pattern}, type_checker=types)
    return strict(schema)


@cache
def _validator() -> Any:
    return strict_validator(_inlined_schema())


def _types(expected: str | list[str]) -> str:
    names = [expected] if isinstance(expected, str) else expected
    article = {"array": "an", "integer": "an", "object": "an", "null": ""}
    return " or ".join(f"{article.get(n, 'a')} {n}".strip() for n in names)


def error_message(error: Any) -> str:
    """What a jsonschema error means, without jsonschema's repr of the whole value."""
    rule, rule_value, value = error.validator, error.validator_value, error.instance
    if rule == "type":
        return f"expected {_types(rule_value)}, found {describe(value)}"
    if rule in ("minimum", "maximum"):
        side = "below the minimum" if rule == "minimum" else "above the maximum"
        return f"{describe(value)} is {side} {rule_value}"
    if rule == "enum":
        return f"{describe(value)} is not one of {', '.join(map(json.dumps, rule_value))}"
    if rule == "const":
        return f"{describe(value)} is not {json.dumps(rule_value)}"
    if rule == "pattern":
        return f"{describe(value)} is not of the form the schema gives (see 'cspace schema')"
    if rule in ("maxItems", "minItems"):
        side = "more" if rule == "maxItems" else "fewer"
        return f"an array of {len(value):,} items, {side} than {rule_value:,}"
    if rule == "maxLength":
        return f"a string of {len(value):,} characters, more than {rule_value:,}"
    return str(error.message)  # required, additionalProperties: short, and names keys


def _first_error(document: dict[str, Any]) -> Any:
    """The first error ``jsonschema`` finds in the document (None: valid), found quickly.

    The quick schema proves a valid document valid, or finds the value jsonschema would
    first fail on: jsonschema, ten times slower, checks that value alone (the whole
    document only if it finds that value valid after all).
    """
    quick = _quick_schema()
    if quick is not None:
        if quick.valid(document):
            return None
        where, schema = quick.locate(document)
        value: Any = document
        for step in where:
            value = value[step]
        error = next(iter(_validator().evolve(schema=schema).iter_errors(value)), None)
        if error is not None:
            error.path.extendleft(reversed(where))  # its pointer from the document's root
            return error
    return next(iter(_validator().iter_errors(document)), None)


def check_schema(path: str, document: dict[str, Any]) -> None:
    """Refuse a document the report's JSON Schema does not hold valid.

    Raises:
        ReportFileError: The first value that is not valid, with its JSON Pointer.
    """
    try:
        error = _first_error(document)
        if error is None:
            return
        where, problem = pointer(error.absolute_path), error_message(error)
    except RecursionError:  # a deep value quoted in jsonschema's own message
        where, problem = "", "nested too deeply"
    raise ReportFileError(path, f"not a valid cspace report: {problem}", pointer=where)
