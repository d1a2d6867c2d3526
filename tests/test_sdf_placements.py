"""SDF robots placed where Drake places them: cspace's Pinocchio model against Drake's plant.

For every SDF file of the corpora `test_sdf_drake` reads (pybullet's data, Drake's
wheel, example-robot-data, the repository's, the small files of ``tests/sdf/``), random
configurations, each converted to Drake's q through cspace's Drake convention, put
every body of Drake's ``MultibodyPlant`` (parsed from the same file, once) where
``cspace.pinocchio_model`` puts the ``BODY`` frame of the same name, within 1e-9 m and
rad. The ``tests/sdf/placed_*.sdf`` files hold each rule of SDFormat's poses that Drake
reads (``relative_to`` on links, joints and frames, frames on frames, ``expressed_in``,
degrees, quaternions, nested models and placement frames, a world of models, SDFormat
1.4 and 1.6), and each rule is shown to move a body in Drake, so that the comparison
holds it; quaternions off unit, which libsdformat keeps as written, are placed as Drake
places them. A pose Drake refuses to resolve leaves the model unbuilt, in one line, while
the C-space is still reported.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex, RigidBody
from test_sdf_drake import SHIPPED, drake_plant, without_cuts

import cspace
from cspace.errors import ModelBuildError

from conftest import REPO, run_cli

logging.getLogger("drake").setLevel(logging.ERROR)

TOLERANCE = 1e-9
"""How far (m, and rad as the largest entry of the rotations' difference) a body may be."""

FIXTURES = REPO / "tests" / "sdf"
CSPACE_REFUSES = {
    "cassie.sdf",  # gearbox joints: Drake refuses them too (test_sdf_drake)
    "wsg50_one_motor_gripper.sdf",  # a link named 'world'
    "wsg50_one_motor_gripper_free_base.sdf",
    "wsg50_one_motor_gripper_new.sdf",
    "wsg50_one_motor_gripper_new_free_base.sdf",
    "wsg50_one_motor_gripper_no_finger.sdf",
    "wsg50_with_r2d2_gripper.sdf",
    "model2.sdf",  # two elements of one name
}
"""Files of the corpora cspace refuses, as Drake does (`test_sdf_drake` holds the reasons)."""


def _plant(path: Path, scratch: Path) -> MultibodyPlant:
    """Drake's plant of the file, without what SDFormat does not define."""
    read = drake_plant(path, scratch)
    if isinstance(read, str):
        raise AssertionError(f"{path}: Drake refuses it: {read}")
    return read[0]


def _bodies(plant: MultibodyPlant, ours: set[str]) -> dict[str, RigidBody]:
    """Drake's bodies but the world's, by cspace's name: model scope and body, as it scopes.

    A document of one model names its links without the model's name; a world of several
    prefixes each with its model's (``arm::base``), as Drake's model instances do.
    """
    bodies = {}
    for k in range(1, plant.num_bodies()):
        body = plant.get_body(BodyIndex(k))
        full = f"{plant.GetModelInstanceName(body.model_instance())}::{body.name()}"
        bodies[full if full in ours else full.split("::", 1)[1]] = body
    return bodies


def _draw(space: cspace.ConfigurationSpace, count: int, seed: int) -> list[np.ndarray]:
    """Configurations, free coordinates and huge ranges (1e16) drawn within +-2."""
    if not space.dimension:
        return [space.neutral()]
    near = {
        c.name: (max(c.lower, -2.0), min(c.upper, 2.0))
        for c in space.coordinates
        if not c.wraps and c.upper - c.lower > 4.0
    }
    return list(space.sample(count, np.random.default_rng(seed), bounds=near))


def placement_errors(
    path: Path, scratch: Path, count: int = 6, tree: Path | None = None
) -> tuple[int, float]:
    """Bodies compared and the largest distance (m or rad) between Drake's and cspace's.

    Args:
        path: An SDF file cspace reads.
        scratch: A folder for Drake's copy of the file.
        count: Configurations drawn.
        tree: For a file with loops, which Drake refuses: the file without the joints
            cspace cuts, read by Drake (and drawn from, as a tree); cspace's model is the
            file's own.
    """
    space = cspace.load(tree or path)
    model = cspace.pinocchio_model(path)
    data = model.createData()
    plant = _plant(tree or path, scratch)
    context = plant.CreateDefaultContext()
    conventions = space.conventions()
    frames = {f.name: k for k, f in enumerate(model.frames) if f.type == pin.FrameType.BODY}
    ours = set(frames) - {"world"}
    bodies = _bodies(plant, ours)
    assert set(bodies) == ours, (sorted(bodies), sorted(ours))  # every body, each once
    worst = 0.0
    for x in _draw(space, count, seed=11):
        plant.SetPositions(context, conventions.to_drake(x))
        pin.forwardKinematics(model, data, conventions.to_pinocchio(x))
        pin.updateFramePlacements(model, data)
        for name, body in bodies.items():
            drake = plant.EvalBodyPoseInWorld(context, body)
            placed = data.oMf[frames[name]]
            worst = max(
                worst,
                float(np.abs(drake.translation() - placed.translation).max()),
                float(np.abs(drake.rotation().matrix() - placed.rotation).max()),
            )
    return len(bodies), worst


CASES = sorted(SHIPPED)
PLACED_FIXTURES = sorted(FIXTURES.glob("placed_*.sdf"))


@pytest.mark.parametrize("path", CASES, ids=lambda p: p.name)
def test_every_body_is_where_drake_puts_it(path: Path, tmp_path: Path) -> None:
    if path.name in CSPACE_REFUSES:
        with pytest.raises(cspace.RobotFileError):
            cspace.inspect(path)
        return
    (tmp_path / "tree").mkdir()
    tree = without_cuts(path, tmp_path / "tree")
    compared, worst = placement_errors(path, tmp_path, tree=tree)
    assert compared > 0
    assert worst < TOLERANCE, f"{path.name}: a body is {worst:.3g} from where Drake puts it"


def test_the_corpora_and_every_rule_are_checked() -> None:
    """Not a vacuous pass: the corpora are there, and each rule has its file."""
    names = {p.name for p in CASES}
    assert len(CASES) - len(CSPACE_REFUSES & names) >= 28
    assert {"Acrobot.sdf", "planar_gripper.sdf", "kuka_with_gripper.sdf"} <= names
    assert {p.name for p in PLACED_FIXTURES} <= names and len(PLACED_FIXTURES) == 8


def test_the_acrobot_elbow_is_where_drake_puts_it(tmp_path: Path) -> None:
    """The issue's example: the elbow at [-0.479, 0.25, -0.878] with the shoulder at 0.5."""
    path = next(p for p in CASES if p.name == "Acrobot.sdf")
    model = cspace.pinocchio_model(path)
    data = model.createData()
    space = cspace.load(path)
    x = space.neutral()
    x[space.names.index("shoulder")] = 0.5
    pin.forwardKinematics(model, data, space.conventions().to_pinocchio(x))
    pin.updateFramePlacements(model, data)
    lower = data.oMf[model.getFrameId("lower_link", pin.FrameType.BODY)]
    np.testing.assert_allclose(lower.translation, [-0.479426, 0.25, -0.877583], atol=1e-6)


MUTATIONS = [
    ("placed_frames.sdf", 'relative_to="mount_tip">0.2', ">0.2"),  # a link's relative_to
    ("placed_frames.sdf", '<pose relative_to="base">0.05', "<pose>0.05"),  # a joint's
    (
        "placed_frames.sdf",
        '<frame name="mount_tip" attached_to="mount">',
        '<frame name="mount_tip">',
    ),
    ("placed_frames.sdf", '<pose relative_to="arm">0.35', "<pose>0.35"),  # a frame's
    ("placed_frames.sdf", '<model name="frames" canonical_link="base">', '<model name="frames">'),
    ("placed_axes.sdf", 'expressed_in="__model__"', ""),
    ("placed_axes.sdf", 'expressed_in="tilted"', ""),
    ("placed_axes.sdf", '<xyz expressed_in="base">', "<xyz>"),
    ("placed_axes.sdf", ' expressed_in="l2"', ""),  # both axes of the universal joint
    ("placed_axes.sdf", "0.05</screw_thread_pitch>", "0.5</screw_thread_pitch>"),
    ("placed_rotations.sdf", '<pose degrees="true">0.1', "<pose>0.1"),
    ("placed_rotations.sdf", "0.2 0 0 0 0 0.6 0.8", "0.2 0 0 0 0 0.8 0.6"),
    ("placed_nested.sdf", '<pose relative_to="base">0.2', "<pose>0.2"),
    ("placed_nested.sdf", ' placement_frame="tip"', ""),
    ("placed_nested.sdf", '<pose relative_to="inner::l2">', "<pose>"),
    ("placed_1_6.sdf", '<pose frame="base">', "<pose>"),
    ("placed_1_6.sdf", "<use_parent_model_frame>true", "<use_parent_model_frame>false"),
    ("placed_1_4.sdf", '<sdf version="1.4">', '<sdf version="1.5">'),
    ("placed_world.sdf", ' placement_frame="grip"', ""),
    ("placed_world.sdf", '<pose relative_to="table">0.5', "<pose>0.5"),
    ("placed_world.sdf", '<frame name="corner" attached_to="table">', '<frame name="corner">'),
    ("placed_static.sdf", "<pose>1 2 0 0 0 0.5</pose>", ""),
]
"""Each rule undone in its file: Drake then puts some body elsewhere (so the rule counts)."""


def _drake_poses(text: str, scratch: Path, q: np.ndarray) -> np.ndarray:
    """Drake's pose of every body for the file's text at Drake's configuration ``q``."""
    scratch.mkdir()
    path = scratch / "robot.sdf"
    path.write_text(text)
    plant = _plant(path, scratch)
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, q)
    poses = [plant.EvalBodyPoseInWorld(context, body) for body in _bodies(plant, set()).values()]
    return np.array([[*p.translation(), *p.rotation().matrix().ravel()] for p in poses])


@pytest.mark.parametrize(("name", "old", "new"), MUTATIONS, ids=lambda v: str(v)[:24])
def test_each_rule_moves_a_body_in_drake(name: str, old: str, new: str, tmp_path: Path) -> None:
    path = FIXTURES / name
    text = path.read_text()
    assert old in text, old
    space = cspace.load(path)
    q = space.conventions().to_drake(_draw(space, 1, seed=3)[0])
    before = _drake_poses(text, tmp_path / "before", q)
    after = _drake_poses(text.replace(old, new), tmp_path / "after", q)
    assert before.shape == after.shape and np.abs(before - after).max() > 1e-3


LIMITED = "<axis><xyz>0 0 1</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis>"
UNRESOLVED = {
    "unknown_frame": ('<pose relative_to="nowhere">0 0 1 0 0 0</pose>', ""),
    "cycle": (
        '<pose relative_to="f">0 0 1 0 0 0</pose>',
        '<frame name="f"><pose relative_to="g"/></frame>'
        '<frame name="g"><pose relative_to="f"/></frame>',
    ),
    "world_in_a_model": ('<pose relative_to="world">0 0 1 0 0 0</pose>', ""),
    "five_numbers": ("<pose>0 0 1 0 0</pose>", ""),
    "zero_quaternion": ('<pose rotation_format="quat_xyzw">0 0 1 0 0 0 0</pose>', ""),
    "frame_attribute_after_1_6": ('<pose frame="a">0 0 1 0 0 0</pose>', ""),
}
"""A pose of link 'b' Drake refuses to resolve (and what else the model holds)."""


@pytest.mark.parametrize("case", sorted(UNRESOLVED))
def test_a_pose_drake_cannot_resolve_leaves_no_model_but_the_c_space(
    case: str, tmp_path: Path
) -> None:
    pose, extra = UNRESOLVED[case]
    path = tmp_path / "robot.sdf"
    path.write_text(
        '<sdf version="1.9">\n<model name="m">\n<link name="a"/>\n'
        f'<link name="b">{pose}</link>\n{extra}\n'
        '<joint name="bolt" type="fixed"><parent>world</parent><child>a</child></joint>\n'
        f'<joint name="j" type="revolute"><parent>a</parent><child>b</child>{LIMITED}</joint>\n'
        "</model>\n</sdf>\n"
    )
    plant = MultibodyPlant(0.0)
    with pytest.raises(RuntimeError):  # Drake's own parser refuses the file
        Parser(plant).AddModels(str(path))
    assert cspace.inspect(path).manifold.notation == "R^1"  # the C-space, as before
    with pytest.raises(ModelBuildError) as raised:
        cspace.pinocchio_model(path)
    message = str(raised.value)
    assert isinstance(raised.value, cspace.RobotFileError) and "\n" not in message
    assert message.startswith(f"{path}: ") and "joint 'j' (line 7)" in message


def test_a_model_placed_relative_to_a_frame_is_refused_at_the_top(tmp_path: Path) -> None:
    """The document's own model may not be placed relative_to anything (Drake refuses it):
    every joint is unplaced, the first one named; the command still reports the C-space."""
    path = tmp_path / "robot.sdf"
    path.write_text(
        '<sdf version="1.9">\n<model name="m">\n<pose relative_to="a">1 0 0 0 0 0</pose>\n'
        '<link name="a"/><link name="b"/>\n'
        '<joint name="bolt" type="fixed"><parent>world</parent><child>a</child></joint>\n'
        f'<joint name="j" type="revolute"><parent>a</parent><child>b</child>{LIMITED}</joint>\n'
        "</model>\n</sdf>\n"
    )
    plant = MultibodyPlant(0.0)
    with pytest.raises(RuntimeError, match="top level model must be left empty"):
        Parser(plant).AddModels(str(path))
    with pytest.raises(ModelBuildError, match=r"joint 'bolt' \(line 5\) has no placement"):
        cspace.pinocchio_model(path)
    run = run_cli("inspect", "--format", "json", str(path))
    assert run.code == 0 and json.loads(run.stdout)["manifold"]["notation"] == "R^1"


def _drake_body_positions(path: Path, scratch: Path, names: tuple[str, ...]) -> np.ndarray:
    """Where Drake puts the named bodies of the file at its default configuration."""
    plant = _plant(path, scratch)
    context = plant.CreateDefaultContext()
    poses = [plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(n)) for n in names]
    return np.array([p.translation() for p in poses])


def test_a_quaternion_off_unit_places_the_bodies_where_drake_does(tmp_path: Path) -> None:
    """libsdformat keeps a quaternion as written, and the inverse of its pose moves positions
    off a rigid transform: Drake puts link 'a' 3e-4 m from where its pose says, and so
    must cspace's model (the numbers are Drake's, from the file as written)."""
    path = tmp_path / "robot.sdf"
    path.write_text(
        '<sdf version="1.9"><model name="m">\n'
        '<link name="a"><pose rotation_format="quat_xyzw">0 0 1 0.1 0.2 0.3 0.927</pose></link>\n'
        '<link name="b"><pose relative_to="a">0 0.3 0 0 0 0</pose></link>\n'
        '<joint name="fix" type="fixed"><parent>world</parent><child>a</child></joint>\n'
        f'<joint name="j" type="revolute"><parent>a</parent><child>b</child>{LIMITED}</joint>\n'
        "</model></sdf>\n"
    )
    drake = _drake_body_positions(path, tmp_path, ("a", "b"))
    expected = [
        [-2.89455118e-04, 4.39423509e-05, 1.00006719],
        [-0.15522382, 0.24010201, 1.09167327],
    ]
    np.testing.assert_allclose(drake, expected, atol=1e-8)
    model = cspace.pinocchio_model(path)
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    ours = [data.oMf[model.getFrameId(n, pin.FrameType.BODY)].translation for n in ("a", "b")]
    np.testing.assert_allclose(ours, drake, rtol=0, atol=TOLERANCE)
    assert placement_errors(path, tmp_path)[1] < TOLERANCE


UNIT = (0.1, 0.2, 0.3, 0.927) / np.linalg.norm((0.1, 0.2, 0.3, 0.927))
ROTATIONS = {
    "review_fixture": ("quat", (0.1, 0.2, 0.3, 0.927)),  # norm 0.99966
    "off_by_1e-6": ("quat", tuple(UNIT * (1 + 1e-6))),
    "off_by_1e-2": ("quat", tuple(UNIT * (1 - 1e-2))),
    "exactly_unit": ("quat", (0.5, -0.5, 0.5, 0.5)),
    "rpy": ("rpy", (0.3, -0.4, 0.5)),
}
"""The rotation of every pose of `_ROTATED` (x y z w for a quaternion), and how written."""

_ROTATED = """<sdf version="1.9"><model name="m">
<link name="a"><pose{r}>0 0 1 {q}</pose></link>
<link name="b"><pose relative_to="a">0 0.3 0 0 0 0</pose></link>
<frame name="f" attached_to="a"><pose>0.2 0 0 0.3 0 0</pose></frame>
<link name="c"><pose relative_to="b"{r}>0.1 0.2 0 {q}</pose></link>
<model name="inner" placement_frame="tip">
  <pose relative_to="c">0 0 0.2 0 0 0</pose>
  <link name="base"/><link name="tip"><pose{r}>0 0.1 0.1 {q}</pose></link>
  <joint name="t" type="revolute"><parent>base</parent><child>tip</child>{limited}</joint>
</model>
<joint name="fix" type="fixed"><parent>world</parent><child>a</child></joint>
<joint name="j" type="revolute"><parent>a</parent><child>b</child>{limited}</joint>
<joint name="k" type="prismatic"><parent>b</parent><child>c</child>
  <axis><xyz expressed_in="f">1 0 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis>
</joint>
<joint name="n" type="fixed"><parent>c</parent><child>inner::base</child></joint>
</model></sdf>
"""
"""Each rotation where a joint is placed relative to it: a link's, a link's along a chain
of relative_to, a nested model's placement frame; and an axis in a frame ('f') whose
product of quaternions from the model's frame is not the joint's."""


def _rotated(case: str, path: Path) -> Path:
    how, numbers = ROTATIONS[case]
    attribute = ' rotation_format="quat_xyzw"' if how == "quat" else ""
    written = " ".join(repr(float(v)) for v in numbers)
    path.write_text(_ROTATED.format(r=attribute, q=written, limited=LIMITED))
    return path


@pytest.mark.parametrize("case", sorted(ROTATIONS))
def test_every_rotation_places_the_bodies_where_drake_does(case: str, tmp_path: Path) -> None:
    """Drake's bodies and cspace's agree within 1e-9 for a quaternion of any norm near 1,
    and those off unit do move Drake's bodies off where rigid transforms put them (link
    'a' is posed at 0 0 1, welded to the world), so that the comparison holds the rule."""
    path = _rotated(case, tmp_path / "robot.sdf")
    compared, worst = placement_errors(path, tmp_path)
    assert compared == 5 and worst < TOLERANCE, f"{case}: {worst:.3g} from Drake"
    moved = np.abs(_drake_body_positions(path, tmp_path, ("a",))[0] - [0, 0, 1]).max()
    assert (moved > 100 * TOLERANCE) == case.startswith(("off", "review")), moved


def test_a_quaternion_far_from_unit_leaves_no_model_but_the_c_space(tmp_path: Path) -> None:
    """A norm outside QUATERNION_NORMS (Drake reads it) is taken for a mistake: one line."""
    path = tmp_path / "robot.sdf"
    path.write_text(
        _ROTATED.format(r=' rotation_format="quat_xyzw"', q="0 0 0 2.5", limited=LIMITED)
    )
    _plant(path, tmp_path)  # Drake reads it
    assert cspace.inspect(path).manifold.notation == "R^3"
    with pytest.raises(ModelBuildError, match=r"^[^\n]*joint 'fix' \(line 11\) has no placement"):
        cspace.pinocchio_model(path)
