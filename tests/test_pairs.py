"""One robot in two formats: ``cspace diff`` compares C-spaces, not storage.

Pairs written by hand live in tests/pairs/; others are made here with MuJoCo's own URDF
converter (``mj_saveLastXML`` of a URDF that MuJoCo loaded), as a user moving a robot to
MuJoCo would. Each pair must say "unchanged" (exit 0), and a real change made in one
side must still be found (exit 1).
"""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np
import pytest
from lxml import etree

import cspace
from cspace._formats.shared.erd import robots_dir
from cspace._reports.diff import diff_reports
from cspace.conventions import Conventions

from conftest import REPO, ROBOTS, run_cli

PAIRS = REPO / "tests" / "pairs"


def mujoco_converted(urdf: Path, out: Path, *, floating: bool = False) -> Path:
    """The MJCF that MuJoCo's compiler saves for ``urdf``.

    Meshes are dropped (MuJoCo would need their files) and fixed links kept as bodies;
    with ``floating``, a floating joint from the world is added above the root link
    first (URDF's way to say the base moves), which MuJoCo turns into a free joint.
    """
    tree = etree.parse(str(urdf))
    root = tree.getroot()
    for element in list(root.iter("visual", "collision")):
        element.getparent().remove(element)
    if floating:
        children = {j.find("child").get("link") for j in root.iter("joint")}
        base = next(lk.get("name") for lk in root.iter("link") if lk.get("name") not in children)
        etree.SubElement(root, "link", name="world")
        joint = etree.SubElement(root, "joint", name="floating_base", type="floating")
        etree.SubElement(joint, "parent", link="world")
        etree.SubElement(joint, "child", link=base)
    compiler = etree.SubElement(etree.SubElement(root, "mujoco"), "compiler")
    for key, value in (
        ("fusestatic", "false"),
        ("discardvisual", "true"),
        ("boundmass", "0.001"),
        ("boundinertia", "0.001"),
        ("balanceinertia", "true"),  # inertias some packages ship fail MuJoCo's check
    ):
        compiler.set(key, value)
    model = mujoco.MjModel.from_xml_string(etree.tostring(tree).decode())
    mujoco.mj_saveLastXML(str(out), model)
    return out


HAND_WRITTEN = [
    ("robots/arm7.urdf", "tests/pairs/arm7.xml", []),
    ("robots/quadruped_nobase.urdf", "tests/pairs/quadruped.xml", ["--old-root-joint", "floating"]),
    ("tests/pairs/ball.sdf", "tests/pairs/ball.xml", []),
]


@pytest.mark.parametrize(("old", "new", "options"), HAND_WRITTEN, ids=lambda v: str(v))
def test_hand_written_pairs_are_unchanged(old: str, new: str, options: list[str]) -> None:
    run = run_cli("diff", old, new, *options, "--format", "json", cwd=REPO)
    assert run.code == 0, run.stdout + run.stderr
    document = json.loads(run.stdout)
    assert document["changed"] is False and document["changes"] == []
    assert document["rel_tolerance"] == 1e-5
    assert any(n["kind"] == "layout" for n in document["notes"])  # storage differs


def test_the_continuous_joint_and_the_quaternion_are_storage_notes() -> None:
    run = run_cli("diff", "tests/pairs/ball.sdf", "tests/pairs/ball.xml", cwd=REPO)
    assert run.code == 0
    assert run.stdout.startswith("no C-space change: R^2 × S^1 × RP^3 (dimension 6)\n")
    assert "limits compared within 1e-06 or 1e-05 relative" in run.stdout
    notes = {line.split()[2]: line for line in run.stdout.splitlines() if "stored as" in line}
    assert "Pinocchio q (cos, sin)" in notes["turret"] and "MuJoCo qpos (angle)" in notes["turret"]
    assert "(qx, qy, qz, qw)" in notes["wrist"] and "(qw, qx, qy, qz)" in notes["wrist"]


def test_the_root_joint_is_given_per_side_and_paired() -> None:
    old, new = "robots/quadruped_nobase.urdf", "tests/pairs/quadruped.xml"
    alone = run_cli("diff", old, new, cwd=REPO)  # the URDF's trunk is bolted to the world
    assert alone.code == 1 and "C-space changed: R^8 -> R^11 × RP^3" in alone.stdout
    # On both sides, the MJCF's trunk would get a second free joint: refused, clearly.
    both = run_cli("diff", old, new, "--root-joint", "floating", cwd=REPO)
    assert both.code == 2 and both.stderr.strip().endswith("[root-joint-stacked]")
    paired = run_cli("diff", old, new, "--old-root-joint", "floating", cwd=REPO)
    assert paired.code == 0
    assert "floating 'root_joint' (added by cspace)" in paired.stdout
    assert "floating 'trunk_free' (in the file)" in paired.stdout


def _edited(path: Path, tmp_path: Path, old: str, new: str) -> Path:
    text = path.read_text()
    assert old in text
    out = tmp_path / path.name
    out.write_text(text.replace(old, new, 1))
    return out


@pytest.mark.parametrize(
    ("edit", "kind", "joint"),
    [
        (('range="-166.158 166.158"', 'range="-150 166.158"'), "limits", "shoulder_pan"),
        (('<joint name="wrist_roll" axis="0 0 1"/>',) * 2, None, None),
        (
            ('<joint name="wrist_roll" axis="0 0 1"/>', '<joint name="wrist_roll" range="-9 9"/>'),
            "joint-retyped",
            "wrist_roll",
        ),
        (('<joint name="elbow" ', '<joint name="elbow2" '), "joint-added", "elbow2"),
    ],
    ids=["limit", "nothing", "continuous-limited", "renamed"],
)
def test_a_real_change_in_one_side_is_found(tmp_path: Path, edit, kind, joint) -> None:
    mjcf = _edited(PAIRS / "arm7.xml", tmp_path, *edit)
    diff = diff_reports(cspace.inspect(ROBOTS / "arm7.urdf"), cspace.inspect(mjcf))
    if kind is None:
        assert not diff.differs
    else:
        assert (kind, joint) in [(c.kind, c.joint) for c in diff.changes]


def test_map_matches_joints_whose_names_differ(tmp_path: Path) -> None:
    mjcf = _edited(PAIRS / "arm7.xml", tmp_path, '<joint name="elbow" ', '<joint name="elbow2" ')
    urdf = str(ROBOTS / "arm7.urdf")
    assert run_cli("diff", urdf, str(mjcf)).code == 1
    run = run_cli("diff", urdf, str(mjcf), "--map", "elbow=elbow2")
    assert run.code == 0, run.stdout
    assert "joint renamed" in run.stdout
    bad = run_cli("diff", urdf, str(mjcf), "--map", "elbo=elbow2")
    assert bad.code == 2
    assert bad.stderr.strip().endswith("[joint-match]") and "'elbo'" in bad.stderr
    assert run_cli("diff", urdf, str(mjcf), "--map", "elbow").code == 2


REPO_URDFS = [
    ("arm7.urdf", False, None),
    ("diffdrive_nobase.urdf", True, None),
    ("mobile_manipulator.urdf", False, None),  # planar -> two slides and a hinge
    ("quadrotor_floating.urdf", False, None),
    ("quadruped_nobase.urdf", True, None),
    ("sensor_head_fixed.urdf", False, None),
    ("turntable_multiturn.urdf", False, None),
    # MuJoCo's converter writes <mimic> as a joint equality: a mimic joint again.
    ("gripper_mimic.urdf", False, None),
]


@pytest.mark.parametrize(("name", "floating", "change"), REPO_URDFS)
def test_mujocos_own_conversion_of_each_teaching_urdf(
    tmp_path: Path, name: str, floating: bool, change: tuple[str, str] | None
) -> None:
    urdf = ROBOTS / name
    mjcf = mujoco_converted(urdf, tmp_path / (urdf.stem + ".xml"), floating=floating)
    options = ["--old-root-joint", "floating"] if floating else []
    run = run_cli("diff", str(urdf), str(mjcf), *options, "--format", "json")
    document = json.loads(run.stdout)
    found = [(c["kind"], c["joint"]) for c in document["changes"]]
    if change is None:
        assert run.code == 0 and found == [], run.stdout
    else:
        assert run.code == 1 and change in found


ERD = [
    ("ur_description/urdf/ur5_robot.urdf", False, None),  # 6.28319 for 2 pi
    ("solo_description/robots/solo12.urdf", True, None),
    ("panda_description/urdf/panda.urdf", False, None),
]


@pytest.mark.parametrize(("relative", "floating", "change"), ERD, ids=lambda v: str(v))
def test_mujocos_own_conversion_of_example_robot_data(
    tmp_path: Path, relative: str, floating: bool, change: tuple[str, str] | None
) -> None:
    urdf = robots_dir() / relative
    old = cspace.inspect(urdf, "floating" if floating else None)
    new = cspace.inspect(mujoco_converted(urdf, tmp_path / "converted.xml", floating=floating))
    diff = diff_reports(old, new)
    found = [(c.kind, c.joint) for c in diff.changes]
    if change is None:
        assert found == [], found
        if floating:
            assert "root-joint-paired" in {n.kind for n in diff.notes}
    else:
        assert change in found
    strict = diff_reports(old, new, rel_tolerance=0.0)
    if relative.startswith("ur_description"):  # MuJoCo writes 6 significant digits
        assert [c.kind for c in strict.changes] == ["limits"] * 6


def _shipped_with_mimic() -> list[Path]:
    """Every URDF with a ``<mimic>`` that example-robot-data and pybullet install."""
    import importlib.util

    spec = importlib.util.find_spec("pybullet_data")  # found, not imported
    assert spec is not None and spec.submodule_search_locations
    folders = [robots_dir(), Path(next(iter(spec.submodule_search_locations)))]
    return sorted(
        path
        for folder in folders
        for path in folder.rglob("*.urdf")
        if b"<mimic" in path.read_bytes()
    )


MIMIC_URDFS = _shipped_with_mimic()


def test_the_packages_ship_urdf_files_with_mimic_joints() -> None:
    assert len(MIMIC_URDFS) >= 14


@pytest.mark.parametrize("urdf", MIMIC_URDFS, ids=lambda p: f"{p.parent.parent.name}/{p.name}")
def test_a_mimic_is_the_same_after_mujocos_conversion(tmp_path: Path, urdf: Path) -> None:
    """MuJoCo writes a <mimic> as a linear joint equality: the same relation, the same space."""
    try:
        old = cspace.inspect(urdf)
    except cspace.RobotFileError as refused:  # a mimic of a joint the file lacks
        assert refused.code == "mimic-unknown-joint", refused
        with pytest.raises(ValueError, match="mimic"):
            import pinocchio

            pinocchio.buildModelFromUrdf(str(urdf), mimic=True)  # the oracle refuses it too
        return
    mjcf = mujoco_converted(urdf, tmp_path / "converted.xml")
    new = cspace.inspect(mjcf)
    diff = diff_reports(old, new)
    assert not diff.differs, [(c.kind, c.joint) for c in diff.changes]
    mimics = {j.name: j.mimic for j in old.joints if j.mimic is not None}
    # (talos's <mimic> elements sit on fixed joints: none are mimic joints on either side)
    assert {j.name: j.mimic for j in new.joints if j.mimic is not None} == mimics
    # A configuration goes to the same qpos from either file, the followers set from leaders.
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    space = cspace.load(urdf)
    x = space.sample(3, np.random.default_rng(5))
    via_urdf = Conventions.of(space, model).to_mujoco(x)
    own = Conventions.of(cspace.load(mjcf))  # the MJCF's own layout fills its followers
    np.testing.assert_allclose(own.to_mujoco(own.from_mujoco(via_urdf)), via_urdf, atol=1e-12)
    for name, mimic in mimics.items():
        follower, leader = model.joint(name).qposadr[0], model.joint(mimic.joint).qposadr[0]
        np.testing.assert_allclose(
            via_urdf[:, follower], mimic.multiplier * via_urdf[:, leader] + mimic.offset
        )


def _split_planar(tmp_path: Path) -> str:
    """MuJoCo's conversion of mobile_manipulator.urdf: the planar joint as three joints."""
    out = mujoco_converted(ROBOTS / "mobile_manipulator.urdf", tmp_path / "split.xml")
    return out.read_text()


def test_a_split_planar_joint_in_another_order_is_still_the_planar_joint(tmp_path: Path) -> None:
    text = _split_planar(tmp_path)
    lines = text.splitlines()
    parts = [i for i, line in enumerate(lines) if 'name="base_planar_' in line]
    assert len(parts) == 3
    tx, ty, rz = (lines[i] for i in parts)
    lines[parts[0]], lines[parts[1]], lines[parts[2]] = rz, tx, ty  # hinge first
    (tmp_path / "rz_first.xml").write_text("\n".join(lines))
    diff = diff_reports(
        cspace.inspect(ROBOTS / "mobile_manipulator.urdf"),
        cspace.inspect(tmp_path / "rz_first.xml"),
    )
    assert not diff.differs, diff.changes
    layout = [n for n in diff.notes if n.kind == "layout" and n.joint == "base_planar"]
    assert layout[0].after == "q 0..2, v 0..2"


def test_a_limited_slide_is_not_read_as_a_planar_joint(tmp_path: Path) -> None:
    text = _split_planar(tmp_path)
    old = '<joint name="base_planar_TX" type="slide"'
    assert old in text
    text = text.replace('limited="false"', "").replace(old, old + ' range="-1 1"', 1)
    (tmp_path / "limited.xml").write_text(text)
    diff = diff_reports(
        cspace.inspect(ROBOTS / "mobile_manipulator.urdf"), cspace.inspect(tmp_path / "limited.xml")
    )
    assert diff.changed
    assert ("joint-removed", "base_planar") in [(c.kind, c.joint) for c in diff.changes]
