"""Whole robots: the configuration space's axioms, agreement with Pinocchio, and its errors."""

from __future__ import annotations

import functools
import math
import pickle

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cspace
from cspace import rotations
from cspace._formats.shared import erd
from cspace._joint_table import KIND_OF_MODEL, factors_of, kind_of
from cspace._manifold import NormalForm
from cspace._reports.report import Limits
from cspace.space import ConfigurationSpace
from cspace.space._geometry.factors import Circle, Line, Rotation

from conftest import ROBOTS

ERD = erd.robots_dir()
TALOS = str(ERD / "talos_data/robots/talos_reduced.urdf")
ROMEO = str(ERD / "romeo_description/urdf/romeo.urdf")  # mimic joints Pinocchio keeps free

CASES = [
    (str(ROBOTS / "arm7.urdf"), None),
    (str(ROBOTS / "diffdrive_nobase.urdf"), "planar"),
    (str(ROBOTS / "gripper_mimic.urdf"), None),
    (str(ROBOTS / "mobile_manipulator.urdf"), None),
    (str(ROBOTS / "quadrotor_floating.urdf"), None),
    (str(ROBOTS / "quadruped_nobase.urdf"), "floating"),
    (str(ROBOTS / "turntable_multiturn.urdf"), None),
    (str(ROBOTS / "mjcf_every_joint.xml"), None),
    (str(ROBOTS / "sdf_every_joint.sdf"), None),
    (TALOS, "floating"),
    (ROMEO, "floating"),
]
URDF_CASES = [c for c in CASES if c[0].endswith(".urdf")]


def case_id(case: tuple[str, str | None]) -> str:
    name = case[0].rsplit("/", 1)[-1]
    return name if case[1] is None else f"{name}.{case[1]}"


@functools.cache
def space_of(path: str, root_joint: str | None) -> ConfigurationSpace:
    return cspace.load(path, root_joint=root_joint)


@functools.cache
def pin_model(path: str, root_joint: str | None) -> pin.Model:
    args = (
        ()
        if root_joint is None
        else (
            {"floating": pin.JointModelFreeFlyer, "planar": pin.JointModelPlanar}[root_joint](),
            "root_joint",
        )
    )
    try:
        return pin.buildModelFromUrdf(path, *args, mimic=True)
    except Exception:  # romeo: Pinocchio cannot keep these mimic joints dependent
        return pin.buildModelFromUrdf(path, *args, mimic=False)


def unbounded(space: ConfigurationSpace) -> dict[str, tuple[float, float]]:
    return {
        s.name: (-2.0, 2.0)
        for s in space.slots
        if isinstance(s.factor, Line) and not s.factor.bounded
    }


def other_representatives(
    space: ConfigurationSpace, x: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    """The same configurations written differently: theta + 2 k pi, -h."""
    y = x.copy()
    for s in space.slots:
        if isinstance(s.factor, Circle):
            y[..., s.column] += 2 * math.pi * rng.integers(-3, 4, size=x.shape[:-1])
        elif isinstance(s.factor, Rotation):
            y[..., s.column : s.column + 4] *= -1
    return y


def tangent(space: ConfigurationSpace, rng: np.random.Generator, shape, mode: str) -> np.ndarray:
    """Tangent steps: tiny (near), or nearly half a turn on every S^1 and SO(3) factor."""
    v = rng.uniform(-0.5, 0.5, size=(*shape, space.dimension))
    if mode == "generic":
        return v
    eps = 10.0 ** rng.uniform(-12, -4)
    for s in space.slots:
        t = slice(s.tangent_column, s.tangent_column + s.factor.dimension)
        if mode == "near":
            v[..., t] *= eps
        elif isinstance(s.factor, Circle):
            v[..., t] = (math.pi - eps) * np.sign(v[..., t])
        elif isinstance(s.factor, Rotation):
            axis = v[..., t] / np.linalg.norm(v[..., t], axis=-1, keepdims=True)
            v[..., t] = (math.pi - eps) * axis
    return v


def reference_distance(space: ConfigurationSpace, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The product metric assembled factor by factor (what the compiled kernel must give)."""
    total = np.zeros(a.shape[:-1])
    for s, w in zip(space.slots, space.weights, strict=True):
        cols = slice(s.column, s.column + s.factor.size)
        total += (w * s.factor.distance(a[..., cols], b[..., cols])) ** 2
    return np.sqrt(total)


@settings(max_examples=60, deadline=None)
@given(
    st.sampled_from(CASES),
    st.sampled_from([(), (5,), (2, 3)]),
    st.sampled_from(["generic", "near", "antipodal"]),
    st.integers(0, 2**32 - 1),
)
def test_space_axioms(case, shape, mode, seed) -> None:
    space = space_of(*case)
    rng = np.random.default_rng(seed)
    n = space.size
    count = math.prod(shape)
    a = space.sample(count, rng, unbounded(space)).reshape(*shape, n)
    b = space.integrate(a, tangent(space, rng, shape, mode))
    c = space.sample(count, rng, unbounded(space)).reshape(*shape, n)
    a_raw = other_representatives(space, a, rng)

    # canonical form: idempotent (bit-exact), one per configuration
    ca = space.canonicalize(a_raw)
    assert ca.shape == (*shape, n)
    assert space.canonicalize(ca).tobytes() == ca.tobytes()
    for s in space.slots:  # the compiled kernel computes exactly what the factors define
        cols = slice(s.column, s.column + s.factor.size)
        assert ca[..., cols].tobytes() == s.factor.canonicalize(a_raw[..., cols]).tobytes()
    assert np.all(np.asarray(space.distance(ca, a)) <= 1e-9)
    np.testing.assert_array_equal(space.contains(a), np.ones(shape, dtype=bool))

    d = space.distance
    assert np.all(np.asarray(d(a, a)) == 0.0)
    np.testing.assert_allclose(d(a_raw, a), 0.0, atol=1e-9)
    np.testing.assert_allclose(d(a, b), d(b, a), atol=1e-12)
    assert np.all(np.asarray(d(a, b)) <= np.asarray(d(a, c)) + np.asarray(d(c, b)) + 1e-9)
    np.testing.assert_allclose(d(a_raw, b), reference_distance(space, ca, b), atol=1e-9)

    # interpolation: exact canonical ends, equidistant midpoint, kernel = factors
    assert space.interpolate(a_raw, b, 0.0).tobytes() == ca.tobytes()
    assert space.interpolate(a, b, np.ones(shape)).tobytes() == space.canonicalize(b).tobytes()
    mid = space.interpolate(a_raw, b, 0.5)
    np.testing.assert_allclose(d(a, mid), d(mid, b), atol=1e-8)
    for s in space.slots:
        cols = slice(s.column, s.column + s.factor.size)
        ref = s.factor.interpolate(ca[..., cols], b[..., cols], np.full(shape, 0.5))
        np.testing.assert_allclose(mid[..., cols], ref, atol=1e-12)

    # tangent pair
    v = space.difference(a_raw, b)
    assert v.shape == (*shape, space.dimension)
    np.testing.assert_allclose(d(space.integrate(a, v), b), 0.0, atol=1e-9)

    # conversions
    q = space.to_pinocchio(a_raw)
    assert q.shape == (*shape, space.nq)
    np.testing.assert_allclose(space.from_pinocchio(q), ca, atol=1e-14)
    one = ca.reshape(-1, n)[0]
    np.testing.assert_allclose(space.from_dict(space.to_dict(one)), one, atol=0)


@pytest.mark.parametrize("case", URDF_CASES, ids=case_id)
def test_agrees_with_pinocchio(case) -> None:
    space = space_of(*case)
    model = pin_model(*case)
    report = cspace.inspect(*case)
    assert space.nq == model.nq
    rng = np.random.default_rng(11)
    a = space.sample(30, rng, unbounded(space))
    b = space.integrate(a, tangent(space, rng, (30,), "antipodal"))
    qa, qb = space.to_pinocchio(a), space.to_pinocchio(b)
    joints = {j.name: j for j in report.joints}
    ours = space.difference(a, b)
    for i in range(len(a)):
        np.testing.assert_allclose(pin.normalize(model, qa[i]), qa[i], atol=1e-15)
        v = pin.difference(model, qa[i], qb[i])
        for s in space.slots:
            j = joints[s.joint]
            if isinstance(s.factor, Rotation):
                k = s.q_index
                ra = pin.Quaternion(qa[i, k + 3], *qa[i, k : k + 3]).toRotationMatrix()
                rb = pin.Quaternion(qb[i, k + 3], *qb[i, k : k + 3]).toRotationMatrix()
                angle = np.linalg.norm(pin.log3(ra.T @ rb))
                cols = slice(s.column, s.column + 4)
                assert s.factor.distance(a[i, cols], b[i, cols]) == pytest.approx(angle, abs=1e-9)
                t = slice(s.tangent_column, s.tangent_column + 3)
                np.testing.assert_allclose(ours[i, t], pin.log3(ra.T @ rb), atol=1e-9)
            elif j.nv == 1:  # a one-dof joint: R^1 or S^1, same tangent as Pinocchio's
                gap = ours[i, s.tangent_column] - v[j.v_index]
                if isinstance(s.factor, Circle):
                    # modulo 2 pi (a half turn is pi or -pi); Pinocchio's (cos, sin)
                    # arithmetic is good to ~1e-9 rad only, next to a half turn
                    gap = (gap + math.pi) % (2 * math.pi) - math.pi
                assert abs(gap) <= (1e-8 if isinstance(s.factor, Circle) else 1e-12)
    for fill in space.layout.fills:  # mimic joints Pinocchio keeps free get their leader's value
        leader = a[:, space.names.index(fill.leader)] if fill.leader else 0.0
        value = fill.multiplier * leader + fill.offset
        got = (
            np.arctan2(qa[:, fill.q_index + 1], qa[:, fill.q_index])
            if fill.cos_sin
            else qa[:, fill.q_index]
        )
        np.testing.assert_allclose(got, value, atol=1e-12)


@pytest.mark.parametrize("case", URDF_CASES, ids=case_id)
def test_from_pinocchio_reads_what_pinocchio_writes(case) -> None:
    space = space_of(*case)
    model = pin_model(*case)
    rng = np.random.default_rng(5)
    q0 = pin.neutral(model)
    for _ in range(10):
        q = pin.integrate(model, q0, rng.uniform(-3, 3, model.nv))
        back = space.to_pinocchio(space.from_pinocchio(q))
        if not space.layout.fills:
            np.testing.assert_allclose(pin.difference(model, q, back), 0.0, atol=1e-12)
        np.testing.assert_allclose(space.from_pinocchio(back), space.from_pinocchio(q), atol=1e-14)


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_coordinates_match_the_report(case) -> None:
    space = space_of(*case)
    report = cspace.inspect(*case)
    section = report.to_dict()["coordinates"]
    assert space.dimension == report.dimension == section["dimension"]
    assert [e["name"] for e in section["entries"]] == list(space.names)
    assert section["neutral"] == space.neutral().tolist()
    assert space.contains(space.neutral())


def test_talos_with_a_floating_base() -> None:
    space = space_of(TALOS, "floating")
    assert (space.size, space.dimension, space.nq) == (39, 38, 39)
    assert space.names[:7] == tuple(
        f"root_joint.{c}" for c in ("x", "y", "z", "qw", "qx", "qy", "qz")
    )
    assert space.neutral()[3:7].tolist() == [1.0, 0.0, 0.0, 0.0]


def test_romeo_mimic_joints_have_no_coordinates_but_fill_q() -> None:
    space = space_of(ROMEO, "floating")
    report = cspace.inspect(ROMEO, "floating")
    assert "mimic-kept-free" in {d.code for d in report.diagnostics}
    mimics = [j.name for j in report.joints if j.kind.value == "mimic"]
    assert mimics and not set(mimics) & set(space.joints)
    assert {f.joint for f in space.layout.fills} == set(mimics)
    assert space.nq == space.size + len(mimics)


def test_distance_broadcasts_one_against_many() -> None:
    space = space_of(str(ROBOTS / "quadrotor_floating.urdf"), None)
    rng = np.random.default_rng(0)
    many = space.sample(7, rng, unbounded(space))
    one = many[3]
    d = space.distance(one, many)
    assert d.shape == (7,) and d[3] == 0.0
    for i in range(7):
        assert d[i] == pytest.approx(space.distance(one, many[i]), abs=1e-15)
    path = space.interpolate(many[0], many[1], np.linspace(0, 1, 4))
    assert path.shape == (4, space.size)
    grid = space.distance(many[:, None, :], many[None, :, :])
    assert grid.shape == (7, 7)
    np.testing.assert_allclose(grid, grid.T, atol=1e-12)


def test_weights_scale_each_joints_contribution() -> None:
    space = space_of(str(ROBOTS / "quadrotor_floating.urdf"), None)
    rng = np.random.default_rng(1)
    a, b = space.sample(2, rng, unbounded(space))
    only_rotation = space.with_weights({"body_free": 0.0, "body_free.rotation": 1.0}).with_weights(
        {j: 0.0 for j in space.joints if j != "body_free"}
    )
    cols = slice(3, 7)
    assert only_rotation.distance(a, b) == pytest.approx(rotations.angle_between(a[cols], b[cols]))
    doubled = space.with_weights({j: 2.0 for j in space.joints})
    assert doubled.distance(a, b) == pytest.approx(2 * space.distance(a, b))
    with pytest.raises(cspace.errors.UnknownJointError, match="body_free"):
        space.with_weights({"nope": 1.0})
    with pytest.raises(cspace.ConfigurationError, match="finite"):
        space.with_weights({"body_free": -1.0})


def test_wrong_input_gets_a_clear_error() -> None:
    space = space_of(TALOS, "floating")
    n = space.size
    x = space.neutral()
    with pytest.raises(cspace.errors.ConfigurationShapeError, match=f"has {n} coordinates") as e:
        space.distance(x[:-1], x)
    assert e.value.expected == n
    batch = np.tile(x, (4, 1))
    batch[2, 10] = np.nan
    with pytest.raises(cspace.errors.NonFiniteValueError, match=space.names[10]) as nan:
        space.distance(batch, x)
    assert (nan.value.coordinate, nan.value.row) == (space.names[10], 2)
    for op in (space.canonicalize, space.contains, space.to_pinocchio):
        with pytest.raises(cspace.errors.NonFiniteValueError):
            op(batch)
    bad = x.copy()
    bad[3:7] = [1.0, 0.01, 0.0, 0.0]  # norm 1.00005
    with pytest.raises(cspace.errors.NotUnitQuaternionError, match=r"root_joint\.rotation") as nq:
        space.interpolate(x, bad, 0.5)
    assert nq.value.norm == pytest.approx(1.00005, abs=1e-6)
    close = x.copy()
    close[3] = 1.0 + 1e-9  # within the tolerance: accepted and normalized
    assert space.canonicalize(close)[3] == 1.0
    with pytest.raises(cspace.errors.UnboundedSamplingError, match="root_joint") as unb:
        space.sample(3, np.random.default_rng(0))
    assert unb.value.joint == "root_joint"
    with pytest.raises(TypeError, match="Generator"):
        space.sample(3, 42)  # type: ignore[arg-type]
    with pytest.raises(cspace.errors.UnknownJointError, match="arm_left_1_joint") as unk:
        space.from_dict({"arm_left_one": 0.0}, default=x)
    assert "arm_left_1_joint" in unk.value.valid
    with pytest.raises(cspace.errors.MissingJointError) as missing:
        space.from_dict({"root_joint": [0, 0, 0, 1, 0, 0, 0]})
    assert len(missing.value.missing) == len(space.joints) - 1
    with pytest.raises(cspace.errors.JointValueError, match="7 numbers"):
        space.from_dict({"root_joint": [0, 0, 0]}, default=x)
    far = x.copy()
    far[7] = 5.0
    assert not space.contains(far)
    with pytest.raises(cspace.errors.OutOfLimitsError) as out:
        space.check(far)
    assert (out.value.joint, out.value.value) == (space.names[7], 5.0)


def test_mapping_form_of_multi_coordinate_joints() -> None:
    space = space_of(str(ROBOTS / "mobile_manipulator.urdf"), None)
    x = space.from_dict({"base_planar": [1.0, 2.0, 4.0]}, default=space.neutral())
    assert x[:3].tolist() == [1.0, 2.0, 4.0 - 2 * math.pi]  # theta canonical in [-pi, pi)
    assert space.to_dict(x)["base_planar"] == [1.0, 2.0, 4.0 - 2 * math.pi]
    q = space.to_pinocchio(x)
    assert q[:4].tolist() == pytest.approx([1.0, 2.0, math.cos(4.0), math.sin(4.0)])


def test_results_can_be_written_into_reused_buffers() -> None:
    space = space_of(TALOS, "floating")
    rng = np.random.default_rng(2)
    a, b = space.sample(9, rng, unbounded(space)), space.sample(9, rng, unbounded(space))
    d = np.empty(9)
    assert space.distance(a, b, out=d) is d
    np.testing.assert_array_equal(d, space.distance(a, b))
    path = np.empty((9, space.size))
    assert space.interpolate(a, b, 0.25, out=path) is path
    np.testing.assert_array_equal(path, space.interpolate(a, b, 0.25))
    canon = np.empty((9, space.size))
    flipped = a.copy()
    flipped[:, 3:7] *= -1.0  # the base's other quaternion
    np.testing.assert_array_equal(space.canonicalize(flipped, out=canon), a)
    with pytest.raises(cspace.errors.ConfigurationShapeError, match="out must be"):
        space.distance(a, b, out=np.empty(8))
    with pytest.raises(cspace.errors.ConfigurationShapeError, match="out must be"):
        space.canonicalize(a, out=np.empty((9, space.size), dtype=np.float32))


def test_large_batches_run_in_chunks_with_the_same_results() -> None:
    # More rows than one chunk: the kernels split the batch over threads.
    space = space_of(TALOS, "floating")
    rng = np.random.default_rng(8)
    a = space.sample(10_000, rng, unbounded(space))
    b = space.sample(10_000, rng, unbounded(space))
    d = space.distance(a, b)
    np.testing.assert_allclose(d, reference_distance(space, a, b), atol=1e-9)
    mid = space.interpolate(a, b, 0.5)
    np.testing.assert_allclose(mid[-3:], space.interpolate(a[-3:], b[-3:], 0.5), atol=0)
    bad = a.copy()
    bad[9_000, 20] = np.inf
    bad[9_500, 3] = 2.0
    for op in (lambda: space.distance(bad, b), lambda: space.interpolate(b, bad, 0.3)):
        with pytest.raises(cspace.errors.NonFiniteValueError) as e:
            op()
        assert e.value.row == 9_000  # the first bad row over all chunks
    bad[9_000, 20] = 0.0
    with pytest.raises(cspace.errors.NotUnitQuaternionError) as nq:
        space.canonicalize(bad)
    assert nq.value.row == 9_500


def test_limited_ball_joints_are_checked_by_their_angle() -> None:
    space = space_of(str(ROBOTS / "mjcf_every_joint.xml"), None)
    rng = np.random.default_rng(4)
    x = space.sample(1, rng, unbounded(space))[0]
    cols = slice(space.names.index("tool_ball.qw"), space.names.index("tool_ball.qw") + 4)
    x[cols] = rotations.exp(np.array([0.0, 0.0, 0.6]))  # 0.6 rad > the ball's 30 degrees
    assert not space.contains(x)
    with pytest.raises(cspace.errors.OutOfLimitsError) as e:
        space.check(x)
    assert e.value.joint == "tool_ball"
    assert e.value.value == pytest.approx(0.6)
    assert e.value.upper == pytest.approx(math.radians(30))
    values = space.to_dict(x)
    values["base_free"] = np.array(values["base_free"])  # NumPy arrays are accepted too
    np.testing.assert_array_equal(space.from_dict(values), space.canonicalize(x))


@pytest.mark.parametrize("shape", [(), (4,)])
def test_rotation_matrices_of_factors_round_trip(shape) -> None:
    space = space_of(str(ROBOTS / "mobile_manipulator.urdf"), None)
    planar = space_of(str(ROBOTS / "quadrotor_floating.urdf"), None)
    rng = np.random.default_rng(6)
    for s, name, size in ((space, "base_planar.theta", 2), (planar, "body_free", 3)):
        x = s.sample(math.prod(shape), rng, unbounded(s)).reshape(*shape, s.size)
        r = s.matrix(x, name)
        assert r.shape == (*shape, size, size)
        np.testing.assert_allclose(np.linalg.det(r), 1.0)
        slot = next(f for f in s.slots if f.name in (name, f"{name}.rotation"))
        cols = slice(slot.column, slot.column + slot.factor.size)
        y = s.with_matrix(s.neutral(), name, r)
        assert y.shape == x.shape
        np.testing.assert_allclose(y[..., cols], x[..., cols], atol=1e-12)
        np.testing.assert_array_equal(
            np.delete(y, cols, axis=-1),
            np.delete(np.broadcast_to(s.neutral(), x.shape), cols, axis=-1),
        )
    # a half turn about z set from its exact matrix is the tie-broken canonical quaternion
    half_turn = np.diag([-1.0, -1.0, 1.0])
    y = planar.with_matrix(planar.neutral(), "body_free.rotation", half_turn)
    assert y[3:7].tolist() == [0.0, 0.0, 0.0, 1.0]
    with pytest.raises(cspace.errors.NotARotationError):
        planar.with_matrix(planar.neutral(), "body_free", np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(cspace.errors.NotARotationError):
        space.with_matrix(space.neutral(), "base_planar", np.eye(2) * 2)
    with pytest.raises(cspace.errors.UnknownJointError, match=r"base_planar\.theta"):
        space.matrix(space.neutral(), "arm_joint_1")


def test_a_robot_without_coordinates_is_a_point() -> None:
    space = space_of(str(ROBOTS / "sensor_head_fixed.urdf"), None)
    assert (space.size, space.dimension) == (0, 0)
    x = space.sample(3, np.random.default_rng(0))
    assert x.shape == (3, 0)
    assert space.distance(space.neutral(), space.neutral()) == 0.0
    assert space.interpolate(x, x, 0.5).shape == (3, 0)
    assert space.to_dict(space.neutral()) == {}
    assert space.from_dict({}).shape == (0,)


@pytest.mark.parametrize("angle", [1e17, -1e17, 1e18, -1e18, 3 * math.pi, -3 * math.pi, 1e150])
def test_huge_angles_canonicalize_into_range_and_agree_with_distance(angle: float) -> None:
    space = cspace.load(str(ROBOTS / "arm7.urdf"))
    x = space.neutral()
    x[space.names.index("wrist_roll")] = angle
    wrapped = space.canonicalize(x)[space.names.index("wrist_roll")]
    assert -math.pi <= wrapped < math.pi
    # The batch kernel (canonicalize) and the distance kernel wrap the same way.
    assert space.distance(x, space.neutral()) == pytest.approx(abs(wrapped), abs=1e-12)


def test_a_half_turn_is_interpolated_the_same_way_in_both_directions() -> None:
    space = cspace.load(str(ROBOTS / "quadrotor_floating.urdf"))
    a, b = space.neutral(), space.neutral()
    i = space.names.index("prop_fl_spin")
    a[i], b[i] = -math.pi / 2, math.pi / 2  # both ways round are a half turn
    t = np.linspace(0.0, 1.0, 9)
    forward = space.interpolate(a, b, t)
    backward = space.interpolate(b, a, 1.0 - t)
    np.testing.assert_allclose(forward[:, i], backward[:, i], atol=1e-12)
    assert forward[4, i] == 0.0  # through the midpoint of the arc between them
    np.testing.assert_allclose(space.difference(a, b), -space.difference(b, a))


def test_a_coordinate_whose_square_overflows_is_named_as_such() -> None:
    space = cspace.load(str(ROBOTS / "arm7.urdf"))
    x = space.neutral()
    x[space.names.index("wrist_roll")] = 1e300
    with pytest.raises(cspace.ConfigurationError, match="too large"):
        space.distance(x, space.neutral())


_STORED = {"value": 1, "angle": 1, "cos_sin": 2, "xyzw": 4, "euler_zyx": 3}
"""Entries of Pinocchio's q each encoding takes."""


def _pinocchio_joint(model: str):  # type: ignore[no-untyped-def]
    make = getattr(pin, model)
    for args in ((), (np.array([0.0, 0.0, 1.0]),)):
        try:
            return make(*args)
        except TypeError:
            continue
    raise AssertionError(f"cannot build {model}")


@pytest.mark.parametrize("model", sorted(KIND_OF_MODEL))
@pytest.mark.parametrize("bounds", [None, (-1.0, 1.0)], ids=["unbounded", "bounded"])
def test_the_joint_table_agrees_with_pinocchios_joint_models(model: str, bounds) -> None:
    """Every joint model the table names, built by Pinocchio: the factors take exactly
    its nq entries of q, their tangent dimensions add up to its nv, and the joint's space
    has dimension nv (the manifold's dimension is that of its tangent space)."""
    pj = _pinocchio_joint(model)
    assert pj.shortname() == model
    width = pj.nq if model == "JointModelUniversal" else 1
    limits = None if bounds is None else Limits((bounds[0],) * width, (bounds[1],) * width, "rad")
    kind = kind_of(model, limits)
    assert kind is not None
    found = factors_of(kind, pj.nq, pj.nv, limits)
    if model == "JointModelMimic":
        assert (found.factors, pj.nq, pj.nv) == ((), 0, 0)
        return
    assert found.factors, (model, found.unsupported)
    assert (found.unsupported is not None) == (model == "JointModelSphericalZYX")
    assert sum(_STORED[f.encoding] for f in found.factors) == pj.nq
    assert sum(f.kind.dimension for f in found.factors) == pj.nv
    assert found.space.dimension == pj.nv


R, S1, RP3 = NormalForm(r=1), NormalForm(t=1), NormalForm(rp3=1)


@pytest.mark.parametrize(
    ("model", "lower", "upper", "space"),
    [
        ("JointModelRZ", (-1.0,), (1.0,), R),  # an interval is homeomorphic to R
        ("JointModelRZ", (), (), S1),  # no limits: the whole circle
        ("JointModelRZ", (math.nan,), (1.0,), S1),  # a limit that is not a number bounds nothing
        ("JointModelRZ", (0.5,), (0.5,), NormalForm()),  # locked: a point
        ("JointModelRUBZ", (), (), S1),
        ("JointModelPX", (), (), R),
        ("JointModelPX", (0.0,), (0.2,), R),
        ("JointModelHZ", (-1.0,), (1.0,), R),
        ("JointModelPlanar", (), (), NormalForm(r=2, t=1)),  # SE(2) = R^2 x S^1
        ("JointModelSpherical", (), (), RP3),  # SO(3) = RP^3
        ("JointModelSpherical", (0.0,), (1.0,), NormalForm(r=3)),  # a ball of rotations
        ("JointModelSpherical", (0.0,), (4.0,), RP3),  # no rotation is larger than pi
        ("JointModelFreeFlyer", (), (), NormalForm(r=3, rp3=1)),  # SE(3) = R^3 x RP^3
        ("JointModelTranslation", (), (), NormalForm(r=3)),
        ("JointModelUniversal", (), (), NormalForm(t=2)),
        ("JointModelUniversal", (-1.0, -1.0), (1.0, 1.0), NormalForm(r=2)),
    ],
)
def test_each_joint_model_has_the_space_the_mathematics_gives(model, lower, upper, space) -> None:
    """docs/cspace-math.md section 1, pinned: the space a joint contributes."""
    pj = _pinocchio_joint(model)
    limits = Limits(lower, upper, "rad") if lower else None
    kind = kind_of(model, limits)
    assert kind is not None
    assert factors_of(kind, pj.nq, pj.nv, limits).space == space


def test_a_space_pickles_without_what_it_derived() -> None:
    # The kernels' columns are built on first use and cached on the space; a pickle
    # holds the fields only (no class of the engines' in it), and the space unpickled
    # rebuilds them and gives the same bits.
    space = cspace.load("erd:talos", "floating")
    rng = np.random.default_rng(7)
    a, b = space.sample(64, rng, unbounded(space)), space.sample(64, rng, unbounded(space))
    before = space.distance(a, b)
    data = pickle.dumps(space)
    assert b"Columns" not in data and b"engines" not in data
    again = pickle.loads(data)
    assert np.array_equal(again.distance(a, b), before)
    assert again.names == space.names and again.weights == space.weights
