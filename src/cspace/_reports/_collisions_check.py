"""A saved collisions report (``cspace collisions --format json``) checked before it is used.

``cspace check --baseline`` reads a baseline's collisions reports as it reads its inspect
reports: untrusted (a pull request writes them). Once parsed strictly
(`cspace._reports.savedreport`), a document must be valid under the collisions report's
JSON Schema (``cspace schema --collisions``), read strictly as the report's is
(`_schema_check`: an ``integer`` is a JSON integer, a ``pattern`` matches the whole
string), and consistent where the schema cannot say it:

- each share's ``samples`` is the report's, ``hits <= samples``, ``share`` is
  ``hits / samples`` and ``low <= share <= high``;
- the pairs are pairs of the report's links (each listed once), ``link1 < link2``, sorted
  and each once; a pair's class agrees with its count (``always``: at least
  `ALWAYS_SHARE` of the samples, ``never``: none, ``sometimes``: some, fewer than
  ``always``'s); only an ``adjacent`` pair may be
  unsampled (``collisions`` null); a witness is a sample in which the pair collides;
- ``srdf`` is given exactly when ``matrix`` is ``srdf``, and no pair has a ``rule``
  when ``matrix`` is ``none``.

Anything else raises `cspace.errors.ReportFileError` (code ``bad-report``) with the JSON
Pointer of the offending value.
"""

from collections.abc import Iterator, Mapping
from functools import cache
from typing import Any

from cspace._reports._strict_json import describe, pointer
from cspace._reports.collisions import ALWAYS_SHARE
from cspace.errors import ReportFileError


@cache
def _validator() -> Any:
    from cspace._reports._schema_check import inlined, strict_validator
    from cspace._schema import collisions_schema

    return strict_validator(inlined(collisions_schema()))


def check_collisions_document(path: str, document: dict[str, Any]) -> None:
    """Refuse a collisions document that is not valid or not consistent (see the module).

    Args:
        path: Where it was read (``FILE:LINE`` for a baseline's line), for messages.
        document: The parsed document.

    Raises:
        ReportFileError: The first value that is not valid, with its JSON Pointer.
    """
    from cspace._reports._schema_check import error_message

    try:
        error = next(iter(_validator().iter_errors(document)), None)
        where = "" if error is None else pointer(error.absolute_path)
        problem = "" if error is None else error_message(error)
    except RecursionError:  # a deep value quoted in jsonschema's own message
        where, problem = "", "nested too deeply"
    if problem:
        raise ReportFileError(
            path, f"not a valid cspace collisions report: {problem}", pointer=where
        )
    for where, problem in _inconsistencies(document):
        raise ReportFileError(
            path, f"not a consistent cspace collisions report: {problem}", pointer=where
        )


def _inconsistencies(document: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
    """Each (JSON Pointer, problem) the schema cannot see, the first first."""
    samples = document["samples"]
    for key in ("free", "free_suggested"):
        yield from _share(f"/{key}", document[key], samples)
    links = document["links"]
    if len(set(links)) != len(links):
        yield "/links", "a link listed twice"
    known = set(links)
    previous: tuple[str, str] | None = None
    matrix = document["matrix"]
    if (document["srdf"] is not None) != (matrix == "srdf"):
        yield "/srdf", f"an SRDF {'read' if document['srdf'] else 'not read'} with matrix {matrix}"
    for k, pair in enumerate(document["pairs"]):
        at = f"/pairs/{k}"
        names = (pair["link1"], pair["link2"])
        if not names[0] < names[1] or not known.issuperset(names):
            yield at, f"{describe(names[0])} and {describe(names[1])} are not two links, sorted"
        if previous is not None and not previous < names:
            yield at, "pairs not sorted, or a pair listed twice"
        previous = names
        if matrix == "none" and pair["rule"] is not None:
            yield f"{at}/rule", "a rule with matrix none"
        yield from _pair(at, pair, samples)


def _pair(at: str, pair: Mapping[str, Any], samples: int) -> Iterator[tuple[str, str]]:
    share, kind, witness = pair["collisions"], pair["kind"], pair["witness"]
    if share is None:
        if kind != "adjacent":
            yield f"{at}/collisions", f"a {kind} pair not sampled"
        if witness is not None:
            yield f"{at}/witness", "a witness of a pair not sampled"
        return
    yield from _share(f"{at}/collisions", share, samples)
    hits = share["hits"]
    always = hits >= ALWAYS_SHARE * samples  # as cspace classes a pair (MoveIt's 95%)
    fits = {"always": always, "never": hits == 0, "sometimes": hits > 0 and not always}
    if not fits.get(kind, True):
        yield f"{at}/kind", f"a {kind} pair in collision in {hits:,} of {samples:,} samples"
    if witness is not None and (hits == 0 or witness["sample"] >= samples):
        yield f"{at}/witness/sample", "a witness beyond the samples, or of a pair never hit"


def _share(at: str, share: Mapping[str, Any], samples: int) -> Iterator[tuple[str, str]]:
    hits, drawn = share["hits"], share["samples"]
    if drawn != samples:
        yield f"{at}/samples", f"{drawn:,} samples in a report of {samples:,}"
    elif hits > drawn:
        yield f"{at}/hits", f"{hits:,} hits of {drawn:,} samples"
    elif share["share"] != hits / drawn:
        yield f"{at}/share", f"{describe(share['share'])} is not {hits:,} / {drawn:,}"
    elif not share["low"] <= share["share"] <= share["high"]:
        yield at, "not low <= share <= high"
