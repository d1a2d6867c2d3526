"""``cspace diff --old-order A --new-order B``: one robot's joint order in two tools.

The same quadruped as a URDF in PyBullet's order and as urdf-usd-converter's USD in
Isaac's (breadth first, four articulations); the URDF against its MJCF in MuJoCo's qpos
(the same order); a mimic follower one vector holds and the other not; a side a
convention refuses; and joint names that are workflow commands, in every diff format.
Each joint's index is held to the vector ``cspace convert`` writes
(`Conventions.names`).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_ci_log import CARRIED, EVIL, assert_no_command, assert_printable

import cspace

from conftest import REPO, ROBOTS, run_cli

URDF = ROBOTS / "quadruped_nobase.urdf"
USD = REPO / "tests" / "usd" / "converted" / "quadruped_nobase.usda"


def _index(path: Path, convention: str, joint: str, **options: str) -> int:
    names = cspace.load(path, **options).conventions().names(convention)  # type: ignore[arg-type]
    return names.index(joint)


def test_pybullets_order_of_a_urdf_against_isaacs_of_its_usd(tmp_path: Path) -> None:
    """PyBullet takes each leg whole, Isaac the four legs' articulations by prim path."""
    args = (str(URDF), str(USD), "--old-order", "pybullet", "--new-order", "isaac")
    run = run_cli("diff", *args, "--format", "json", cwd=tmp_path)
    assert run.code == 1, run.stderr
    document = json.loads(run.stdout)
    assert document["verdict"] == "differs"
    orders = document["orders"]
    assert (orders["old"], orders["new"]) == ("pybullet", "isaac")
    assert len(orders["joints"]) == 8
    for row in orders["joints"]:
        assert row["old"] == _index(URDF, "pybullet", row["joint"])
        assert row["new"] == _index(USD, "isaac", row["joint"])
    moved = {c["joint"] for c in document["changes"] if c["kind"] == "order"}
    assert moved == {"rf_hip_pitch", "rf_knee", "lh_hip_pitch", "lh_knee"}
    text = run_cli("diff", *args, cwd=tmp_path)
    assert text.code == 1
    assert "joint order  rf_hip_pitch  PyBullet q 2  Isaac joint_pos 4" in text.stdout


def test_a_urdf_in_pybullets_order_is_its_mjcf_in_mujocos(tmp_path: Path) -> None:
    """Both declare the legs one after another: the order is the same, a note says so,
    and the root joint cspace adds is paired with the MJCF's free joint."""
    pair = REPO / "tests" / "pairs" / "quadruped.xml"
    run = run_cli(
        "diff", str(URDF), str(pair), "--old-order", "pybullet", "--new-order", "mujoco",
        "--old-root-joint", "floating", "--format", "json", cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 0, run.stdout
    document = json.loads(run.stdout)
    assert [n for n in document["notes"] if n["kind"] == "order"] == [
        {
            "kind": "order",
            "joint": None,
            "before": "PyBullet q",
            "after": "MuJoCo qpos: 9 joints in the same order",
        }
    ]
    assert document["orders"]["joints"][0] == {"joint": "trunk_free", "old": 0, "new": 0}


def test_one_convention_given_is_both_sides(tmp_path: Path) -> None:
    run = run_cli("diff", str(URDF), str(URDF), "--new-order", "isaac", cwd=tmp_path)
    assert run.code == 0 and "Isaac joint_pos: 8 joints in the same order" in run.stdout
    plain = run_cli("diff", str(URDF), str(URDF), "--format", "json", cwd=tmp_path)
    assert "orders" not in json.loads(plain.stdout)  # only when asked for


def test_a_follower_one_vector_holds_is_a_change(tmp_path: Path) -> None:
    """Pinocchio's q leaves the mimic follower out; PyBullet's keeps it (free there)."""
    path = ROBOTS / "gripper_mimic.urdf"
    run = run_cli(
        "diff", str(path), str(path), "--old-order", "pinocchio", "--new-order", "pybullet",
        "--format", "json", cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 1
    document = json.loads(run.stdout)
    assert document["changes"] == [
        {"kind": "order", "joint": "right_finger_joint", "before": "-", "after": "PyBullet q 1"}
    ]
    assert {"joint": "right_finger_joint", "old": None, "new": 1} in document["orders"]["joints"]


def test_a_side_the_convention_refuses_is_one_line(tmp_path: Path) -> None:
    path = ROBOTS / "mobile_manipulator.urdf"
    run = run_cli("diff", str(path), str(URDF), "--old-order", "pybullet", cwd=tmp_path)
    assert run.code == 2 and run.stdout == ""
    assert run.stderr.count("\n") == 1
    assert run.stderr.startswith(f"cspace: error: {path}: joint 'base_planar' is planar")


@pytest.mark.parametrize("fmt", ["text", "json", "markdown", "html"])
def test_joint_names_in_the_orders_reach_no_ci_log_as_commands(fmt: str, tmp_path: Path) -> None:
    """Two branches declared in one order, named otherwise: PyBullet and Isaac differ."""
    joints = "".join(
        f'<joint name="{EVIL}{name}" type="revolute"><parent link="base"/>'
        f'<child link="l{k}"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        for k, name in enumerate(("b", "a"))
    )
    (tmp_path / "r.urdf").write_text(
        f'<robot name="r"><link name="base"/><link name="l0"/><link name="l1"/>\n{joints}</robot>'
    )
    run = run_cli(
        "diff", "r.urdf", "r.urdf", "--old-order", "pybullet", "--new-order", "pinocchio",
        "--format", fmt, cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 1, run.stderr
    for text in (run.stdout, run.stderr):
        assert_no_command(text)
        assert_printable(text)
    if fmt == "json":
        names = [row["joint"] for row in json.loads(run.stdout)["orders"]["joints"]]
        assert len(names) == 2 and all(name.startswith("::error::x\n") for name in names)
    else:
        assert all(carried in run.stdout for carried in CARRIED)


_TWO = """<robot name="r">
  <link name="base"/>{mount}<link name="l1"/><link name="l2"/>
  <joint name="j1" type="revolute"><parent link="{parent}"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def test_a_fixed_joint_added_before_shifts_pybullets_joint_indices(tmp_path: Path) -> None:
    """The vector's order is the same, but PyBullet numbers the fixed joint too: each
    moving joint's jointIndex (what setJointMotorControl2 takes) is one more."""
    pybullet = pytest.importorskip("pybullet")
    (tmp_path / "old.urdf").write_text(_TWO.format(mount="", parent="base"))
    mount = '<link name="l0"/><joint name="mount" type="fixed"><parent link="base"/>'
    mount += '<child link="l0"/></joint>'
    (tmp_path / "new.urdf").write_text(_TWO.format(mount=mount, parent="l0"))
    client = pybullet.connect(pybullet.DIRECT)
    try:
        indices = []
        for name in ("old.urdf", "new.urdf"):
            body = pybullet.loadURDF(str(tmp_path / name), physicsClientId=client)
            count = pybullet.getNumJoints(body, physicsClientId=client)
            info = [pybullet.getJointInfo(body, i, physicsClientId=client) for i in range(count)]
            indices.append({i[1].decode(): i[0] for i in info})
    finally:
        pybullet.disconnect(client)
    assert indices == [{"j1": 0, "j2": 1}, {"mount": 0, "j1": 1, "j2": 2}]
    args = ("diff", "old.urdf", "new.urdf", "--old-order", "pybullet", "--format", "json")
    run = run_cli(*args, cwd=tmp_path)
    assert run.code == 1, run.stdout
    changes = json.loads(run.stdout)["changes"]
    assert [(c["kind"], c["joint"], c["before"], c["after"]) for c in changes] == [
        ("order", "j1", "PyBullet jointIndex 0", "PyBullet jointIndex 1"),
        ("order", "j2", "PyBullet jointIndex 1", "PyBullet jointIndex 2"),
    ]
    same = run_cli("diff", "new.urdf", "new.urdf", "--old-order", "pybullet", cwd=tmp_path)
    assert same.code == 0 and "2 joints in the same order" in same.stdout
