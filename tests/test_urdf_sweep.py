"""Every URDF file pybullet, Drake and robosuite ship, against Pinocchio and yourdfpy.

pybullet and drake are test dependencies, robosuite robot data (tests/robot-data.txt):
pybullet's 1,095 URDF files (pybullet_data), the 14 of Drake's wheel and robosuite's 5
are on disk. For each: when
Pinocchio's own parser (urdfdom) refuses the file, cspace refuses it too, in one line;
when it reads it, cspace's factor counts are yourdfpy's by the rules of
docs/cspace-math.md (as tests/test_erd.py counts them) and its dimension is Pinocchio's
free coordinates, less mimic and locked joints. yourdfpy itself refuses two files
(geometry it does not know: ``<plane>``, ``<cdf>``); for those, Pinocchio's count alone.

The figures this test measures are in docs/formats.md (after the MJCF sweep).
"""

from __future__ import annotations

import importlib.util
import os
from collections import Counter
from pathlib import Path

import pinocchio as pin
import pybullet_data
import pydrake
from test_erd import independent_counts

import cspace

PYBULLET = sorted(Path(pybullet_data.getDataPath()).rglob("*.urdf"))
DRAKE = sorted((Path(pydrake.__file__).parent / "share" / "drake").rglob("*.urdf"))
_ROBOSUITE = importlib.util.find_spec("robosuite")  # robot data: found, never imported
assert _ROBOSUITE is not None and _ROBOSUITE.submodule_search_locations
ROBOSUITE = sorted(Path(next(iter(_ROBOSUITE.submodule_search_locations))).rglob("*.urdf"))


def _pinocchio(path: Path) -> pin.Model | None:
    """Pinocchio's model of the file (its parser's noise sent to /dev/null), or None."""
    saved = os.dup(2)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
            try:
                return pin.buildModelFromUrdf(str(path))
            except (RuntimeError, ValueError):
                return None
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def _world_declared(path: Path) -> pin.Model | None:
    """Pinocchio's model of the file with ``<link name="world"/>`` declared, or None."""
    text = path.read_text()
    start = text.index(">", text.index("<robot")) + 1
    declared = f'{text[:start]}<link name="world"/>{text[start:]}'
    try:
        return pin.buildModelFromXML(declared)
    except (RuntimeError, ValueError):
        return None


def _check(path: Path) -> str:
    """``agree``, ``both-refuse``, ``agree-pinocchio`` or what went wrong.

    A file that names a link ``world`` it does not declare (Drake's Acrobot.urdf) is
    read as Drake reads it, as if declared (a ``world-undeclared`` info): so it is
    compared with Pinocchio's model of the file with ``world`` declared.
    """
    model = _pinocchio(path)
    try:
        report = cspace.inspect(path)
    except cspace.RobotFileError as refused:
        if "\n" in str(refused):
            return f"multi-line error: {refused}"
        return "both-refuse" if model is None else f"cspace refuses: {refused}"
    if model is None and any(d.code == "world-undeclared" for d in report.diagnostics):
        model = _world_declared(path)
    if model is None:
        return f"cspace reads what Pinocchio refuses: {report.manifold.notation}"
    mimics = sum(j.kind is cspace.JointKind.MIMIC for j in report.joints)
    try:
        counts, their_mimics, locked = independent_counts(path)
    except ValueError:  # yourdfpy: geometry it does not know
        locked = sum(
            j.kind is not cspace.JointKind.MIMIC and j.nv and not j.space.dimension
            for j in report.joints
        )
        if report.dimension != model.nv - mimics - locked:
            return f"differs from Pinocchio: {report.dimension} != {model.nv} - {mimics}"
        return "agree-pinocchio"
    if report.manifold.counts() != dict(counts):
        return f"differs from yourdfpy: {report.manifold.counts()} != {dict(counts)}"
    if (mimics, report.dimension) != (their_mimics, model.nv - their_mimics - locked):
        return f"differs from Pinocchio: {report.dimension} != {model.nv} - {their_mimics}"
    return "agree"


def test_every_urdf_file_of_pybullet_drake_and_robosuite_follows_pinocchio_and_yourdfpy() -> None:
    assert len(PYBULLET) >= 1_000 and len(DRAKE) >= 10 and len(ROBOSUITE) >= 5
    outcomes = {path: _check(path) for path in PYBULLET + DRAKE + ROBOSUITE}
    fine = ("agree", "both-refuse", "agree-pinocchio")
    wrong = {str(p): o for p, o in outcomes.items() if o not in fine}
    assert wrong == {}
    counts = Counter(outcomes.values())
    # The figures of docs/formats.md
    assert counts["agree"] >= 1_100 and counts["both-refuse"] <= 10, counts
