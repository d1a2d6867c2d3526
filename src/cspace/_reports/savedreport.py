"""Reading a saved JSON report: strict JSON, checked against the report's JSON Schema.

``cspace diff`` and ``cspace check`` take a report saved by ``cspace inspect --format
json`` wherever they take a robot file, and in CI that report comes from a pull request:
it is as untrusted as a robot file. Before anything uses it, it must be

1. UTF-8 JSON, parsed strictly (`_strict_json`): no ``NaN``, ``Infinity`` or
   ``-Infinity``, no number beyond a double (``1e400``, an integer of more than 309
   digits), no key twice in one object, no nesting deeper than Python's recursion limit;
2. a cspace report of ``schema_version`` 1;
3. valid under the report's JSON Schema (``cspace schema``), read strictly
   (`_schema_check`): an ``integer`` is a JSON integer (``1.0`` is not), and a
   ``pattern`` must match the whole string (a final line break included). `_fast_schema`
   proves a valid report valid in a tenth of ``jsonschema``'s time; ``jsonschema``
   checks whatever it cannot prove valid, and says what is wrong;
4. consistent where the schema cannot say it (`_consistency`): the normal form, its
   ASCII form, the fundamental group and the dimension are those of the factor counts,
   a joint's limits have as many upper bounds as lower ones, the joints' ``slots`` name
   at most 14,000 entries of each vector, a joint's ``origin`` is a floating joint's,
   turned by a unit quaternion, within 1,000 km of the world's origin, and
   ``at_world_origin`` is said of the root joint only, never true of one with an
   ``origin``; a mechanism's ``closure`` agrees with itself and the report (its cuts
   hold links of the report's joints, its counts, ranks and mobility agree,
   `_closure_check`);
5. a kinematic tree that ``cspace inspect`` could write (`_tree_check`):
   unique joint names, one root, no loop, one parent per link (MJCF: a body's several
   joints one after another).

The schema also bounds sizes as robot files are bounded: 5,001 joints (5,000 and a root
joint cspace added), names of 256 characters (``name-too-long``), a coordinate's name of
272 (a joint's name and a suffix such as ``.theta.cos``), messages of 600, paths of 4,096,
14,000 coordinates, 10,000 findings and 5,000 cuts closing loops: what ``cspace
inspect`` can write, so that every
renderer's output stays within a small multiple of the report's size.

Anything else raises `cspace.errors.ReportFileError` (code ``bad-report``) with the JSON
Pointer of the offending value.

A ``cspace collisions`` report (``kind`` ``collisions``) is no C-space report: `diff`
and ``check ROBOT`` refuse it in one line. A baseline's line may be one
(`read_saved_document`): parsed as strictly and bounded as much, then checked against
its own schema, ``cspace schema --collisions``, and for its consistency
(`_collisions_check`). ``jsonschema`` is imported only by `_schema_check`, when
a saved report is not proved valid at once (about 100 ms), never by ``cspace inspect``.
"""

from __future__ import annotations

from typing import Any

from cspace._reports._consistency import check_consistency
from cspace._reports._schema_check import check_schema
from cspace._reports._strict_json import describe, parse_strict_json
from cspace._reports._tree_check import check_tree
from cspace._reports.report import SCHEMA_VERSION
from cspace.errors import ReportFileError

MAX_REPORT_BYTES = 48 * 1024 * 1024
"""Largest saved report read (48 MiB): a report of 5,000 joints takes about 6 MB, the
largest cspace writes (3,333 ball joints named in six slots each, names of 256 ``&``,
1,500 findings) about 33 MB, and checking one takes about a second per 3 MB."""

MAX_REPORT_VALUES = 1_000_000
"""Most JSON values (counted as ``{``, ``[`` and ``,`` bytes) in a saved report, checked
before parsing: 64 MiB of ``{},`` took 1.7 GiB to parse."""


def read_report_document(path: str, data: bytes) -> dict[str, Any]:
    """A saved JSON report, checked before anything uses it (see the module's docstring).

    Args:
        path: The file, for messages.
        data: Its bytes.

    Returns:
        The report document: safe to give to `diff_reports`.

    Raises:
        ReportFileError: Not strict JSON, not a cspace report of schema_version 1 (a
            collisions report among them), not valid under its JSON Schema, not
            consistent, or not a tree (code ``bad-report``).
    """
    return _checked_report(path, _parsed(path, data))


def read_saved_document(path: str, data: bytes) -> dict[str, Any]:
    """A saved report of either kind: ``inspect``'s, or ``collisions``' (``kind``).

    A document of ``kind`` ``collisions`` is checked as `check_collisions_document`
    says (its schema, ``cspace schema --collisions``, and its consistency); any other is
    read as `read_report_document` reads it. Both are parsed as strictly.

    Raises:
        ReportFileError: As `read_report_document`, or a collisions report not valid
            under its schema or not consistent, or another ``kind``.
    """
    document = _parsed(path, data)
    if isinstance(document, dict) and document.get("kind") == COLLISIONS_KIND:
        from cspace._reports._collisions_check import check_collisions_document

        checked: dict[str, Any] = document
        check_collisions_document(path, checked)
        return checked
    return _checked_report(path, document)


COLLISIONS_KIND = "collisions"
"""The ``kind`` of a ``cspace collisions`` report (an inspect report has none)."""


def _parsed(path: str, data: bytes) -> Any:
    """The JSON value of a saved report's bytes, bounded in size and parsed strictly."""
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
    return parse_strict_json(path, data)


def _checked_report(path: str, document: Any) -> dict[str, Any]:
    """An inspect report's document, checked (schema, consistency, tree), or refused."""
    if isinstance(document, dict) and document.get("kind") == COLLISIONS_KIND:
        raise ReportFileError(
            path,
            "a cspace collisions report, not a C-space report (cspace inspect --format json)",
            pointer="/kind",
        )
    if not isinstance(document, dict) or "joints" not in document or "manifold" not in document:
        kind = document.get("kind") if isinstance(document, dict) else None
        said = "" if kind is None else f" of kind {describe(kind)}"
        raise ReportFileError(
            path, f"JSON{said}, but not a cspace report (no joints, no manifold)", pointer=""
        )
    version = document.get("schema_version")
    if type(version) is not int or version != SCHEMA_VERSION:
        raise ReportFileError(
            path,
            f"report schema_version {describe(version)}; this cspace reads {SCHEMA_VERSION}",
            pointer="/schema_version",
        )
    check_schema(path, document)
    check_consistency(path, document)
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
