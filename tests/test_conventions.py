"""Layout maps between conventions, checked against Pinocchio and MuJoCo themselves.

Every map round-trips exactly on canonical input, over every factor kind and several
batch shapes; forward kinematics through Pinocchio of a configuration equal forward
kinematics through MuJoCo of its mapped qpos (body placements to 1e-9); velocities agree
with each tool's own finite difference of two configurations (``pinocchio.difference``,
``mujoco.mj_differentiatePos``).
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from test_pairs import mujoco_converted

import cspace
from cspace.conventions import MujocoLayout

from conftest import REPO, ROBOTS

SHAPES = [(), (5,), (2, 3)]

MJCF = [
    ROBOTS / "mjcf_every_joint.xml",
    ROBOTS / "mjcf_balls.xml",
    REPO / "tests" / "pairs" / "ball.xml",
    REPO / "tests" / "pairs" / "quadruped.xml",
]

# (URDF, its MuJoCo conversion needs a floating joint added) for URDF <-> MuJoCo maps.
URDF = [
    ("arm7.urdf", False),
    ("quadruped_nobase.urdf", True),
    ("mobile_manipulator.urdf", False),  # planar: MuJoCo's two slides and a hinge
    ("gripper_mimic.urdf", False),  # the mimic joint is a joint of its own in MuJoCo
    ("turntable_multiturn.urdf", False),
]


def _sample(space: cspace.ConfigurationSpace, shape: tuple[int, ...], seed: int = 0):  # type: ignore[no-untyped-def]
    """Configurations of ``shape``: within the limits; unbounded lines within +-3 m."""
    free = {
        c.name: (-3.0, 3.0)
        for c in space.coordinates
        if not c.wraps and np.isinf(c.lower) and np.isinf(c.upper)
    }
    x = space.sample(int(np.prod(shape)), np.random.default_rng(seed), bounds=free)
    return x.reshape(*shape, space.size)


def _space_and_conventions(urdf: str, floating: bool, tmp_path: Path):  # type: ignore[no-untyped-def]
    path = ROBOTS / urdf
    mjcf = mujoco_converted(path, tmp_path / (path.stem + ".xml"), floating=floating)
    space = cspace.load(path, "floating" if floating else None)
    return space, space.conventions(mujoco=mjcf), mjcf


@pytest.mark.parametrize("path", MJCF, ids=lambda p: p.name)
@pytest.mark.parametrize("shape", SHAPES, ids=str)
def test_mujoco_round_trips_on_the_robots_own_mjcf(path: Path, shape) -> None:
    space = cspace.load(path)
    conventions = space.conventions()
    x = _sample(space, shape)
    qpos = conventions.to_mujoco(x)
    assert qpos.shape == (*shape, space.mujoco.nq)
    np.testing.assert_array_equal(conventions.from_mujoco(qpos), x)
    np.testing.assert_array_equal(conventions.to_mujoco(conventions.from_mujoco(qpos)), qpos)
    dx = np.random.default_rng(1).normal(size=(*shape, space.dimension))
    np.testing.assert_array_equal(
        conventions.from_mujoco_velocity(conventions.to_mujoco_velocity(dx)), dx
    )
    q = conventions.to_pinocchio(x)
    np.testing.assert_allclose(conventions.from_pinocchio(q), x, rtol=0, atol=1e-15)
    v = conventions.to_pinocchio_velocity(x, dx)
    np.testing.assert_allclose(conventions.from_pinocchio_velocity(x, v), dx, rtol=0, atol=1e-12)


def _body_placements_agree(pin_model, q: np.ndarray, mj_model, qpos: np.ndarray) -> None:  # type: ignore[no-untyped-def]
    data, pin_data = mujoco.MjData(mj_model), pin_model.createData()
    data.qpos[:] = qpos
    mujoco.mj_kinematics(mj_model, data)
    pin.framesForwardKinematics(pin_model, pin_data, q)
    checked = 0
    for body in range(1, mj_model.nbody):
        name = mujoco.mj_id2name(mj_model, mujoco.mjtObj.mjOBJ_BODY, body)
        if not name or not pin_model.existFrame(name, pin.FrameType.BODY):
            continue
        placement = pin_data.oMf[pin_model.getFrameId(name, pin.FrameType.BODY)]
        np.testing.assert_allclose(placement.translation, data.xpos[body], rtol=0, atol=1e-9)
        np.testing.assert_allclose(
            placement.rotation, data.xmat[body].reshape(3, 3), rtol=0, atol=1e-9
        )
        checked += 1
    assert checked >= 2


@pytest.mark.parametrize("path", MJCF, ids=lambda p: p.name)
def test_pinocchio_and_mujoco_place_every_body_alike(path: Path) -> None:
    space = cspace.load(path)
    conventions = space.conventions()
    model = mujoco.MjModel.from_xml_path(str(path))
    built = cspace.pinocchio_model(path)
    for x in _sample(space, (8,), seed=3):
        _body_placements_agree(built, conventions.to_pinocchio(x), model, conventions.to_mujoco(x))


@pytest.mark.parametrize(("urdf", "floating"), URDF)
def test_a_urdf_and_mujocos_conversion_of_it_place_every_body_alike(
    tmp_path: Path, urdf: str, floating: bool
) -> None:
    space, conventions, mjcf = _space_and_conventions(urdf, floating, tmp_path)
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    built = cspace.pinocchio_model(ROBOTS / urdf, "floating" if floating else None)
    for x in _sample(space, (8,), seed=4):
        qpos = conventions.to_mujoco(x)
        _body_placements_agree(built, conventions.to_pinocchio(x), model, qpos)
        np.testing.assert_allclose(conventions.from_mujoco(qpos), x, rtol=0, atol=1e-15)


@pytest.mark.parametrize(("urdf", "floating"), URDF)
def test_velocities_are_each_tools_own_finite_difference(
    tmp_path: Path, urdf: str, floating: bool
) -> None:
    """v and qvel of a tangent dx match Pinocchio's and MuJoCo's differences of x and
    x moved a little along dx (first order: to 1e-6 for a step of 1e-7)."""
    space, conventions, mjcf = _space_and_conventions(urdf, floating, tmp_path)
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    built = cspace.pinocchio_model(ROBOTS / urdf, "floating" if floating else None)
    rng = np.random.default_rng(5)
    eps = 1e-7
    for x in _sample(space, (6,), seed=5):
        dx = rng.normal(size=space.dimension)
        moved = space.integrate(x, eps * dx)
        v = pin.difference(built, conventions.to_pinocchio(x), conventions.to_pinocchio(moved))
        np.testing.assert_allclose(conventions.to_pinocchio_velocity(x, dx), v / eps, atol=1e-5)
        qvel = np.zeros(model.nv)
        mujoco.mj_differentiatePos(
            model, qvel, eps, conventions.to_mujoco(x), conventions.to_mujoco(moved)
        )
        np.testing.assert_allclose(conventions.to_mujoco_velocity(dx), qvel, atol=1e-5)


def test_a_floating_base_velocity_is_in_the_body_frame_for_pinocchio_only(tmp_path: Path) -> None:
    space, conventions, _ = _space_and_conventions("quadruped_nobase.urdf", True, tmp_path)
    x = space.neutral()
    x[space.names.index("root_joint.qw") : space.names.index("root_joint.qz") + 1] = [
        np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)
    ]  # fmt: skip  # turned by 90 degrees about z
    dx = np.zeros(space.dimension)
    dx[0] = 1.0  # moving along the world's x axis
    v = conventions.to_pinocchio_velocity(x, dx)
    np.testing.assert_allclose(v[:3], [0.0, -1.0, 0.0], atol=1e-15)  # the body's -y axis
    np.testing.assert_allclose(conventions.to_mujoco_velocity(dx)[:3], [1.0, 0.0, 0.0])


@pytest.mark.parametrize("shape", SHAPES, ids=str)
def test_named_values_in_any_order(shape) -> None:
    space = cspace.load(ROBOTS / "gripper_mimic.urdf")
    conventions = space.conventions()
    x = _sample(space, shape)
    report = cspace.inspect(ROBOTS / "gripper_mimic.urdf")
    mimic = next(j for j in report.joints if j.mimic is not None)
    names = [mimic.name, *reversed(space.joints)]
    values = conventions.to_named(x, names)
    assert values.shape == (*shape, len(names))
    leader = x[..., space.names.index(mimic.mimic.joint)]
    np.testing.assert_allclose(
        values[..., 0], mimic.mimic.multiplier * leader + mimic.mimic.offset, rtol=0, atol=0
    )
    np.testing.assert_array_equal(conventions.from_named(values, names), x)


def test_named_continuous_angles_are_wrapped_on_the_way_in() -> None:
    space = cspace.load(ROBOTS / "arm7.urdf")
    conventions = space.conventions()
    x = space.neutral()
    values = conventions.to_named(x, space.joints)
    values[space.joints.index("wrist_roll")] = 3 * np.pi + 0.25  # as a ROS driver may send
    back = conventions.from_named(values, space.joints)
    assert back[space.names.index("wrist_roll")] == pytest.approx(-np.pi + 0.25)


def test_named_errors_name_the_joints() -> None:
    space = cspace.load(ROBOTS / "quadruped_nobase.urdf", "floating")
    conventions = space.conventions()
    x = space.neutral()
    with pytest.raises(cspace.JointMatchError, match=r"'root_joint' \(floating\) has 7"):
        conventions.to_named(x, ["root_joint"])
    with pytest.raises(cspace.JointMatchError, match="'lf_knee' is named twice"):
        conventions.to_named(x, ["lf_knee", "lf_knee"])
    with pytest.raises(cspace.JointMatchError, match="'elbow' is unknown") as caught:
        conventions.to_named(x, ["elbow"])
    assert caught.value.joints == ("elbow",) and caught.value.code == "joint-match"
    legs = [j for j in space.joints if j != "root_joint"]
    with pytest.raises(cspace.JointMatchError, match=r"no value for joint\(s\) root_joint"):
        conventions.from_named(np.zeros(len(legs)), legs)
    back = conventions.from_named(np.zeros(len(legs)), legs, default=x)
    np.testing.assert_array_equal(back, x)


def test_mujoco_errors_name_the_joints(tmp_path: Path) -> None:
    space = cspace.load(ROBOTS / "arm7.urdf")
    with pytest.raises(cspace.JointMatchError, match="was not read from MJCF"):
        space.conventions().to_mujoco(space.neutral())
    with pytest.raises(cspace.JointMatchError, match="has no joint 'root_joint'"):
        cspace.load(ROBOTS / "quadruped_nobase.urdf", "floating").conventions(
            mujoco=REPO / "tests" / "pairs" / "ball.xml"
        )
    extra = mujoco_converted(ROBOTS / "arm7.urdf", tmp_path / "arm7.xml")
    text = extra.read_text().replace(
        '<body name="tool0"',
        '<body name="tool0"><joint name="spare" type="slide"/></body><body name="x"',
    )
    extra.write_text(text)
    with pytest.raises(cspace.JointMatchError, match=r"joint\(s\) the robot does not: spare"):
        space.conventions(mujoco=extra)
    with pytest.raises(cspace.JointMatchError, match="is a urdf file"):
        space.conventions(mujoco=ROBOTS / "arm7.urdf")


def test_a_mujoco_model_object_is_a_layout_too() -> None:
    path = REPO / "tests" / "pairs" / "ball.xml"
    model = mujoco.MjModel.from_xml_path(str(path))
    from_model = MujocoLayout.from_model(model)
    assert from_model == MujocoLayout.from_report(cspace.inspect(path))
    space = cspace.load(REPO / "tests" / "pairs" / "ball.sdf")
    x = _sample(space, (4,))
    a = space.conventions(mujoco=model).to_mujoco(x)
    np.testing.assert_array_equal(a, space.conventions(mujoco=path).to_mujoco(x))


# --- trajectories --------------------------------------------------------------------

TRAJECTORY_ROBOTS = [
    (ROBOTS / "mjcf_every_joint.xml", None),
    (ROBOTS / "sdf_every_joint.sdf", None),
    (ROBOTS / "quadruped_nobase.urdf", "floating"),
    (ROBOTS / "mobile_manipulator.urdf", None),
]


def _random_walk(space: cspace.ConfigurationSpace, steps: int, step: float, seed: int):  # type: ignore[no-untyped-def]
    """A walk of small tangent steps from a sample: crosses +-pi on circles, w = 0 on
    rotations; canonical at every sample, as a logger would store it."""
    rng = np.random.default_rng(seed)
    drift = np.zeros(space.dimension)  # along circles and whole rotations: they wrap
    lines: list[int] = []
    for slot in space.slots:
        if (slot.factor.wraps and slot.factor.dimension == 1) or slot.name.endswith("rotation"):
            drift[slot.tangent] = 2.0
        elif not slot.factor.wraps:
            lines.append(slot.column)
    lower = np.array([c.lower for c in space.coordinates])[lines]
    upper = np.array([c.upper for c in space.coordinates])[lines]
    out = [_sample(space, (), seed)]
    while len(out) < steps:
        direction = drift + rng.normal(size=space.dimension)
        moved = space.integrate(out[-1], step * direction / np.linalg.norm(direction))
        moved[lines] = np.clip(moved[lines], lower, upper)  # lines stay within their limits
        if space.contains(moved):  # a ball joint's cone: the step is drawn again
            out.append(space.canonicalize(moved))
    return np.array(out)


@pytest.mark.parametrize(
    ("path", "root"), TRAJECTORY_ROBOTS, ids=lambda v: getattr(v, "name", str(v))
)
def test_unwrapping_a_random_walk_leaves_no_jump_above_the_step(path: Path, root) -> None:
    space = cspace.load(path, root)
    conventions = space.conventions()
    step = 0.2
    walk = _random_walk(space, 400, step, seed=11)
    lift = conventions.unwrap(walk)
    np.testing.assert_allclose(conventions.wrap(lift), walk, rtol=0, atol=1e-12)
    jumps = np.abs(np.diff(lift, axis=0)).max(axis=0)
    crossed = np.abs(np.diff(walk, axis=0)).max(axis=0)
    wrapping = [i for i, c in enumerate(space.coordinates) if c.wraps]
    assert (crossed[wrapping] > 1.0).any()  # the walk did cross a wrap...
    assert jumps.max() <= step + 1e-9  # ...and the lift has no jump


@pytest.mark.parametrize("convention", ["canonical", "pinocchio", "mujoco"])
@pytest.mark.parametrize("shape", [(7,), (3, 7)], ids=str)
def test_unwrap_then_wrap_is_the_identity_in_every_convention(convention: str, shape) -> None:
    space = cspace.load(ROBOTS / "mjcf_every_joint.xml")
    conventions = space.conventions()
    x = _sample(space, shape, seed=2)
    stored = conventions.from_canonical(x, convention)
    lift = conventions.unwrap(stored, convention)
    assert lift.shape == (*shape, space.size)
    np.testing.assert_allclose(conventions.wrap(lift, convention), stored, rtol=0, atol=1e-12)


def test_a_continuous_joint_crossing_pi_is_lifted_past_it() -> None:
    space = cspace.load(ROBOTS / "arm7.urdf")
    conventions = space.conventions()
    column = space.names.index("wrist_roll")
    walk = np.tile(space.neutral(), (5, 1))
    walk[:, column] = [3.0, 3.1, -3.1, -3.0, -2.9]  # through pi, stored canonically
    lift = conventions.unwrap(walk)
    np.testing.assert_allclose(np.diff(lift[:, column]), [0.1, 2 * np.pi - 6.2, 0.1, 0.1])
    q = conventions.to_pinocchio(walk)  # (cos, sin): the same lift from Pinocchio's q
    np.testing.assert_allclose(conventions.unwrap(q, "pinocchio"), lift, atol=1e-12)


def test_a_quaternion_keeps_its_sign_along_a_trajectory() -> None:
    space = cspace.load(ROBOTS / "mjcf_balls.xml")
    conventions = space.conventions()
    rotation = next(s for s in space.slots if s.factor.size == 4)
    angles = np.linspace(2.8, 3.5, 8)  # about z, through pi: w crosses 0
    walk = np.tile(space.neutral(), (8, 1))
    walk[:, rotation.columns] = np.stack(
        [np.cos(angles / 2), 0 * angles, 0 * angles, np.sin(angles / 2)], axis=-1
    )
    walk = space.canonicalize(walk)
    assert (np.diff(np.sign(walk[:, rotation.column + 3])) != 0).any()  # canonical flips
    lift = conventions.unwrap(walk)
    dots = np.sum(lift[1:, rotation.columns] * lift[:-1, rotation.columns], axis=-1)
    assert (dots > 0.99).all()


def test_an_unknown_convention_is_an_error_not_canonical() -> None:
    space = cspace.load(REPO / "tests" / "pairs" / "quadruped.xml")
    conventions = space.conventions()
    qpos = conventions.to_mujoco(space.neutral())
    for call in (
        lambda: conventions.convert(qpos, "MuJoCo", "canonical"),  # type: ignore[arg-type]
        lambda: conventions.unwrap(qpos[None], "MuJoCo"),  # type: ignore[arg-type]
        lambda: conventions.names("named"),  # type: ignore[arg-type]
    ):
        with pytest.raises(cspace.errors.ArgumentError, match="convention must be one of"):
            call()


def test_an_mjcf_robot_with_a_root_joint_maps_to_pinocchio_not_to_mujoco() -> None:
    space = cspace.load(REPO / "tests" / "pairs" / "arm7.xml", "floating")
    conventions = space.conventions()  # the MuJoCo map is built only when used
    x = _sample(space, (3,))
    np.testing.assert_allclose(
        conventions.from_pinocchio(conventions.to_pinocchio(x)), x, atol=4e-16
    )
    with pytest.raises(cspace.JointMatchError, match="has no joint 'root_joint'"):
        conventions.to_mujoco(x)
