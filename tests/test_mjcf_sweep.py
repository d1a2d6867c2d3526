"""Every MJCF model dm_control, Gymnasium (and its robotics) and pybullet install, vs MuJoCo.

The packages are test dependencies (their files are on disk, nothing is downloaded). For
each XML file whose root is ``<mujoco>``: when MuJoCo compiles it (from the file, with
its meshes), cspace's report must follow the compiled model: the same joints in the
same order (unnamed ones named as documented), each joint's kind from ``jnt_type`` and
``jnt_limited``, MuJoCo's ``qposadr``/``dofadr``, ``nq``, ``nv`` and a dimension equal to
``nv``; and the Pinocchio model cspace builds must place every body where MuJoCo does.
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
from test_mujoco_oracle import KIND_OF_TYPE, _joint_names, misplaced_body

import cspace


def _package_files(package: str) -> list[Path]:
    spec = importlib.util.find_spec(package)  # found, not imported
    assert spec is not None and spec.submodule_search_locations, package
    folder = Path(next(iter(spec.submodule_search_locations)))
    return sorted(
        path
        for path in folder.rglob("*.xml")
        if re.match(rb"(\s|<\?xml[^>]*\?>|<!--.*?-->)*<mujoco[\s>]", path.read_bytes(), re.S)
    )


FILES = [
    *_package_files("dm_control"),
    *_package_files("gymnasium"),
    *_package_files("gymnasium_robotics"),
    *_package_files("pybullet_data"),
]


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
    moving = [j for j in report.joints if j.q_index is not None]
    facts = [
        ([j.name for j in moving], _joint_names(model)),
        (
            [(j.qposadr, j.dofadr) for j in moving],
            [(int(model.jnt_qposadr[k]), int(model.jnt_dofadr[k])) for k in range(model.njnt)],
        ),
        ((report.nq, report.nv, report.dimension), (model.nq, model.nv, model.nv)),
    ]
    for ours, theirs in facts:
        if ours != theirs:
            return f"differs: {ours} != {theirs}"
    for k, joint in enumerate(moving):
        if joint.kind not in KIND_OF_TYPE[mujoco.mjtJoint(model.jnt_type[k])]:
            return f"differs: kind of {joint.name}"
    misplaced = misplaced_body(model, built, np.random.default_rng(3), 3)
    if misplaced is not None:
        return f"differs: body {misplaced} placed elsewhere"
    return "agree" if model.njnt else "no-joints"


def test_every_mjcf_model_of_the_test_packages_follows_mujoco() -> None:
    assert len(FILES) >= 70
    with ThreadPoolExecutor(2) as pool:  # cspace compiles in a child: two at a time
        outcomes = dict(zip(FILES, pool.map(_check, FILES), strict=True))
    fine = ("agree", "both-refuse", "no-joints", "geometry-missing")
    wrong = {str(p): o for p, o in outcomes.items() if o not in fine}
    assert wrong == {}
    counts = Counter(outcomes.values())
    # The figures of docs/formats.md: every file MuJoCo compiles with joints, cspace agrees on.
    assert counts["agree"] >= 50, counts
