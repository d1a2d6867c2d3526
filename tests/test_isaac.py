"""Isaac's vectors (``--to isaac``): PhysX's joint order, held to Newton's emulation of it.

Isaac Lab 3 gives its Newton back end PhysX's joint order by building the articulation
with ``ModelBuilder.add_usd(joint_ordering="bfs", bodies_follow_joint_ordering=True)``
and reading ``ArticulationView(exclude_joint_types=[FREE, FIXED]).joint_dof_names``
(``isaaclab/assets/articulation/ordering.py``). That is the oracle here: Newton itself,
on the stages of ``tests/usd``, in a child process.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest

import cspace
from cspace.errors import JointMatchError

from conftest import REPO, ROBOTS, run_cli

HERE = REPO / "tests" / "usd"
STAGES = {
    "isaac_order_fixed.usda": "a fixed base: siblings by prim path, not by name or order",
    "isaac_order_floating.usda": "the same, floating",
    "converted/arm7.usda": "urdf-usd-converter's output for robots/arm7.urdf",
    "converted/quadruped_nobase.usda": "four legs on a static trunk: four articulations",
    "converted/gripper_mimic.usda": "a URDF <mimic> as the converter writes it (NewtonMimicAPI); "
    "Newton makes no articulation of its fingers, which hang from the static mount",
    "mimics.usda": "NewtonMimicAPI and PhysxMimicJointAPI, revolute and prismatic",
    "isaac_order_root_api.usda": "a floating quadruped whose ArticulationRootAPI is on its "
    "top Xform: the root is the body UsdPhysics picks (the trunk, the centre of its joints, "
    "where Newton roots it too), not the first body by path",
}
"""The stages held to Newton, and what each shows."""

NEWTON = """
import json, sys
import warp as wp
wp.config.quiet = True
from newton import JointType, ModelBuilder
from newton._src.usd.schemas import SchemaResolverNewton, SchemaResolverPhysx
from newton.selection import ArticulationView
from pxr import Usd, UsdGeom, UsdPhysics
out = {}
for path in sys.argv[1:]:
    stage = Usd.Stage.Open(path)
    roots = [str(p.GetPath()) for p in stage.Traverse() if p.HasAPI(UsdPhysics.ArticulationRootAPI)]
    builder = ModelBuilder(up_axis=UsdGeom.GetStageUpAxis(stage))
    builder.add_usd(stage, load_visual_shapes=False, skip_mesh_approximation=True,
                    schema_resolvers=[SchemaResolverNewton(), SchemaResolverPhysx()],
                    joint_ordering="bfs", bodies_follow_joint_ordering=True)
    labels = [label.rsplit("/", 1)[-1] for label in builder.joint_label]
    leaders = [int(j) for j in builder.joint_mimic_joint]
    coefficients = [list(map(float, c)) for c in builder.joint_mimic_coeffs]
    mimics = {labels[j]: [labels[leader], *coefficients[j]]
              for j, leader in enumerate(leaders) if leader >= 0}
    model = builder.finalize(device="cpu")
    dofs = []
    for root in roots:
        try:
            view = ArticulationView(model, root, verbose=False,
                                    exclude_joint_types=[JointType.FREE, JointType.FIXED])
        except KeyError:  # a root Newton made no articulation of
            continue
        dofs.append(list(view.joint_dof_names))
    out[path] = {"dofs": dofs, "mimics": mimics}
print(json.dumps(out))
"""


@pytest.fixture(scope="session")
def newton() -> dict[str, dict[str, Any]]:
    """What Newton reads of each stage: ``dofs``, each articulation's degrees of freedom
    in its PhysX order; ``mimics``, each follower's leader, offset and multiplier.

    Warp compiles Newton's kernels once a machine, into its own cache (``~/.cache/warp``),
    as pip keeps its wheels: a run after the first reads them from there (a third of the
    CPU time)."""
    paths = [str(HERE / name) for name in STAGES]
    run = subprocess.run(
        [sys.executable, "-c", NEWTON, *paths],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    found: dict[str, dict[str, Any]] = json.loads(run.stdout.strip().splitlines()[-1])
    return {str(Path(path).relative_to(HERE)): facts for path, facts in found.items()}


def _joint_names(path: Path, **options: object) -> list[str]:
    """cspace's Isaac positions of a robot, the floating roots' pose left out."""
    maps = cspace.load(path, **options).conventions().maps("isaac")  # type: ignore[arg-type]
    roots = {n.rsplit("_", 1)[0] for n in maps.names(False) if n.endswith("_qw")}
    return [n for n in maps.names(False) if n.rsplit("_", 1)[0] not in roots]


@pytest.mark.parametrize("stage", list(STAGES), ids=list(STAGES))
def test_the_order_is_newtons_emulation_of_physx(
    stage: str, newton: dict[str, dict[str, Any]]
) -> None:
    """Every articulation's degrees of freedom in Newton's order, one after another; the
    mimic joints Newton reads, with their leaders and coefficients."""
    ours = _joint_names(HERE / stage)
    if stage != "converted/gripper_mimic.usda":
        articulations = sorted(newton[stage]["dofs"], key=lambda dofs: ours.index(dofs[0]))
        assert ours == [name for dofs in articulations for name in dofs], STAGES[stage]
    report = json.loads(run_cli("inspect", str(HERE / stage), "--format", "json").stdout)
    mimics = {
        j["name"]: [j["mimic"]["joint"], j["mimic"]["offset"], j["mimic"]["multiplier"]]
        for j in report["joints"]
        if j.get("mimic")
    }
    assert mimics.keys() == newton[stage]["mimics"].keys()
    for name, (leader, *coefficients) in newton[stage]["mimics"].items():
        assert mimics[name][0] == leader
        np.testing.assert_allclose(mimics[name][1:], coefficients, rtol=1e-6)


def test_a_urdf_root_link_is_the_articulations_root() -> None:
    """A URDF's root link is the root of one articulation (Isaac Sim's importer makes it
    so): breadth first from it. ``urdf-usd-converter`` makes the root link static
    instead, and each leg an articulation of its own (held to Newton above)."""
    assert _joint_names(ROBOTS / "arm7.urdf") == _joint_names(HERE / "converted/arm7.usda")
    hips = [f"{leg}_hip_pitch" for leg in ("lf", "lh", "rf", "rh")]
    knees = [f"{leg}_knee" for leg in ("lf", "lh", "rf", "rh")]
    for options in ({}, {"root_joint": "floating"}):
        assert _joint_names(ROBOTS / "quadruped_nobase.urdf", **options) == hips + knees
    legs = _joint_names(HERE / "converted/quadruped_nobase.usda")
    assert legs == [name for pair in zip(hips, knees, strict=True) for name in pair]


def test_a_floating_root_is_isaac_labs_root_pose_and_velocity() -> None:
    """Position, quaternion (x, y, z, w); linear and angular velocity in the world frame:
    the angular one is R w of the canonical body-frame w, checked with Pinocchio."""
    space = cspace.load(HERE / "isaac_order_floating.usda")
    conv = space.conventions()
    rng = np.random.default_rng(3)
    x = space.sample(5, rng, bounds={"base.x": (-1, 1), "base.y": (-1, 1), "base.z": (-1, 1)})
    dx = rng.normal(size=(5, space.dimension))
    q = conv.to_isaac(x)
    base = space.layout.joint_columns["base"]
    xyz, wxyz = x[:, base][:, :3], x[:, base][:, 3:]
    np.testing.assert_allclose(q[:, :3], xyz)
    np.testing.assert_allclose(q[:, 3:7], np.roll(wxyz, -1, axis=1))  # w last
    np.testing.assert_allclose(conv.from_isaac(q), x, atol=1e-12)
    v = conv.to_isaac_velocity(x, dx)
    for row in range(5):
        rotation = pin.Quaternion(*wxyz[row]).matrix()
        np.testing.assert_allclose(v[row, 3:6], rotation @ dx[row, 3:6], atol=1e-12)
        np.testing.assert_allclose(v[row, :3], dx[row, :3], atol=1e-12)
    np.testing.assert_allclose(conv.from_isaac_velocity(x, v), dx, atol=1e-12)


def test_a_locked_joint_and_a_mimic_follower_keep_their_entries() -> None:
    """PhysX simulates both as joints: the locked one at 0, the follower from its leader."""
    space = cspace.load(HERE / "isaac_order_fixed.usda")
    conv = space.conventions()
    assert "stuck" in conv.maps("isaac").names(False)
    assert "stuck" not in space.names  # no factor of its own
    x = space.sample(3, np.random.default_rng(0))
    q = conv.to_isaac(x)
    assert np.all(q[:, conv.maps("isaac").names(False).index("stuck")] == 0.0)
    gripper = cspace.load(ROBOTS / "gripper_mimic.urdf")
    names = gripper.conventions().maps("isaac").names(False)
    assert names == ("left_finger_joint", "right_finger_joint")
    q = gripper.conventions().to_isaac([0.02])
    np.testing.assert_allclose(q, [0.02, -0.02])  # right = -1 × left


def test_what_isaac_stores_otherwise_is_refused_by_name(tmp_path: Path) -> None:
    """A ball (PhysX's three angles) and a planar joint: refused, named, one line."""
    with pytest.raises(JointMatchError, match="joint 'neck' is spherical: Isaac stores"):
        cspace.load(ROBOTS / "mjcf_balls.xml").conventions().maps("isaac")
    (tmp_path / "q.jsonl").write_text("[0, 0, 0]\n")
    run = run_cli(
        "convert", str(ROBOTS / "mobile_manipulator.urdf"), "q.jsonl",
        "--from", "canonical", "--to", "isaac", cwd=tmp_path,
    )  # fmt: skip
    assert run.code != 0
    assert "joint 'base_planar' is planar: Isaac stores it" in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr


def test_an_mjcf_body_of_several_joints_is_refused_by_name(tmp_path: Path) -> None:
    """Isaac's importer makes them one D6 joint, whose axes' order is not known: refused,
    at once, however deep such bodies nest (each once in the walk, not once per joint)."""
    bodies = "".join(
        f'<body name="b{i}"><joint name="p{i}" axis="0 1 0" range="-1 1"/>'
        f'<joint name="r{i}" axis="1 0 0" range="-1 1"/><geom size="0.1"/>'
        for i in range(30)
    )
    robot = tmp_path / "deep.xml"
    robot.write_text(f"<mujoco><worldbody>{bodies}{'</body>' * 30}</worldbody></mujoco>")
    with pytest.raises(JointMatchError, match="joints 'p0' and 'r0' both move body 'b0'"):
        cspace.load(robot).conventions().maps("isaac")


def test_a_root_named_like_a_joint_entry_is_renamed_as_drake_does(tmp_path: Path) -> None:
    """A joint named ``base_x`` and a floating body ``base``: the root's entries become
    ``_base_x`` ..., so that a CSV's header names each column once."""
    robot = tmp_path / "clash.urdf"
    robot.write_text(
        '<robot name="c"><link name="base"/><link name="arm"/>'
        '<joint name="base_x" type="revolute"><parent link="base"/><child link="arm"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    names = cspace.load(robot, root_joint="floating").conventions().names("isaac")
    assert names[:7] == tuple(f"_base_{s}" for s in ("x", "y", "z", "qx", "qy", "qz", "qw"))
    assert len(set(names)) == len(names) == 8


def test_convert_writes_isaac_vectors_on_the_command_line(tmp_path: Path) -> None:
    """``cspace convert --to isaac``: Pinocchio's order to PhysX's, by name."""
    space = cspace.load(HERE / "isaac_order_fixed.usda")
    x = space.sample(4, np.random.default_rng(5))
    (tmp_path / "x.jsonl").write_text("".join(json.dumps(r.tolist()) + "\n" for r in x))
    run = run_cli(
        "convert", str(HERE / "isaac_order_fixed.usda"), "x.jsonl",
        "--from", "canonical", "--to", "isaac", "--format", "csv", cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 0, run.stderr
    header, *rows = run.stdout.splitlines()
    assert header.split(",") == ["spin", "a_hip", "b_hip", "stuck", "knee", "z_ankle", "after_weld"]
    values = np.array([[float(v) for v in row.split(",")] for row in rows])
    for column, name in enumerate(header.split(",")):
        expected = x[:, space.names.index(name)] if name in space.names else 0.0
        np.testing.assert_allclose(values[:, column], expected)


@pytest.mark.parametrize(
    ("rows", "said"),
    [
        ("[0.1, NaN, 0, 0, 0, 0, 0]\n", "v.jsonl:1: value 2 is not finite"),  # its line
        ("[0.1, 0.2]\n", "v.jsonl:1: has 2 values"),  # the wrong width
        ('{"a": 1}\n', ""),  # no vector at all
    ],
)
def test_a_hostile_isaac_vector_file_is_one_line(tmp_path: Path, rows: str, said: str) -> None:
    (tmp_path / "v.jsonl").write_text(rows)
    run = run_cli(
        "convert", str(HERE / "isaac_order_fixed.usda"), "v.jsonl",
        "--from", "isaac", "--to", "pinocchio", cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 2 and run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    assert said in run.stderr
