"""Reading a saved JSON report: strict JSON, checked against the report's JSON Schema.

``cspace diff`` and ``cspace check`` take a report saved by ``cspace inspect --format
json`` wherever they take a robot file, and in CI that report comes from a pull request:
it is as untrusted as a robot file. Before anything uses it, it must be

1. UTF-8 JSON, parsed strictly: no ``NaN``, ``Infinity`` or ``-Infinity``, no number
   beyond a double (``1e400``, an integer of more than 309 digits), no key twice in one
   object, no nesting deeper than Python's recursion limit;
2. a cspace report of ``schema_version`` 1;
3. valid under the report's JSON Schema (``cspace schema``), read strictly: an
   ``integer`` is a JSON integer (``1.0`` is not), and a ``pattern`` must match the
   whole string (a final line break included). `_fast_schema` proves
   a valid report valid in a tenth of ``jsonschema``'s time; ``jsonschema`` checks
   whatever it cannot prove valid, and says what is wrong;
4. consistent where the schema cannot say it: the normal form, its ASCII form, the
   fundamental group and the dimension are those of the factor counts, a joint's limits
   have as many upper bounds as lower ones, the joints' ``slots`` name at most
   `MAX_SLOT_NAMES` entries of each vector, a joint's ``origin`` is a floating
   joint's, turned by a unit quaternion, within `MAX_ORIGIN_METRES` of the world's
   origin, and ``at_world_origin`` is said of the root joint only, never true of one
   with an ``origin``;
5. a kinematic tree that ``cspace inspect`` could write (`_tree_check`):
   unique joint names, one root, no loop, one parent per link (MJCF: a body's several
   joints one after another).

The schema also bounds sizes as robot files are bounded: 5,001 joints (5,000 and a root
joint cspace added), names of 256 characters (``name-too-long``), a coordinate's name of
272 (a joint's name and a suffix such as ``.theta.cos``), messages of 600, paths of 4,096,
14,000 coordinates and 10,000 findings: what ``cspace inspect`` can write, so that every
renderer's output stays within a small multiple of the report's size.

Anything else raises `cspace.errors.ReportFileError` (code ``bad-report``) with the JSON
Pointer of the offending value. ``jsonschema`` is imported only here, when a saved
report is not proved valid at once (about 100 ms), never by ``cspace inspect``.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterable, Iterator
from functools import cache
from typing import Any, NoReturn

from cspace._reports._fast_schema import QuickSchema, UnsupportedSchemaError
from cspace._reports._tree_check import check_tree
from cspace._reports.report import SCHEMA_VERSION
from cspace.errors import ReportFileError

MAX_INTEGER_DIGITS = 309
"""No finite double has more digits before its point; a longer JSON integer is refused
before Python converts it (which takes time quadratic in its length)."""


MAX_REPORT_BYTES = 48 * 1024 * 1024
"""Largest saved report read (48 MiB): a report of 5,000 joints takes about 6 MB, the
largest cspace writes (3,333 ball joints named in six slots each, names of 256 ``&``,
1,500 findings) about 33 MB, and checking one takes about a second per 3 MB."""

MAX_REPORT_VALUES = 1_000_000
"""Most JSON values (counted as ``{``, ``[`` and ``,`` bytes) in a saved report, checked
before parsing: 64 MiB of ``{},`` took 1.7 GiB to parse."""


MAX_SLOT_NAMES = 14_000
"""Most entries of one convention's vector (canonical coordinates, Pinocchio's q, MuJoCo's
qpos, ...) named in the joints' ``slots``, like the 14,000 coordinates the schema allows:
a robot of 5,000 joints and 10,000 degrees of freedom has at most 13,340 (3,333 ball
joints of four each, and a floating root joint). The page draws a cell for each."""


ORIGIN_TOLERANCE = 1e-9
"""How far from 1 the norm of a joint origin's quaternion may be: cspace writes them
unit to rounding, and the Drake convention composes them as they are."""


MAX_ORIGIN_METRES = 1e6
"""Farthest a root joint's ``origin`` may be from the world's origin, along each axis (m):
a thousand kilometres is no robot's placement, and composed into Drake's q a double there
keeps only about a tenth of a nanometre."""

_SPLIT_SUFFIXES = ("_TX", "_TY", "_RZ")
"""MuJoCo's URDF converter's joints of a planar joint (`matching.SPLIT_PLANAR`)."""


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


@cache
def _inlined_schema() -> dict[str, Any]:
    from cspace._schema import report_schema

    schema = report_schema()
    definitions = schema.pop("$defs")
    inlined: dict[str, Any] = _inline(schema, definitions)
    return inlined


@cache
def _quick_schema() -> QuickSchema | None:
    """The schema compiled for a quick check, or None if it cannot be."""
    try:
        return QuickSchema(_inlined_schema())
    except UnsupportedSchemaError:
        return None


@cache
def _validator() -> Any:
    import jsonschema  # only here: saved reports are the only JSON that cspace validates

    base = jsonschema.Draft202012Validator
    types = base.TYPE_CHECKER.redefine(
        "integer", lambda _checker, value: isinstance(value, int) and not isinstance(value, bool)
    )
    strict = jsonschema.validators.extend(base, {"pattern": _pattern}, type_checker=types)
    return strict(_inlined_schema())


def _types(expected: str | list[str]) -> str:
    names = [expected] if isinstance(expected, str) else expected
    article = {"array": "an", "integer": "an", "object": "an", "null": ""}
    return " or ".join(f"{article.get(n, 'a')} {n}".strip() for n in names)


def _message(error: Any) -> str:
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


def _check_schema(path: str, document: dict[str, Any]) -> None:
    try:
        error = _first_error(document)
        if error is None:
            return
        where, problem = pointer(error.absolute_path), _message(error)
    except RecursionError:  # a deep value quoted in jsonschema's own message
        where, problem = "", "nested too deeply"
    raise ReportFileError(path, f"not a valid cspace report: {problem}", pointer=where)


def _check_consistency(path: str, document: dict[str, Any]) -> None:
    from cspace._manifold import NormalForm

    manifold = document["manifold"]
    counts = manifold["factors"]
    form = NormalForm(r=counts["R"], t=counts["T"], rp3=counts["RP3"])
    derived = {
        "/manifold/notation": (manifold["notation"], form.notation),
        "/manifold/ascii": (manifold["ascii"], form.ascii),
        "/manifold/fundamental_group": (manifold["fundamental_group"], form.fundamental_group),
        "/manifold/simply_connected": (manifold["simply_connected"], form.simply_connected),
        "/dimension": (document["dimension"], form.dimension),
    }
    for where, (found, expected) in derived.items():
        if found != expected:
            problem = f"{describe(found)} contradicts the factors, which give {describe(expected)}"
            raise ReportFileError(path, f"not a valid cspace report: {problem}", pointer=where)
    slot_names: dict[str, int] = {}
    names = {joint["name"] for joint in document["joints"]}
    roots = _root_names(document["joints"], names)
    for index, joint in enumerate(document["joints"]):
        mimic = joint["mimic"]
        if mimic is not None and (mimic["joint"] not in names or mimic["joint"] == joint["name"]):
            problem = f"joint {describe(joint['name'])} follows {describe(mimic['joint'])}, " + (
                "itself" if mimic["joint"] == joint["name"] else "which the report does not have"
            )
            raise ReportFileError(
                path,
                f"not a valid cspace report: {problem}",
                pointer=f"/joints/{index}/mimic/joint",
            )
        _check_origin(path, joint, index, roots)
        limits = joint["limits"]
        if limits is not None and len(limits["lower"]) != len(limits["upper"]):
            problem = f"{len(limits['upper'])} upper bounds for {len(limits['lower'])} lower bounds"
            raise ReportFileError(
                path,
                f"not a valid cspace report: {problem}",
                pointer=f"/joints/{index}/limits/upper",
            )
        for convention, slot in joint.get("slots", {}).items():
            slot_names[convention] = slot_names.get(convention, 0) + len(slot["names"])
            if slot_names[convention] > MAX_SLOT_NAMES:
                problem = (
                    f"more than {MAX_SLOT_NAMES:,} entries in {convention} (a vector of "
                    "coordinates); cspace inspect writes at most that many"
                )
                raise ReportFileError(
                    path,
                    f"not a valid cspace report: {problem}",
                    pointer=f"/joints/{index}/slots/{convention}/names",
                )
    coordinates = document["coordinates"]
    sizes = (coordinates["size"], len(coordinates["entries"]), len(coordinates["neutral"]))
    if len(set(sizes)) != 1:
        problem = (
            f"the coordinates section has size {sizes[0]}, {sizes[1]} entries and "
            f"{sizes[2]} neutral values"
        )
        raise ReportFileError(
            path, f"not a valid cspace report: {problem}", pointer="/coordinates/neutral"
        )


def _root_names(joints: list[dict[str, Any]], names: set[str]) -> set[str]:
    """The joints ``at_world_origin`` may be said of: the root joint's (as `_root_place`).

    The first joint with coordinates when it is at q 0 and floating or planar, or, when
    it is one of MuJoCo's three joints of a planar joint ``P`` (``P_TX``, ``P_TY``,
    ``P_RZ``), those three.
    """
    first = next((j for j in joints if j["q_index"] is not None), None)
    if first is None or first["q_index"] != 0:
        return set()
    if first["kind"] in ("floating", "planar"):
        return {first["name"]}
    name = first["name"]
    suffix = next((s for s in _SPLIT_SUFFIXES if name.endswith(s)), None)
    if suffix is None:
        return set()
    base = name.removesuffix(suffix)
    return {f"{base}{s}" for s in _SPLIT_SUFFIXES} & names


def _check_origin(path: str, joint: dict[str, Any], index: int, roots: set[str]) -> None:
    """A joint's placement, as cspace writes it.

    ``at_world_origin`` is said of the root joint only (`_root_names`) and is not true of
    a joint with an ``origin``; an ``origin`` is a floating joint's, turned by a unit
    quaternion, within `MAX_ORIGIN_METRES` of the world's origin along each axis.
    """
    name = describe(joint["name"])
    pointer = f"/joints/{index}/at_world_origin"
    origin = joint.get("origin")
    problem = None
    if "at_world_origin" in joint and joint["name"] not in roots:
        problem = f"joint {name} is not the root joint: only the root joint is at_world_origin"
    elif origin is None:
        return
    elif joint.get("at_world_origin") is True:
        problem = f"joint {name} is at_world_origin, yet has an origin off the world's"
    else:
        pointer = f"/joints/{index}/origin"
        if joint["kind"] != "floating":
            problem = f"joint {name} is {joint['kind']}: only a floating one has an origin"
        elif abs(math.hypot(*origin[3:]) - 1.0) > ORIGIN_TOLERANCE:
            problem = f"joint {name}'s origin turns by a quaternion that is not unit"
        elif any(abs(v) > MAX_ORIGIN_METRES for v in origin[:3]):
            problem = (
                f"joint {name}'s origin is farther than {MAX_ORIGIN_METRES:g} m from the "
                "world's origin"
            )
    if problem is not None:
        raise ReportFileError(path, f"not a valid cspace report: {problem}", pointer=pointer)


def read_report_document(path: str, data: bytes) -> dict[str, Any]:
    """A saved JSON report, checked before anything uses it (see the module's docstring).

    Args:
        path: The file, for messages.
        data: Its bytes.

    Returns:
        The report document: safe to give to `diff_reports`.

    Raises:
        ReportFileError: Not strict JSON, not a cspace report of schema_version 1, not
            valid under its JSON Schema, not consistent, or not a tree (code
            ``bad-report``).
    """
    if len(data) > MAX_REPORT_BYTES:
        raise ReportFileError(
            path,
            f"a saved report of {len(data):,} bytes, larger than the {MAX_REPORT_BYTES:,} "
            "cspace reads",
            pointer="",
        )
    values = data.count(b"{") + data.count(b"[") + data.count(b",")
    if values > MAX_REPORT_VALUES:
        raise ReportFileError(
            path,
            f"a saved report of about {values:,} JSON values, more than the "
            f"{MAX_REPORT_VALUES:,} cspace reads",
            pointer="",
        )
    document = parse_strict_json(path, data)
    if not isinstance(document, dict) or "joints" not in document or "manifold" not in document:
        raise ReportFileError(
            path, "JSON, but not a cspace report (no joints, no manifold)", pointer=""
        )
    version = document.get("schema_version")
    if type(version) is not int or version != SCHEMA_VERSION:
        raise ReportFileError(
            path,
            f"report schema_version {describe(version)}; this cspace reads {SCHEMA_VERSION}",
            pointer="/schema_version",
        )
    _check_schema(path, document)
    _check_consistency(path, document)
    check_tree(path, document)
    return document


def looks_like_json(data: bytes) -> bool:
    """True when the bytes start (after white space) like JSON rather than XML.

    Any JSON value counts (``"text"``, ``42``, ``null``): it is then a JSON file that is
    not a report, not a robot file that is not XML.
    """
    start = data.lstrip()[:5]
    first = start[:1]
    return (bool(first) and first in b'{["-0123456789') or start.startswith(
        (b"true", b"false", b"null")
    )
