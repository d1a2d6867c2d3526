"""What a saved report's ``closure`` must say consistently, where its schema cannot say it.

The schema bounds each value of the ``closure`` object (`cspace schema`); this checks that
its values agree with each other and with the rest of the report, as ``cspace inspect``
writes them (`cspace._reports.closure.Closure.to_dict`):

- each cut's ``links`` are links of the report's joints, its ``file`` is the report's
  ``source.path``, and its ``rows`` what its ``free`` leaves (3, 6, 5);
- ``constraint_rows`` is the sum of the cuts' rows (a cut the analysis left out is in
  neither), and ``loops`` at most the number of cuts;
- ``grubler`` is ``dimension - constraint_rows``, ``mobility`` is ``dimension -
  rank.highest`` (when both are present; less, not below 0, with a ``closure-shaky``
  finding), ``rank.lowest <= rank.highest <= min(constraint_rows, nv)``, and the samples'
  largest residual at most 1e-6; ``loops`` at least 1 with a cut;
- ``samples`` at most ``attempts``; a rank and a largest residual exactly when there are
  samples, a mobility only with a rank; ``assembled`` null when nothing was tried, else
  whether a sample was found;
- each singularity's rank is below ``rank.highest`` and at least ``rank.lowest``, and its
  configuration has as many numbers as the report's coordinates;
- the ``actuated`` names are joints of the report, each once; a ``chart`` is judged
  only with actuated joints and samples.

A report of an SRDF group (``group``) has no closure: its joints are the group's, the
mechanism the whole robot's (``closure-whole-robot``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from cspace._reports._refusal import invalid
from cspace._reports._strict_json import describe
from cspace._reports.closure import ASSEMBLED_TOLERANCE


def check_closure(path: str, document: Mapping[str, Any]) -> None:
    """Refuse a report whose ``closure`` contradicts itself or the report (see the module).

    Raises:
        ReportFileError: The first contradiction, with its JSON Pointer.
    """
    closure = document.get("closure")
    if closure is None:
        return
    if document.get("group") is not None:
        invalid(path, "a group's report has no closure (it is the whole robot's)", "/closure")
    _check_cuts(path, document, closure)
    rows, rank = closure["constraint_rows"], closure["rank"]
    if closure["grubler"] != document["dimension"] - rows:
        invalid(
            path,
            f"Grübler's count {closure['grubler']} is not the dimension "
            f"{document['dimension']} less the {rows} constraint rows",
            "/closure/grubler",
        )
    samples, attempts = closure["samples"], closure["attempts"]
    if samples > attempts:
        invalid(path, f"{samples} samples of {attempts} attempts", "/closure/samples")
    if (rank is None) != (samples == 0):
        invalid(path, f"a rank is given with {samples} samples", "/closure/rank")
    if closure["max_residual"] is not None and closure["max_residual"] > ASSEMBLED_TOLERANCE:
        invalid(
            path,
            f"the samples' largest residual {closure['max_residual']!r} is more than the "
            f"{ASSEMBLED_TOLERANCE:g} a configuration on the mechanism has",
            "/closure/max_residual",
        )
    if (closure["max_residual"] is None) != (samples == 0):
        invalid(
            path, f"a largest residual is given with {samples} samples", "/closure/max_residual"
        )
    expected = None if attempts == 0 else samples > 0
    if closure["assembled"] is not expected:
        invalid(
            path,
            f"assembled is {describe(closure['assembled'])} with {samples} samples of "
            f"{attempts} attempts",
            "/closure/assembled",
        )
    mobility = closure["mobility"]
    if rank is not None:
        most = min(rows, document["nv"])
        if not rank["lowest"] <= rank["highest"] <= most:
            invalid(
                path,
                f"rank from {rank['lowest']} to {rank['highest']}, not within 0 to {most} "
                f"(the {rows} constraint rows, the {document['nv']} velocities)",
                "/closure/rank",
            )
        first_order = document["dimension"] - rank["highest"]
        shaky = any(d["code"] == "closure-shaky" for d in document["diagnostics"])
        if mobility is not None and not (
            mobility == first_order or (shaky and 0 <= mobility < first_order)
        ):
            invalid(
                path,
                f"mobility {mobility} is not the dimension {document['dimension']} less the "
                f"rank {rank['highest']} (nor less, with a closure-shaky finding)",
                "/closure/mobility",
            )
    elif mobility is not None:
        invalid(path, f"mobility {mobility} without a rank", "/closure/mobility")
    _check_singularities(path, document, closure)
    _check_actuated(path, document, closure)
    if closure["chart"] is not None and (samples == 0 or not closure["actuated"]):
        invalid(
            path,
            f"a chart is judged with {samples} samples and {len(closure['actuated'])} "
            "actuated joints",
            "/closure/chart",
        )


def _check_cuts(path: str, document: Mapping[str, Any], closure: Mapping[str, Any]) -> None:
    links = {j["parent_link"] for j in document["joints"]} | {
        j["child_link"] for j in document["joints"]
    }
    source = document["source"]["path"]
    cuts = closure["cuts"]
    for index, cut in enumerate(cuts):
        for side, link in enumerate(cut["links"]):
            if link not in links:
                invalid(
                    path,
                    f"cut {describe(cut['name'])} holds link {describe(link)}, which no joint "
                    "of the report has",
                    f"/closure/cuts/{index}/links/{side}",
                )
        if cut["file"] != source:
            invalid(
                path,
                f"cut {describe(cut['name'])} is in {describe(cut['file'])}, not the report's "
                f"file {describe(source)}",
                f"/closure/cuts/{index}/file",
            )
    for index, cut in enumerate(cuts):
        rows = {"rotation": 3, "none": 6, "revolute": 5, "prismatic": 5}[cut["free"]]
        if cut["rows"] != rows:
            invalid(
                path,
                f"cut {describe(cut['name'])} leaves {cut['free']} free: {rows} rows, not "
                f"{cut['rows']}",
                f"/closure/cuts/{index}/rows",
            )
    total = sum(cut["rows"] for cut in cuts)
    rows = closure["constraint_rows"]
    if rows != total:
        invalid(
            path, f"{rows} constraint rows, but the cuts make {total}", "/closure/constraint_rows"
        )
    if closure["loops"] > len(cuts) or (cuts and closure["loops"] < 1):
        invalid(path, f"{closure['loops']} loops of {len(cuts)} cuts", "/closure/loops")


def _check_singularities(
    path: str, document: Mapping[str, Any], closure: Mapping[str, Any]
) -> None:
    rank, size = closure["rank"], document["coordinates"]["size"]
    for index, singular in enumerate(closure["singularities"]):
        if rank is None or not rank["lowest"] <= singular["rank"] < rank["highest"]:
            shown = "no rank" if rank is None else f"{rank['lowest']} to {rank['highest']}"
            invalid(
                path,
                f"a singularity of rank {singular['rank']}, not below the highest rank ({shown})",
                f"/closure/singularities/{index}/rank",
            )
        if len(singular["configuration"]) != size:
            invalid(
                path,
                f"a singular configuration of {len(singular['configuration'])} numbers, not "
                f"the {size} coordinates",
                f"/closure/singularities/{index}/configuration",
            )


def _check_actuated(path: str, document: Mapping[str, Any], closure: Mapping[str, Any]) -> None:
    names = {j["name"] for j in document["joints"]}
    seen: set[str] = set()
    for index, name in enumerate(closure["actuated"]):
        if name not in names or name in seen:
            problem = "twice" if name in seen else "which the report does not have"
            invalid(
                path, f"actuated joint {describe(name)}, {problem}", f"/closure/actuated/{index}"
            )
        seen.add(name)
