"""Every MJCF model that dm_control, Gymnasium (and its robotics), pybullet, robosuite and
metaworld install, vs MuJoCo.

The packages are test dependencies (their files are on disk, nothing is downloaded). For
each XML file whose root is ``<mujoco>``: when MuJoCo compiles it (from the file, with
its meshes), cspace's report must follow the compiled model: the same joints in the
same order (unnamed ones named as documented), each joint's kind from ``jnt_type`` and
``jnt_limited``, MuJoCo's ``qposadr``/``dofadr``, ``nq``, ``nv`` and a dimension equal to
``nv``, less one per linear joint equality (a mimic joint, as a URDF ``<mimic>`` is); and
the Pinocchio model cspace builds must place every body where MuJoCo does.
When MuJoCo refuses a file, cspace must refuse it too, with a one-line error.

The figures this test measures are in docs/formats.md (section "MJCF").
"""

from __future__ import annotations

import importlib.util
import re
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import mujoco
import numpy as np
import pytest
from test_mujoco_oracle import (
    KIND_OF_TYPE,
    _joint_names,
    _tie_path,
    dependent,
    linear_ties,
    misplaced_body,
    sampled,
    tie_residuals,
)

import cspace
from cspace.conventions import Conventions


def _package_files(package: str) -> list[Path]:
    spec = importlib.util.find_spec(package)  # found, not imported
    assert spec is not None and spec.submodule_search_locations, package
    folder = Path(next(iter(spec.submodule_search_locations)))
    return sorted(
        path
        for path in folder.rglob("*.xml")
        if re.match(rb"(\s|<\?xml[^>]*\?>|<!--.*?-->)*<mujoco[\s>]", path.read_bytes(), re.S)
    )


PACKAGES = (
    "dm_control",
    "gymnasium",
    "gymnasium_robotics",
    "pybullet_data",
    "robosuite",
    "metaworld",
)
"""robosuite and metaworld are robot data here (tests/robot-data.txt: installed without
their requirements, never imported)."""

GEOMETRY_MISSING = re.compile(r"Error opening file '[^']*\.(stl|obj|msh|png|skn)'", re.I)
"""MuJoCo's error for a mesh, texture or skin file that is not there (dm_control ships
some models without their meshes): cspace reads these models, as it must."""


def _check(path: Path) -> str:
    """``agree``, ``both-refuse``, ``no-joints``, ``geometry-missing`` or what went wrong."""
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as oracle:
        try:
            cspace.inspect(path)
        except cspace.RobotFileError as refused:
            return "both-refuse" if "\n" not in str(refused) else f"multi-line error: {refused}"
        if GEOMETRY_MISSING.search(str(oracle)):
            return "geometry-missing"
        return f"cspace reads a model MuJoCo refuses: {oracle}"
    try:
        report = cspace.inspect(path)
        built = cspace.pinocchio_model(path)
    except cspace.RobotFileError as refused:
        return f"cspace refuses: {refused}"
    joints = [j for j in report.joints if j.qposadr is not None]
    names, ties = _joint_names(model), linear_ties(model)
    kept = len(dependent(report))
    mimics = {j.name: j.mimic.joint for j in joints if j.mimic is not None}
    held = [
        e for f, lead in mimics.items() for e in _tie_path(ties, names.index(f), names.index(lead))
    ]
    facts = [
        ([j.name for j in joints], names),
        (
            [(j.qposadr, j.dofadr) for j in joints],
            [(int(model.jnt_qposadr[k]), int(model.jnt_dofadr[k])) for k in range(model.njnt)],
        ),
        (
            (report.nq, report.nv, report.dimension),
            (model.nq - kept, model.nv - kept, model.nv - len(mimics)),
        ),
        (len(held) >= len(mimics), True),  # MuJoCo's ties lead each follower to its leader
    ]
    for ours, theirs in facts:
        if ours != theirs:
            return f"differs: {ours} != {theirs}"
    for k, joint in enumerate(joints):
        if (
            joint.mimic is None
            and joint.kind not in KIND_OF_TYPE[mujoco.mjtJoint(model.jnt_type[k])]
        ):
            return f"differs: kind of {joint.name}"
    if held:  # MuJoCo finds no error in those ties at configurations cspace writes
        space = cspace.ConfigurationSpace.from_report(report)
        for row in Conventions.of(space).to_mujoco(sampled(space, 5)):
            residuals = tie_residuals(model, row)
            if any(abs(residuals[e]) > 1e-9 for e in held):
                return f"differs: a tie MuJoCo holds is broken: {residuals}"
    misplaced = misplaced_body(model, built, np.random.default_rng(3), 3, report)
    if misplaced is not None:
        return f"differs: body {misplaced} placed elsewhere"
    return "agree" if model.njnt else "no-joints"


AGREE = {
    "dm_control": 37,
    "gymnasium": 14,
    "gymnasium_robotics": 30,
    "pybullet_data": 18,
    "robosuite": 26,
    "metaworld": 73,
}
"""The files with joints each package ships that cspace agrees on (docs/formats.md)."""


@pytest.mark.parametrize("package", PACKAGES)
def test_every_mjcf_model_of_the_test_packages_follows_mujoco(package: str) -> None:
    files = _package_files(package)
    assert len(files) >= 10
    with ThreadPoolExecutor(2) as pool:  # cspace compiles in a child: two at a time
        outcomes = dict(zip(files, pool.map(_check, files), strict=True))
    fine = ("agree", "both-refuse", "no-joints", "geometry-missing")
    wrong = {str(p): o for p, o in outcomes.items() if o not in fine}
    assert wrong == {}
    counts = Counter(outcomes.values())
    # The figures of docs/formats.md: every file MuJoCo compiles with joints, cspace agrees on.
    assert counts["agree"] >= AGREE[package], counts


def test_a_scene_of_two_robosuite_arms_each_named_robot_xml_gives_mujocos_nq(
    tmp_path: Path,
) -> None:
    """robosuite names every robot file robot.xml: attached side by side, MuJoCo tells
    them apart by folder, and so must cspace (it was ``bad-include``)."""
    spec = importlib.util.find_spec("robosuite")
    assert spec is not None and spec.submodule_search_locations
    robots = Path(next(iter(spec.submodule_search_locations))) / "models" / "assets" / "robots"
    scene = tmp_path / "scene.xml"
    scene.write_text(
        f'<mujoco model="two"><asset><model name="panda" file="{robots}/panda/robot.xml"/>'
        f'<model name="iiwa" file="{robots}/iiwa/robot.xml"/></asset><worldbody>'
        '<body name="left"><attach model="panda" prefix="left_"/></body>'
        '<body name="right" pos="1 0 0"><attach model="iiwa" prefix="right_"/></body>'
        "</worldbody></mujoco>"
    )
    model = mujoco.MjModel.from_xml_path(str(scene))
    report = cspace.inspect(scene, allow_dirs=[robots])
    assert (report.nq, report.nv, report.dimension) == (model.nq, model.nv, model.nv) == (14,) * 3
    names = [j.name for j in report.joints if j.qposadr is not None]
    assert names == _joint_names(model) and names[0] == "left_joint1"
