"""A quick reading of the report's JSON Schema: is a document valid, and if not, where.

``jsonschema`` takes about 4.4 µs a JSON value: 2.2 s for a saved report of half a
million values, twice that for a diff of two. `QuickSchema` compiles the same
schema (``cspace schema``, its ``$ref`` inlined) into nested Python functions that take
about a tenth of that. It proves a valid document valid; for any other, it finds the
value where ``jsonschema`` would report its first error (keywords in the schema's order,
as ``jsonschema`` reads them), so that ``jsonschema`` need only check that value to say
what is wrong.

It is never more lenient than ``jsonschema`` (Draft 2020-12, with cspace's strict
``integer`` and whole-string ``pattern``): it knows the keywords the schema uses, reads
each as ``jsonschema`` does, and is stricter where that is simpler (``const`` and
``enum`` match values of the same JSON type only). Where it is stricter, the value it
finds may be valid after all: then ``jsonschema`` checks the whole document. A schema
with any other keyword is not compiled (`UnsupportedSchemaError`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from typing import Any

Check = Callable[[Any], bool]
"""A compiled schema or keyword: True when the value is valid under it."""

Path = tuple[str | int, ...]
"""Keys and indices from the document's root to a value."""

_IGNORED = frozenset({"description", "title", "$schema", "$id"})

_TYPES: dict[str, Check] = {
    "string": lambda v: type(v) is str,
    "integer": lambda v: type(v) is int,  # a bool is not one (cspace's strict integer)
    "number": lambda v: type(v) is int or type(v) is float,
    "boolean": lambda v: type(v) is bool,
    "null": lambda v: v is None,
    "object": lambda v: type(v) is dict,
    "array": lambda v: type(v) is list,
}


class UnsupportedSchemaError(ValueError):
    """The schema uses a keyword (or a form of one) this module does not read."""


class QuickSchema:
    """A schema (``$ref`` inlined) compiled: `valid` and `locate`."""

    def __init__(self, schema: Mapping[str, Any]) -> None:
        """Compile ``schema``.

        Raises:
            UnsupportedSchemaError: A keyword, or a form of one, it does not read.
        """
        self._compiled: dict[int, Check] = {}  # id of a schema node -> its check
        self._keywords: dict[int, list[tuple[str, Any, Check]]] = {}
        self._schema = schema
        self.valid = self._compile(schema)

    def locate(self, value: Any) -> tuple[Path, Mapping[str, Any]]:
        """Where ``value`` (not `valid`) first fails, and the schema there.

        The deepest value whose own keyword fails, found in the order ``jsonschema``
        reads the schema: a parent's keyword before its properties and items.
        """
        path: list[str | int] = []
        schema = self._schema
        while True:
            child = self._failing_child(schema, value)
            if child is None:
                return tuple(path), schema
            step, schema, value = child
            if step is not None:
                path.append(step)

    def _failing_child(
        self, schema: Mapping[str, Any], value: Any
    ) -> tuple[str | int | None, Mapping[str, Any], Any] | None:
        for name, argument, check in self._keywords[id(schema)]:
            if name == "properties" and type(value) is dict:
                for key, sub in argument.items():
                    if key in value and not self._compiled[id(sub)](value[key]):
                        return key, sub, value[key]
            elif name == "items" and type(value) is list:
                item = self._compiled[id(argument)]
                for index, element in enumerate(value):
                    if not item(element):
                        return index, argument, element
            elif name == "allOf":
                for part in argument:
                    if not self._compiled[id(part)](value):
                        return None, part, value
            elif not check(value):
                return None  # this value's own keyword
        return None

    def _compile(self, schema: Mapping[str, Any]) -> Check:
        keywords = [
            (name, argument, self._keyword(name, argument, schema))
            for name, argument in schema.items()
            if name not in _IGNORED
        ]
        self._keywords[id(schema)] = keywords
        checks = [check for _, _, check in keywords]
        compiled: Check = (
            checks[0] if len(checks) == 1 else (lambda v: all(check(v) for check in checks))
        )
        self._compiled[id(schema)] = compiled
        return compiled

    def _keyword(self, name: str, argument: Any, schema: Mapping[str, Any]) -> Check:
        if name == "type":
            return _type(argument)
        if name in ("const", "enum"):
            return _one_of([argument] if name == "const" else argument)
        if name == "required":
            keys = tuple(argument)
            return lambda v: type(v) is not dict or all(k in v for k in keys)
        if name == "properties":
            children = [(key, self._compile(sub)) for key, sub in argument.items()]
            return lambda v: (
                type(v) is not dict or all(sub(v[key]) for key, sub in children if key in v)
            )
        if name == "additionalProperties" and type(argument) is bool:
            known = frozenset(schema.get("properties", {}))
            return lambda v: argument or type(v) is not dict or known.issuperset(v)
        if name == "items" and isinstance(argument, Mapping):
            item = self._compile(argument)
            return lambda v: type(v) is not list or all(item(i) for i in v)
        if name == "allOf":
            parts = [self._compile(part) for part in argument]
            return lambda v: all(part(v) for part in parts)
        return _bound(name, argument)


def _type(argument: str | list[str]) -> Check:
    names = [argument] if isinstance(argument, str) else list(argument)
    if not all(n in _TYPES for n in names):
        raise UnsupportedSchemaError(f"type {argument!r}")
    checks = [_TYPES[n] for n in names]
    if len(checks) == 1:
        return checks[0]
    return lambda v: any(check(v) for check in checks)


def _one_of(values: list[Any]) -> Check:
    """``const``/``enum``: the same JSON type and value (1.0 is not 1: stricter)."""
    if not all(v is None or type(v) in (str, int) for v in values):
        raise UnsupportedSchemaError(f"const or enum of {values!r}")
    allowed = {(type(v), v) for v in values}
    return lambda v: type(v) in (str, int, type(None)) and (type(v), v) in allowed


def _bound(name: str, argument: Any) -> Check:
    """The keywords that bound one value: sizes, numbers, lengths, patterns."""
    if name in ("maxItems", "minItems", "maxLength", "minLength") and type(argument) is int:
        kind = list if name.endswith("Items") else str
        if name.startswith("max"):
            return lambda v: type(v) is not kind or len(v) <= argument
        return lambda v: type(v) is not kind or len(v) >= argument
    if name in ("minimum", "maximum") and type(argument) in (int, float):
        if name == "minimum":
            return lambda v: type(v) not in (int, float) or v >= argument
        return lambda v: type(v) not in (int, float) or v <= argument
    if name == "pattern" and isinstance(argument, str):
        pattern, to_end = re.compile(argument), argument.endswith("$")

        def matches(v: Any) -> bool:
            if type(v) is not str:
                return True
            found = pattern.search(v)  # ECMA-262's $ ends the string: no final line break
            return found is not None and (not to_end or found.end() == len(v))

        return matches
    raise UnsupportedSchemaError(f"keyword {name!r}")
