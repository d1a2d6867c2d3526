"""Every URDF that example-robot-data installs: a correct report, or a precise error.

The expected factor counts come from an independent reader (yourdfpy) and the rules of
docs/cspace-math.md, and the dimension is checked against Pinocchio's own
count of free coordinates. Some of these real files are broken, and some trip
Pinocchio's parser: those must end in a precise error, never a crash or a wrong count.
"""

from __future__ import annotations

import math
from collections import Counter
from pathlib import Path

import jsonschema
import pinocchio as pin
import pytest

import cspace
from cspace._formats.shared.erd import robots_dir, urdf_files
from cspace._schema import report_schema

ERD_FILES = urdf_files()
VALIDATOR = jsonschema.Draft202012Validator(report_schema())

# Files that are broken as shipped, with the error code that must name the problem.
BROKEN = {
    # <mimic joint="index_q1"> names a joint that does not exist (it is "Left_index_q1").
    "alex_description/urdf/alex_psyonic_hands.urdf": "mimic-unknown-joint",
    # An empty <robot> element: xacro output with every macro call missing.
    "ur_description/urdf/ur3.urdf": "no-links",
}


def _rel(path: Path) -> str:
    return path.relative_to(robots_dir()).as_posix()


def independent_counts(path: Path) -> tuple[Counter[str], int, int]:
    """Factor counts, mimic count and locked count, by yourdfpy and the rules alone."""
    import yourdfpy  # trimesh with it: half a second, for the worker that runs this file

    robot = yourdfpy.URDF.load(
        str(path),
        build_scene_graph=False,
        build_collision_scene_graph=False,
        load_meshes=False,
        load_collision_meshes=False,
    ).robot
    counts: Counter[str] = Counter(R=0, T=0, RP3=0)
    mimics = locked = 0
    for joint in robot.joints:
        if joint.type == "fixed":
            continue  # a point, even when it carries a (meaningless) <mimic>
        if joint.mimic is not None:
            mimics += 1
            continue
        if joint.type in ("revolute", "prismatic"):
            lower = joint.limit.lower if joint.limit.lower is not None else 0.0
            upper = joint.limit.upper if joint.limit.upper is not None else 0.0
            if lower == upper:
                locked += 1
            elif joint.type == "revolute" and not (math.isfinite(lower) and math.isfinite(upper)):
                counts["T"] += 1
            else:
                counts["R"] += 1
        elif joint.type == "continuous":
            counts["T"] += 1
        elif joint.type == "floating":
            counts.update(R=3, RP3=1)
        elif joint.type == "planar":
            counts.update(R=2, T=1)
    return counts, mimics, locked


def test_there_are_many_files() -> None:
    assert len(ERD_FILES) >= 60


@pytest.mark.parametrize("path", ERD_FILES, ids=_rel)
def test_report_or_precise_error(path: Path, capfd: pytest.CaptureFixture[str]) -> None:
    expected_error = BROKEN.get(_rel(path))
    if expected_error is not None:
        with pytest.raises(cspace.RobotFileError) as caught:
            cspace.inspect(str(path))
        assert caught.value.code == expected_error
        assert str(caught.value).startswith(str(path))
        assert "\n" not in str(caught.value)
        assert capfd.readouterr() == ("", "")  # Pinocchio's C++ messages are kept quiet
        return
    report = cspace.inspect(str(path))
    assert capfd.readouterr() == ("", "")
    VALIDATOR.validate(report.to_dict())

    counts, mimics, locked = independent_counts(path)
    assert report.manifold.counts() == dict(counts)
    assert sum(j.kind is cspace.JointKind.MIMIC for j in report.joints) == mimics

    free_model = pin.buildModelFromUrdf(str(path))  # mimic joints counted as free joints
    assert report.dimension == free_model.nv - mimics - locked


@pytest.mark.parametrize("path", ERD_FILES, ids=_rel)
def test_joint_order_and_layout_follow_pinocchio(path: Path) -> None:
    if _rel(path) in BROKEN:
        return
    report = cspace.inspect(str(path))
    slots = [(j.q_index, j.nq, j.v_index, j.nv) for j in report.joints if j.q_index is not None]
    # Tree order is Pinocchio's order: q and v are tiled left to right without gaps.
    q_end = v_end = 0
    for q_index, nq, v_index, nv in slots:
        assert (q_index, v_index) == (q_end, v_end)
        q_end, v_end = q_index + nq, v_index + nv
    assert (q_end, v_end) == (report.nq, report.nv)


def test_floating_root_adds_se3_to_every_legged_robot() -> None:
    path = robots_dir() / "solo_description/robots/solo12.urdf"
    plain = cspace.inspect(str(path))
    floating = cspace.inspect(str(path), root_joint="floating")
    assert floating.manifold == plain.manifold * cspace.NormalForm(r=3, rp3=1)
    assert floating.joints[0].name == "root_joint"
    assert (floating.nq, floating.nv) == (plain.nq + 7, plain.nv + 6)
