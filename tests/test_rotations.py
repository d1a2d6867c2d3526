"""cspace.space._geometry.rotations: exact matrix <-> quaternion, canonical form, Haar sampling."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cspace import rotations
from cspace.space._geometry.factors import Rotation


def axis_angle(axis: tuple[float, float, float], angle: float) -> np.ndarray:
    """LaValle (4.21), written out independently: cos(t/2) + sin(t/2) v."""
    v = np.asarray(axis, dtype=float)
    v = v / np.linalg.norm(v)
    return np.concatenate(([math.cos(angle / 2)], math.sin(angle / 2) * v))


def rodrigues(axis: tuple[float, float, float], angle: float) -> np.ndarray:
    """R = I + sin t K + (1 - cos t) K^2, independent of any quaternion formula."""
    v = np.asarray(axis, dtype=float)
    v = v / np.linalg.norm(v)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def upper(h: np.ndarray) -> np.ndarray:
    """The upper-hemisphere representative by the rule of cspace-math.md section 3."""
    for c in h:
        if c != 0:
            return h if c > 0 else -h
    raise ValueError("zero quaternion")


AXES = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, 1, 1), (0, -1, 1), (-2, 0.5, 0.1)]
ANGLES = [0.0, 1e-9, 0.3, math.pi / 2, 2.0, math.pi - 1e-9, math.pi]


@pytest.mark.parametrize("axis", AXES)
@pytest.mark.parametrize("angle", ANGLES)
def test_quaternion_from_matrix_is_exact_everywhere(
    axis: tuple[float, float, float], angle: float
) -> None:
    # Rotations by pi and pure yaw, pitch or roll are where (4.24)-(4.30) break down.
    h = rotations.quaternion_from_matrix(rodrigues(axis, angle))
    expected = upper(axis_angle(axis, angle))
    np.testing.assert_allclose(h, expected, atol=2e-15)
    assert h[0] >= 0


def test_rotation_by_pi_about_each_axis_gives_the_tie_broken_representative() -> None:
    # Exact matrices: a half turn about x, y or z negates the other two axes.
    for i in range(3):
        r = -np.eye(3)
        r[i, i] = 1.0
        h = rotations.quaternion_from_matrix(r)
        expected = np.zeros(4)
        expected[i + 1] = 1.0
        assert h.tolist() == expected.tolist()
    # A half turn about (0, -1, 1)/sqrt 2: w = x = 0 and y < 0 in one representative.
    s = math.sqrt(0.5)
    r = np.array([[-1.0, 0, 0], [0, 0, -1.0], [0, -1.0, 0]])
    h = rotations.quaternion_from_matrix(r)
    np.testing.assert_allclose(h, [0.0, 0.0, s, -s], atol=1e-16)
    assert h[0] == 0.0 and h[1] == 0.0


def test_matrix_from_quaternion_matches_pinocchio() -> None:
    rng = np.random.default_rng(7)
    h = Rotation().sample(rng, (50,))
    mats = rotations.matrix_from_quaternion(h)
    for hi, mi in zip(h, mats, strict=True):
        q = pin.Quaternion(hi[0], hi[1], hi[2], hi[3])  # pinocchio's constructor is (w, x, y, z)
        np.testing.assert_allclose(mi, q.toRotationMatrix(), atol=1e-14)


@pytest.mark.parametrize("shape", [(), (4,), (2, 3)])
def test_batched_round_trips(shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(3)
    h = Rotation().sample(rng, shape)
    r = rotations.matrix_from_quaternion(h)
    assert r.shape == (*shape, 3, 3)
    assert rotations.is_rotation_matrix(r).all()
    back = rotations.quaternion_from_matrix(r)
    assert back.shape == (*shape, 4)
    np.testing.assert_allclose(back, h, atol=1e-14)


def test_is_rotation_matrix_rejects_reflections_and_nan() -> None:
    r = np.stack([np.eye(3), np.diag([1.0, 1.0, -1.0]), np.full((3, 3), np.nan), 2 * np.eye(3)])
    assert rotations.is_rotation_matrix(r).tolist() == [True, False, False, False]


def test_tie_breaks_on_the_equator() -> None:
    cases = {
        (0.0, -1.0, 0.0, 0.0): (0.0, 1.0, 0.0, 0.0),
        (-0.0, 0.0, -0.6, 0.8): (0.0, 0.0, 0.6, -0.8),
        (0.0, 0.0, 0.0, -1.0): (0.0, 0.0, 0.0, 1.0),
        (-0.0, -0.0, -0.0, 1.0): (0.0, 0.0, 0.0, 1.0),
    }
    for given_h, expected in cases.items():
        out = rotations.canonicalize(np.array(given_h))
        assert out.tolist() == list(expected)
        assert not np.signbit(out[out == 0]).any()  # zeros come out as +0.0


quaternions = st.tuples(*[st.floats(-1, 1, allow_subnormal=False)] * 4).filter(
    lambda t: sum(x * x for x in t) ** 0.5 > 0.5
)


@settings(max_examples=200, deadline=None)
@given(quaternions)
def test_canonical_form_properties(t: tuple[float, float, float, float]) -> None:
    h = np.array(t) / np.linalg.norm(t)
    c = rotations.canonicalize(h)
    assert rotations.canonicalize(-h).tobytes() == c.tobytes()  # h ~ -h, bit-identical
    assert rotations.canonicalize(c).tobytes() == c.tobytes()  # idempotent, bit-exact
    assert np.array_equal(c, upper(c))
    assert abs(np.linalg.norm(c) - 1) < 1e-15
    np.testing.assert_allclose(
        rotations.matrix_from_quaternion(c), rotations.matrix_from_quaternion(h), atol=1e-15
    )
    back = rotations.quaternion_from_matrix(rotations.matrix_from_quaternion(h))
    assert rotations.angle_between(back, c) < 1e-14
    if c[0] > 1e-7:  # off the equator the hemisphere is decided by the matrix's digits
        np.testing.assert_allclose(back, c, atol=1e-14)


def test_angle_between_is_accurate_near_zero_and_pi() -> None:
    for angle in (1e-12, 1e-8, 1e-4, 1.0, math.pi - 1e-8, math.pi):
        a = axis_angle((0.3, -1, 2), 0.7)
        b = rotations.multiply(a, axis_angle((1, 2, 3), angle))
        got = rotations.angle_between(a, b)
        ref = np.linalg.norm(pin.log3(rodrigues((1, 2, 3), angle)))
        assert got == pytest.approx(ref, rel=1e-9, abs=1e-15)
        assert rotations.angle_between(a, -b) == got


def test_haar_samples_have_the_uniform_angle_distribution() -> None:
    # Under the Haar measure the rotation angle has density (1 - cos t) / pi on [0, pi],
    # so its distribution function is (t - sin t) / pi. Kolmogorov-Smirnov at a fixed seed.
    n = 20000
    h = Rotation().sample(np.random.default_rng(2024), (n,))
    angle = np.sort(rotations.angle_between(h, np.array([1.0, 0, 0, 0])))
    cdf = (angle - np.sin(angle)) / math.pi
    ecdf_hi = np.arange(1, n + 1) / n
    ecdf_lo = np.arange(0, n) / n
    ks = max(np.max(ecdf_hi - cdf), np.max(cdf - ecdf_lo))
    assert ks < 1.36 / math.sqrt(n)  # 5 % critical value
    # The axis is uniform too: the mean rotation matrix of Haar samples is 0.
    assert np.abs(rotations.matrix_from_quaternion(h).mean(axis=0)).max() < 0.03


def test_ball_samples_have_the_restricted_haar_angle_distribution() -> None:
    m = 0.8
    n = 20000
    h = Rotation(max_angle=m).sample(np.random.default_rng(5), (n,))
    assert Rotation(max_angle=m).contains(h).all()
    angle = np.sort(rotations.angle_between(h, np.array([1.0, 0, 0, 0])))
    cdf = (angle - np.sin(angle)) / (m - math.sin(m))
    ks = max(np.max(np.arange(1, n + 1) / n - cdf), np.max(cdf - np.arange(0, n) / n))
    assert ks < 1.36 / math.sqrt(n)


def test_conversions_reject_what_is_not_a_rotation() -> None:
    import cspace

    stack = np.stack([np.eye(3), np.eye(3), np.diag([1.0, 1.0, -1.0])])
    with pytest.raises(cspace.errors.NotARotationError) as e:
        rotations.quaternion_from_matrix(stack)
    assert e.value.row == 2
    with pytest.raises(cspace.errors.NotARotationError):
        rotations.quaternion_from_matrix(np.full((3, 3), np.nan))
    with pytest.raises(cspace.errors.ConfigurationShapeError):
        rotations.quaternion_from_matrix(np.eye(4))
    with pytest.raises(cspace.errors.NotUnitQuaternionError) as q:
        rotations.matrix_from_quaternion(np.array([[1.0, 0, 0, 0], [1.0, 0.1, 0, 0]]))
    assert q.value.row == 1
    # skipping the check is the caller's choice (for already validated data)
    assert rotations.matrix_from_quaternion(np.array([2.0, 0, 0, 0]), check=False).shape == (3, 3)
